"""Test planning on the deformed structure: suspension layouts ranked by how far their suspension
modes sit below the first elastic mode (and how much each elastic mode they contaminate), lines
refused when loaded past their allowance; sensor stations by effective independence on the
deformed mode shapes, and a driving point that excites every target mode."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable, Sequence

import numpy as np

from ..errors import ConvergenceError, ModelError, SingularModelError
from ..correlation import Sensors
from ..fem import Modes, solve_modes, solve_static
from ..model import Configuration, Model
from .networks import Line
from .removal import remove_suspension


@dataclass(frozen=True)
class Attachment:
    """One suspension point of a layout: the structure's node (and offset [m]), the line, the
    anchor (3,) [m] and the share of the structure's weight it carries (None: equal shares)."""

    node: int
    line: Line
    anchor: tuple
    offset: tuple = (0.0, 0.0, 0.0)
    share: float | None = None


@dataclass(frozen=True)
class Layout:
    """A candidate suspension: a name and its attachments."""

    name: str
    attachments: tuple[Attachment, ...]


@dataclass
class LayoutResult:
    """A layout's predicted hung test: its configuration and static state, the suspension and
    elastic modes, the separation (first elastic over highest suspension frequency), each elastic
    mode's shift from free-free and its share of energy in the suspension, and the problems
    (lines loaded past their allowance)."""

    layout: Layout
    configuration: Configuration | None
    state: object | None
    suspension_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    elastic: list[dict] = field(default_factory=list)
    separation: float = 0.0
    problems: list[str] = field(default_factory=list)
    tensions: np.ndarray = field(default_factory=lambda: np.zeros(0))
    modes: Modes | None = None
    suspension_labels: list[str] = field(default_factory=list)

    @property
    def acceptable(self) -> bool:
        return not self.problems

    @property
    def name(self) -> str:
        return self.layout.name

    @property
    def n_contaminated(self) -> int:
        """Elastic modes the suspension contaminates (or all reported ones when the test was not solved)."""
        return sum(bool(e.get("contaminated")) for e in self.elastic) if self.state is not None else 10**6

    @property
    def max_shift_percent(self) -> float:
        """The largest |shift| [%] of a paired elastic mode from free-free (inf when not solved)."""
        shifts = [abs(e["suspended_shift_percent"]) for e in self.elastic if e.get("suspended_shift_percent")
                  is not None]
        return max(shifts) if shifts else (0.0 if self.state is not None else float("inf"))

    @property
    def first_elastic_hz(self) -> float | None:
        """The hung structure's lowest elastic frequency [Hz] (None when not solved)."""
        if self.modes is None:
            return None
        f = self.modes.frequencies_hz[self.modes.energy_fractions[:, 4] <= 0.5]
        return float(f.min()) if len(f) else None


def layout_configuration(model: Model, layout: Layout, gravity: float = 1.0,
                         base: Configuration | None = None) -> Configuration:
    """The Configuration that hangs ``model`` on ``layout`` (cords sized to carry their share of the
    weight at the undeformed attachment points). ``base``: a configuration whose extra masses, loads,
    springs and gravity direction the hung test keeps (its own suspension is replaced; its load
    factor is used when it has one, else ``gravity``)."""
    from ..fem import mass_properties
    base = base if base is not None else Configuration(layout.name)
    if base.fixed:
        raise ModelError(f"layout '{layout.name}' on configuration '{base.name}': the configuration fixes DOFs "
                         f"(nodes {sorted(base.fixed)}); a suspension hangs a free structure: plan on a "
                         "configuration without supports")
    gravity = base.gravity if base.gravity else gravity
    g = abs(gravity) * base.g
    weight = mass_properties(model, base.with_(suspension=())).mass * g
    xyz = model.xyz
    shares = np.array([a.share if a.share is not None else 1.0 / len(layout.attachments) for a in layout.attachments])
    cords = []
    for a, share in zip(layout.attachments, shares):
        attach = xyz[model.index_of([a.node], f"layout '{layout.name}'")[0]] + np.asarray(a.offset, float)
        try:
            cords.append(a.line.cord(a.node, a.anchor, attach, share * weight, offset=a.offset))
        except ModelError as exc:
            raise ModelError(f"layout '{layout.name}', attachment at node {a.node}: {exc}") from None
    return base.with_(name=layout.name, suspension=tuple(cords), gravity=gravity)


