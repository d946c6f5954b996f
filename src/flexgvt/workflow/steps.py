"""Steps 2-4 of the main job, each a public function a script can call on its own:
updating on every configuration at once, the check of unseen configurations, and the
free-flying prediction (suspension removed, proposed suspensions) scored against a reference."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import FlexGVTError
from ..model import Configuration, Model
from ..updating import MassTarget, Objective, ResultsStore, UpdateResult
from .identification import Identified, measured
from .project import Project, ProjectError


def objective(project: Project) -> tuple[Objective, MassTarget | None]:
    """(Objective, MassTarget or None) from the project's [objective] table."""
    from dataclasses import fields

    o = project.spec.objective
    return Objective(**{f.name: getattr(o, f.name) for f in fields(Objective)}), o.measured_mass


def update_model(project: Project, identified: dict[str, Identified], store: ResultsStore | None = None,
                 progress: Callable[[dict], None] | None = None,
                 callback: Callable[[dict], None] | None = None) -> UpdateResult:
    """flexgvt.updating.update on every configuration with role 'update' at once, with the project's
    [optimiser] settings; progress: called with each accepted iterate's history row (``callback``:
    its deprecated name)."""
    from ..updating import update
    from ..updating.settings import renamed
    if callback is not None:
        renamed("update_model(callback=...)", "update_model(progress=...)")
        progress = progress or callback
    names = project.to_update
    missing = [n for n in names if n not in identified]
    if missing:
        raise ProjectError(f"{project.path}: no measured modes for configuration(s) {missing}")
    obj, target = objective(project)
    return update(project.model, [project.configurations[n] for n in names],
                  [measured(identified[n], project) for n in names], project.variables, mass_target=target,
                  objective=obj, store=store, progress=progress, **project.spec.optimiser.to_dict())


def check(project: Project, model: Model, identified: dict[str, Identified], n_modes: int | None = None) -> dict:
    """Configurations with role 'check' (not updated on): measured against ``model``'s modes, paired by
    MAC (or frequency without shapes, within the measured mode's family when labelled). Returns
    {name: rows}; an unpaired mode's row says why (unpaired_reason)."""
    from ..fem import solve_modes, solve_static
    from ..correlation import pair, pair_by_frequency
    out = {}
    for spec in project.spec.configurations:
        if spec.role != "check" or spec.name not in identified:
            continue
        meas = identified[spec.name]
        modes = solve_modes(solve_static(model, project.configurations[spec.name]),
                            n_modes or 2 * len(meas.frequencies_hz) + 6, damped=False)
        rows = []
        if meas.shapes is not None:
            m = measured(meas, project)
            p = pair(meas, modes, m.sensors, mac_floor=project.spec.objective.mac_floor,
                     max_frequency_ratio=project.spec.objective.max_frequency_ratio, configuration=spec.name)
        else:  # by frequency, among the FE modes of each measured mode's family when its label names one
            p = pair_by_frequency(meas.frequencies_hz, modes.frequencies_hz, measured_labels=meas.labels,
                                  analytical_labels=modes.labels, configuration=spec.name,
                                  max_frequency_ratio=project.spec.objective.max_frequency_ratio)
        got = {int(i): (int(j), None if np.isnan(v) else float(v)) for i, j, v in zip(p.measured, p.analytical, p.mac)}
        why = {u.mode - 1: u.text for u in p.reasons}
        for i, f in enumerate(meas.frequencies_hz):
            j, mac = got.get(i, (None, None))
            fa = None if j is None else float(modes.frequencies_hz[j])
            rows.append({"mode": i + 1, "label": meas.labels[i] if i < len(meas.labels) else "",
                         "measured_hz": float(f), "analytical_hz": fa,
                         "error_percent": None if fa is None else 100 * (fa - f) / f, "mac": mac,
                         "unpaired_reason": why.get(i)})
        out[spec.name] = rows
    return out


def _pair_by_frequency(measured, analytical) -> dict:
    from scipy.optimize import linear_sum_assignment
    fa = np.asarray(analytical)
    ok = np.flatnonzero(fa > 1e-6)
    cost = np.abs(np.log(np.asarray(measured)[:, None] / fa[ok][None, :]))
    r, c = linear_sum_assignment(cost)
    return {int(i): (int(ok[j]), None) for i, j in zip(r, c)}


