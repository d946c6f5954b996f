"""Plain data of a report: frozen dataclasses of numpy arrays, lists and dicts.

Nothing here knows about models, workflows or solvers, so that any script can fill a
`ReportContent` and hand it to `flexgvt.report.write_report`. Arrays are converted with
`np.asarray` and their shapes checked on construction; a bad shape raises `ReportError` saying
which field of which object is wrong. Units: positions and displacements in m, frequencies in Hz,
percentages in %.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ReportError


def _set(obj, name: str, value) -> None:
    object.__setattr__(obj, name, value)


def _array(obj, name: str, shape: tuple, dtype=float, where: str = "") -> np.ndarray:
    """Field `name` of `obj` as an array of the given shape (None in `shape` = any length)."""
    value = np.asarray(getattr(obj, name), dtype=dtype)
    ok = value.ndim == len(shape) and all(s is None or s == n for s, n in zip(shape, value.shape))
    if not ok:
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise ReportError(f"{type(obj).__name__}{where}.{name} must have shape {want}, got {value.shape}")
    _set(obj, name, value)
    return value


@dataclass(frozen=True)
class Geometry:
    """A wireframe: node positions xyz (n, 3) [m] and beam edges (m, 2) as index pairs into xyz."""

    xyz: np.ndarray
    edges: np.ndarray

    def __post_init__(self):
        xyz = _array(self, "xyz", (None, 3))
        edges = np.asarray(self.edges, dtype=np.int64).reshape(-1, 2)
        if edges.size and (edges.min() < 0 or edges.max() >= len(xyz)):
            raise ReportError(f"Geometry.edges index a node outside 0..{len(xyz) - 1}: "
                              f"range {edges.min()}..{edges.max()}")
        _set(self, "edges", edges)

    @property
    def span(self) -> float:
        """Largest extent of the bounding box [m] (1 for a single point)."""
        if len(self.xyz) < 2:
            return 1.0
        ext = float(np.ptp(self.xyz, axis=0).max())
        return ext if ext > 0 else 1.0


@dataclass(frozen=True)
class ModeShape:
    """One mode to animate: the analytical shape on the geometry's nodes and, optionally, the
    measured shape at the test points.

    displacement: (n, 3) analytical translations at the deformed geometry's nodes (any scale).
    measured_xyz: (p, 3) test-point positions [m] on the deformed geometry, or None.
    measured_displacement: (p, 3) real measured translations at the test points (any scale), or None.
    """

    label: str
    analytical_hz: float
    displacement: np.ndarray
    measured_hz: float | None = None
    mac: float | None = None
    measured_xyz: np.ndarray | None = None
    measured_displacement: np.ndarray | None = None

    def __post_init__(self):
        where = f"[{self.label!r}]"
        _array(self, "displacement", (None, 3), where=where)
        if (self.measured_xyz is None) != (self.measured_displacement is None):
            raise ReportError(f"ModeShape{where}: give both measured_xyz and measured_displacement, or neither")
        if self.measured_xyz is not None:
            p = len(_array(self, "measured_xyz", (None, 3), where=where))
            _array(self, "measured_displacement", (p, 3), where=where)


@dataclass(frozen=True)
class StabilisationData:
    """A stabilisation diagram as flat arrays.

    frequencies_hz, indicator: (nf,) the FRF frequency axis [Hz] and a positive mode indicator on
    it (sum of |H|, CMIF...), drawn on a log axis.
    orders, poles_hz, stable: (n_poles,) model order, pole frequency [Hz] and stability flag of
    every pole of every order. selected_hz: (k,) the selected modes [Hz]; selected_std_hz: (k,)
    their standard deviations [Hz] (drawn as +-2 sigma bands; NaN where unknown) or None.
    ringed_hz, ringed_orders, ringed_strong: (m,) poles of the candidate clusters an automatic
    selection kept (flexgvt.ema.select_ml's info['kept']), strong or weak (stable over a narrow
    band of orders).
    """

    frequencies_hz: np.ndarray
    indicator: np.ndarray
    orders: np.ndarray
    poles_hz: np.ndarray
    stable: np.ndarray
    selected_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    selected_std_hz: np.ndarray | None = None
    ringed_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    ringed_orders: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    ringed_strong: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))

    def __post_init__(self):
        nf = len(_array(self, "frequencies_hz", (None,)))
        _array(self, "indicator", (nf,))
        n = len(_array(self, "orders", (None,), dtype=np.int64))
        _array(self, "poles_hz", (n,))
        _array(self, "stable", (n,), dtype=bool)
        k = len(_array(self, "selected_hz", (None,)))
        if self.selected_std_hz is not None:
            _array(self, "selected_std_hz", (k,))
        m = len(_array(self, "ringed_hz", (None,)))
        _array(self, "ringed_orders", (m,), dtype=np.int64)
        _array(self, "ringed_strong", (m,), dtype=bool)

    @classmethod
    def from_stabilisation(cls, stab, selected_hz=None, selected_std_hz=None, clusters=None,
                           band: bool = False) -> StabilisationData:
        """From a `flexgvt.ema.polymax` Stabilisation (poles as complex s [rad/s] per order); the
        indicator is the sum of |H| over all outputs and inputs. clusters: the kept candidate
        clusters of an automatic selection (ringed); band: only the fitted band (lines and poles)."""
        lo, hi = stab.band if band else (-np.inf, np.inf)
        orders, poles, stable = [], [], []
        for order, s, st in zip(stab.orders, stab.poles, stab.stable):
            f = np.abs(np.asarray(s)) / (2 * np.pi)
            keep = (f >= lo) & (f <= hi)
            orders.append(np.full(int(keep.sum()), order, dtype=np.int64))
            poles.append(f[keep])
            stable.append(np.asarray(st, dtype=bool)[keep])

        def cat(parts, dt):
            return np.concatenate(parts) if parts else np.zeros(0, dtype=dt)

        freq = np.asarray(stab.frequencies_hz, float)
        lines = (freq >= lo) & (freq <= hi)
        H = np.asarray(stab.H)[lines]
        indicator = np.abs(H).reshape(len(H), -1).sum(axis=1)
        rings = [(np.asarray(c.frequencies_hz, float), np.asarray(stab.orders)[np.asarray(c.orders)],
                  np.full(len(c.frequencies_hz), bool(c.strong))) for c in (clusters or ())]
        return cls(freq[lines], indicator, cat(orders, np.int64), cat(poles, float), cat(stable, bool),
                   np.zeros(0) if selected_hz is None else np.atleast_1d(np.asarray(selected_hz, float)),
                   None if selected_std_hz is None else np.atleast_1d(np.asarray(selected_std_hz, float)),
                   cat([r[0] for r in rings], float), cat([r[1] for r in rings], np.int64),
                   cat([r[2] for r in rings], bool))


@dataclass(frozen=True)
class FRFComparison:
    """Measured FRFs against those synthesised from the identified modes, for one reference.

    reference: its name (e.g. "10+Z"); frequencies_hz (nf,); measured, synthesised: (nf, k) complex
    curves named by labels (k,) (the sum of |H| over the outputs, the driving point...);
    mif_measured, mif_synthesised: (nf,) the reference's mode indicator function (dips at modes);
    fit: rows of the synthesis quality per output (any columns, e.g. output, frac), or empty;
    modes_hz: the identified modes [Hz] (marked on the plot)."""

    reference: str
    frequencies_hz: np.ndarray
    measured: np.ndarray
    synthesised: np.ndarray
    labels: list[str]
    mif_measured: np.ndarray | None = None
    mif_synthesised: np.ndarray | None = None
    fit: list[dict[str, Any]] = field(default_factory=list)
    modes_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self):
        where = f"[{self.reference!r}]"
        nf = len(_array(self, "frequencies_hz", (None,), where=where))
        k = len(self.labels)
        _array(self, "measured", (nf, k), dtype=complex, where=where)
        _array(self, "synthesised", (nf, k), dtype=complex, where=where)
        for name in ("mif_measured", "mif_synthesised"):
            if getattr(self, name) is not None:
                _array(self, name, (nf,), where=where)
        _array(self, "modes_hz", (None,), where=where)


@dataclass(frozen=True)
class ConfigurationSection:
    """Everything reported for one test configuration (suspension layout, load case...).

    frequency_table: rows with keys mode, label, measured_hz, initial_hz, updated_hz,
    initial_error_percent, updated_error_percent, mac_initial, mac_updated (None allowed; extra
    keys become extra columns). mac_initial, mac_updated: (n_measured, n_analytical) or None, rows
    labelled by measured_labels and columns by analytical_labels.
    role: "update" (the model was updated on it) or "check" (only compared).
    test_modes: rows of the identified modes' quality (damping, its standard deviation, MPC, MPD...).
    auto_mac: (n_measured, n_measured) MAC of the test modes with themselves, labelled by
    measured_labels, or None. comac: rows per sensor DOF (point, direction, node, comac...).
    setup: the test set-up as {table title: rows} (suspension points, added masses, sensors).
    frfs: measured against synthesised FRFs, one FRFComparison per reference.
    notes: lines under the section (unpaired modes and why...).
    """

    name: str
    undeformed: Geometry
    deformed: Geometry
    frequency_table: list[dict[str, Any]] = field(default_factory=list)
    mac_initial: np.ndarray | None = None
    mac_updated: np.ndarray | None = None
    measured_labels: list[str] = field(default_factory=list)
    analytical_labels: list[str] = field(default_factory=list)
    stabilisation: StabilisationData | None = None
    modes: list[ModeShape] = field(default_factory=list)
    role: str = "update"
    test_modes: list[dict[str, Any]] = field(default_factory=list)
    auto_mac: np.ndarray | None = None
    comac: list[dict[str, Any]] = field(default_factory=list)
    setup: dict[str, list[dict[str, Any]]] = field(default_factory=dict)
    frfs: list[FRFComparison] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def __post_init__(self):
        where = f"[{self.name!r}]"
        shape = (len(self.measured_labels), len(self.analytical_labels))
        for name in ("mac_initial", "mac_updated"):
            if getattr(self, name) is not None:
                if not (self.measured_labels and self.analytical_labels):
                    m = np.asarray(getattr(self, name))
                    if not self.measured_labels:
                        _set(self, "measured_labels", [f"test {i + 1}" for i in range(m.shape[0])])
                    if not self.analytical_labels:
                        _set(self, "analytical_labels", [f"FE {j + 1}" for j in range(m.shape[-1])])
                    shape = (len(self.measured_labels), len(self.analytical_labels))
                _array(self, name, shape, where=where)
        if self.auto_mac is not None:
            n = np.shape(self.auto_mac)[0]
            if not self.measured_labels:
                _set(self, "measured_labels", [f"test {i + 1}" for i in range(n)])
            _array(self, "auto_mac", (len(self.measured_labels),) * 2, where=where)
        n = len(self.deformed.xyz)
        for mode in self.modes:
            if len(mode.displacement) != n:
                raise ReportError(f"ConfigurationSection{where}: mode {mode.label!r} has "
                                  f"{len(mode.displacement)} displacements for {n} deformed nodes")


@dataclass(frozen=True)
class StageSection:
    """One stage of a staged updating, shown in its order: summary (key, value) lines, fixed inputs
    (rows), the stage's design variables (rows as ReportContent.variables) and {configuration:
    frequency rows as ConfigurationSection.frequency_table} of the configurations it updated on
    (initial: the model the stage started from; updated: the model it produced); mass: rows of the
    measured mass properties against both models."""

    name: str
    summary: list[tuple[str, str]] = field(default_factory=list)
    fixed: list[dict[str, Any]] = field(default_factory=list)
    variables: list[dict[str, Any]] = field(default_factory=list)
    frequencies: dict[str, list[dict[str, Any]]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    mass: list[dict[str, Any]] = field(default_factory=list)


@dataclass(frozen=True)
class ReportContent:
    """A whole report.

    summary: (key, value) lines at the top (model, method, time, objective before/after...).
    variables: rows with keys name, initial, updated, change_percent, std_percent (or None),
    bounds (a (low, high) pair or None); extra keys become extra columns.
    history: objective per optimiser iteration.
    load_evolution: {"load_factors": (k,), "frequencies_hz": (k, n_modes), "labels": [n_modes]}
    or None (frequencies versus load).
    prediction: rows of the free-flying prediction table, any columns (mode, label, free_hz,
    truth_hz, error_percent, bungee_hz...).
    prediction_modes: {configuration: rows} the full mode list of each predicted configuration,
    shown as a table each under the prediction table.
    stages: the stages of a staged updating (StageSection), shown after the summary.
    variables_title, history_title: the headings of the variables and history sections (a staged
    run's name the final updating stage).
    """

    title: str
    summary: list[tuple[str, str]] = field(default_factory=list)
    configurations: list[ConfigurationSection] = field(default_factory=list)
    variables: list[dict[str, Any]] = field(default_factory=list)
    history: list[float] = field(default_factory=list)
    load_evolution: dict[str, Any] | None = None
    prediction: list[dict[str, Any]] = field(default_factory=list)
    prediction_title: str = "Free-flying prediction"
    notes: list[str] = field(default_factory=list)
    prediction_modes: dict[str, list[dict[str, Any]]] = field(default_factory=dict)
    stages: list[StageSection] = field(default_factory=list)
    variables_title: str = "Design variables"
    history_title: str = "Optimiser history"

    def __post_init__(self):
        names = [c.name for c in self.configurations]
        if len(set(names)) != len(names):
            raise ReportError(f"ReportContent.configurations: names must be unique, got {names}")
        if any(not isinstance(s, StageSection) for s in self.stages):
            raise ReportError("ReportContent.stages must hold StageSection objects")
        ev = self.load_evolution
        if ev is not None:
            lf = np.asarray(ev.get("load_factors", []), float).ravel()
            f = np.asarray(ev.get("frequencies_hz", []), float)
            if f.ndim == 1:
                f = f[:, None]
            if f.ndim != 2 or f.shape[0] != len(lf):
                raise ReportError("ReportContent.load_evolution['frequencies_hz'] must have shape "
                                  f"(k, n_modes) with k = {len(lf)} load factors, got {f.shape}")
            labels = list(ev.get("labels") or [f"mode {j + 1}" for j in range(f.shape[1])])
            if len(labels) != f.shape[1]:
                raise ReportError(f"ReportContent.load_evolution['labels'] has {len(labels)} entries "
                                  f"for {f.shape[1]} modes")
            _set(self, "load_evolution", {"load_factors": lf, "frequencies_hz": f, "labels": labels})
        hist = np.asarray(self.history, float).ravel()
        _set(self, "history", [float(v) for v in hist])