def assess(model: Model, configuration: Configuration, layout: Layout | None = None, n_modes: int = 10,
           energy_limit: float = 0.1, shift_limit_percent: float = 1.0) -> LayoutResult:
    """One hung test predicted (``configuration`` with its suspension; ``layout``: the candidate it
    was built from, None for a suspension given as cords): its static state, suspension modes,
    separation, each elastic mode's shift from free-free and share of energy in the suspension
    (see plan_suspension), and its problems."""
    layout = layout if layout is not None else Layout(configuration.name, ())
    res = LayoutResult(layout, configuration, None)
    try:
        state = solve_static(model, configuration)
    except (ConvergenceError, SingularModelError) as exc:
        res.problems.append(f"the hung static solution failed: {exc}")
        return res
    res.state = state
    res.tensions = np.asarray(state.cord_tension, float)
    for a, T in zip(layout.attachments, res.tensions):
        res.problems += [f"node {a.node}: {p}" for p in a.line.check(float(T))]
    modes = solve_modes(state, n_modes + len(configuration.suspension) + 6, damped=False)
    res.modes = modes
    susp = modes.energy_fractions[:, 4] > 0.5
    res.suspension_hz = modes.frequencies_hz[susp]
    res.suspension_labels = [modes.labels[k] for k in np.flatnonzero(susp)] if modes.labels else []
    removal = remove_suspension(model, configuration, n_modes=n_modes)
    elastic_hz = modes.frequencies_hz[~susp]
    res.separation = float(elastic_hz.min() / res.suspension_hz.max()) if len(res.suspension_hz) and len(
        elastic_hz) else float("inf")
    for row in removal.rows:
        j = row.get("suspended_mode")
        share = float(modes.energy_fractions[j - 1, 4]) if j else None
        # A free mode no hung mode resembles (MAC below the pairing floor) is changed past recognition.
        res.elastic.append({**row, "suspension_energy": share, "unpaired": not j,
                            "contaminated": bool(not j or abs(row["suspended_shift_percent"]) > shift_limit_percent
                                                 or share > energy_limit)})
    if res.separation < 2.0:
        k = int(np.flatnonzero(susp)[np.argmax(modes.frequencies_hz[susp])])
        res.problems.append(f"suspension mode '{modes.labels[k]}' ({modes.frequencies_hz[k]:.3g} Hz) sits within "
                            f"2x of the first elastic mode ({elastic_hz.min():.3g} Hz): soften the lines (plunge, "
                            "roll) or lengthen them (pendulum), or move the attachments")
    return res


def plan_suspension(model: Model, layouts: Iterable[Layout], n_modes: int = 10, energy_limit: float = 0.1,
                    shift_limit_percent: float = 1.0, base: Configuration | None = None) -> list[LayoutResult]:
    """Predict each layout's hung test and rank them (see rank): acceptable layouts first, then
    those that contaminate fewer elastic modes, then those that move them less, then by separation.

    Every elastic mode gets its frequency shift from free-free and the share of its energy in the
    suspension (docs/method.md: a separation below 10x always contaminates very flexible aircraft; the
    row says by how much): 'contaminated' when that share passes ``energy_limit`` or the shift
    ``shift_limit_percent``, or when no hung mode pairs with it ('unpaired': MAC below 0.6). A line
    loaded or stretched past its allowance is a problem of the layout (a spring that would yield), not
    an error. ``base``: the configuration hung (its masses and loads kept, see layout_configuration);
    default the bare structure in 1 g.
    """
    results = []
    for layout in layouts:
        try:
            cfg = layout_configuration(model, layout, base=base)
        except ModelError as exc:  # a line too soft for its anchor: a finding of the plan
            if base is not None and base.fixed:
                raise
            results.append(LayoutResult(layout, None, None, problems=[str(exc)]))
            continue
        results.append(assess(model, cfg, layout, n_modes, energy_limit, shift_limit_percent))
    return rank(results)