@dataclass
class Prediction:
    """Free-flying prediction of one model: free-free modes (suspension removed, free fall) and each
    proposed configuration's elastic modes paired with them by mass-weighted MAC; rows: one per
    free elastic mode (free_hz, <configuration>_hz, <configuration>_shift_percent, ...,
    reference_hz and error_percent when a reference was given; <value>_low_hz and <value>_high_hz,
    the confidence bounds, when they were computed); modes: {configuration: its full mode list}
    (configuration_modes); uncertainty: how the bounds were made (flexgvt.workflow.add_bounds), or None."""

    model_name: str
    rows: list[dict]
    free: object
    proposed: dict = field(default_factory=dict)
    modes: dict = field(default_factory=dict)
    uncertainty: dict | None = None

    def frequencies(self) -> np.ndarray:
        """The free-free elastic frequencies [Hz] of the rows."""
        return np.array([r["free_hz"] for r in self.rows])

    def table(self) -> list[dict]:
        """The rows (one per free elastic mode)."""
        return self.rows


def predict(project: Project, model: Model, configurations: dict[str, Configuration] | None = None,
            n_modes: int | None = None) -> Prediction:
    """Remove the suspension of ``model`` and predict the free-free modes, the tested configurations'
    suspended modes and the proposed configurations' modes, each paired with the free-free ones."""
    from ..suspension import remove_suspension
    n = n_modes or project.spec.prediction.n_modes
    configurations = configurations or project.configurations
    cases = {name: cfg for name, cfg in configurations.items() if cfg.suspension and not cfg.fixed}
    for name in project.spec.prediction.proposed:
        cases[name] = project.available.get(name) or configurations[name]
    if not cases:
        raise ProjectError(f"{project.path}: nothing to predict: no configuration hangs on cords "
                           "(add prediction.proposed or a suspended configuration)")
    rows: dict[int, dict] = {}
    free = None
    proposed = {}
    modes = {}
    for name, cfg in cases.items():
        try:
            removal = remove_suspension(model, cfg, n_modes=n)
        except FlexGVTError as exc:
            raise ProjectError(f"prediction, configuration '{name}': {exc}") from None
        free = removal.free
        proposed[name] = removal.suspended
        modes[name] = configuration_modes(removal)
        for r in removal.rows:
            row = rows.setdefault(r["free_mode"], {"free_mode": r["free_mode"], "label": r["label"],
                                                   "free_hz": r["free_hz"]})
            row[f"{name}_hz"] = r["suspended_hz"]
            row[f"{name}_shift_percent"] = r["suspended_shift_percent"]
            row[f"{name}_mac"] = r["suspended_mac"]
    out = Prediction(model.name, [rows[k] for k in sorted(rows)], free, proposed, modes)
    if project.spec.prediction.reference is not None:
        from .validate import read_json
        path = project.file(project.spec.prediction.reference)
        score(out, read_json(path, f"{project.path}: prediction.reference"), where=f"{project.path}: {path}")
    return out


def configuration_modes(removal) -> list[dict]:
    """Every mode (above 0 Hz) of a predicted configuration (a flexgvt.suspension Removal's suspended
    case): mode number, frequency_hz, label, suspension (its energy mostly in the cords), and the
    free-free mode it pairs with by mass-weighted MAC (free_mode, free_label, mac), None when it pairs
    with none (a mode of the suspended aircraft with no free-free partner above the MAC floor)."""
    modes = removal.suspended
    partner = {r["suspended_mode"]: r for r in removal.rows if r.get("suspended_mode") is not None}
    out = []
    for j, f in enumerate(modes.frequencies_hz):
        if not f > 0:
            continue
        r = partner.get(j + 1)
        out.append({"mode": j + 1, "frequency_hz": float(f), "label": modes.labels[j] if modes.labels else "",
                    "suspension": bool(modes.energy_fractions[j, 4] > 0.5),
                    "free_mode": None if r is None else r["free_mode"],
                    "free_label": None if r is None else r["label"],
                    "mac": None if r is None else r["suspended_mac"]})
    return out


def score(prediction: Prediction, reference: dict, where: str = "reference") -> None:
    """Add reference_hz and error_percent to the free-free rows. reference: {'free_free':
    {'frequencies_hz': [...], 'labels': [...]}} (elastic modes); paired by label where the labels
    agree one to one, else by nearest frequency (one to one). ProjectError (naming ``where``) for
    any other layout."""
    from .validate import reference_table
    f, labels = reference_table(reference, where)
    pred = prediction.frequencies()
    if not len(f) or not len(pred):
        return
    pairs = _pair_by_frequency(f, pred)
    lab = [r["label"] for r in prediction.rows]
    for i, name in enumerate(labels):
        if name and lab.count(name) == 1 and labels.count(name) == 1:
            pairs[i] = (lab.index(name), None)
    for i, (j, _) in pairs.items():
        row = prediction.rows[j]
        row["reference_hz"] = float(f[i])
        row["reference_label"] = labels[i] if i < len(labels) else ""
        row["error_percent"] = 100 * (row["free_hz"] - f[i]) / f[i]