def rank(results: Iterable[LayoutResult]) -> list[LayoutResult]:
    """Acceptable first, then fewer contaminated elastic modes, then the smaller largest shift of an
    elastic mode from free-free (to 0.01 %), then the larger separation."""
    return sorted(results, key=lambda r: (not r.acceptable, r.n_contaminated, round(r.max_shift_percent, 2),
                                          -r.separation))


def effective_independence(shapes: np.ndarray, n_sensors: int) -> np.ndarray:
    """Indices of ``n_sensors`` rows of ``shapes`` (n_candidates, n_modes) kept by effective
    independence (Kammer): the candidate with the smallest E_i = diag(Phi (Phi^T Phi)^-1 Phi^T) is
    dropped, one at a time, so the kept rows keep the target modes as independent as possible."""
    Phi = np.asarray(shapes, float)
    n_modes = Phi.shape[1]
    if n_sensors < n_modes:
        raise ModelError(f"effective_independence: {n_sensors} sensors cannot tell {n_modes} modes apart")
    keep = np.arange(len(Phi))
    while len(keep) > n_sensors:
        P = Phi[keep]
        E = np.einsum("ij,jk,ik->i", P, np.linalg.pinv(P.T @ P), P)
        keep = np.delete(keep, int(np.argmin(E)))
    return keep


def place_sensors(modes: Modes, n_sensors: int, candidates: Sensors | None = None,
                  mode_indices: Sequence[int] | None = None) -> tuple[Sensors, np.ndarray]:
    """Sensors (flexgvt.correlation.Sensors) for the target modes on their deformed state: the
    candidates (default: X, Y, Z at every node, following the deformed structure) chosen by
    effective independence, and the candidates' auto-MAC of the targets."""
    from ..correlation import auto_mac
    idx = np.arange(modes.n_modes) if mode_indices is None else np.asarray(mode_indices, int)
    cand = candidates if candidates is not None else Sensors.triaxial(modes.node_ids)
    S = cand.matrix(modes.node_ids, modes.state)
    Phi = np.asarray(S @ modes.matrix()[:, idx])
    keep = effective_independence(Phi, n_sensors)
    chosen = Sensors([cand[k] for k in keep])
    return chosen, auto_mac(Phi[keep].T)


def driving_residues(modes: Modes, candidates: Sensors | None = None,
                     mode_indices: Sequence[int] | None = None) -> np.ndarray:
    """(n_candidates, n_targets) driving-point residues phi_r(p)^2 of each candidate exciter point
    for each target mode, normalised by the mode's largest over the candidates (1: the best point
    for that mode, 0: a node of it)."""
    idx = np.arange(modes.n_modes) if mode_indices is None else np.asarray(mode_indices, int)
    cand = candidates if candidates is not None else Sensors.triaxial(modes.node_ids)
    Phi = np.asarray(cand.matrix(modes.node_ids, modes.state) @ modes.matrix()[:, idx])
    return Phi**2 / np.maximum((Phi**2).max(axis=0, keepdims=True), 1e-300)


def driving_point(modes: Modes, candidates: Sensors | None = None,
                  mode_indices: Sequence[int] | None = None) -> tuple[int, np.ndarray]:
    """The candidate sensor/exciter point that drives every target mode best: it maximises the
    smallest driving-point residue phi_r(p)^2, each mode's residues normalised by their largest.
    Returns (index into candidates, the normalised residues of that point per mode)."""
    idx = np.arange(modes.n_modes) if mode_indices is None else np.asarray(mode_indices, int)
    res = driving_residues(modes, candidates, idx)
    best = int(np.argmax(res.min(axis=1)))
    if res[best].min() < 1e-3:
        weak = idx[np.argmin(res[best])]
        raise ModelError(f"driving_point: no candidate drives mode {weak + 1} "
                         f"({modes.labels[weak] if modes.labels else ''});"
                         " add candidate points off the elastic axis or in other directions")
    return best, res[best]
