"""Pre-test planning of the user's own project (`flexgvt plan project.toml`), as Testlab or FEMtools
pre-test analysis does, on the deformed configurations:

    project = fg.workflow.plan.load_plan_project("project.toml")
    result = fg.workflow.plan.plan_project(project)        # writes pretest/*.csv, pretest/plan.json

For each configuration of the project: every candidate suspension of [plan] (each station with
each line rate and cord length; and the configuration's own cords, when it has some) hung under the
configuration's masses, loads and gravity, ranked by flexgvt.suspension.plan_suspension; then, on
the configuration as it will be tested (its own suspension, else the best candidate, else as it
stands), the target elastic modes, the sensors chosen by effective independence (with the chosen
set's auto-MAC) and the driving points ranked by their smallest normalised residue over the target
modes. The workflow returns results and writes tables; the report (flexgvt.report.pretest) renders.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ..correlation import Sensors
from ..errors import FlexGVTError, ModelError
from ..fem import solve_modes, solve_static
from ..model import Configuration
from ..suspension import (Attachment, Layout, LayoutResult, Line, LineElement, assess, driving_residues,
                          place_sensors, plan_suspension, rank)
from .plansettings import PlanSettings
from .projectbase import Project, ProjectError

AXES = "XYZ"
WEAK_RESIDUE = 0.05  # a driving point exciting a target mode below 5 % of that mode's best point is noted


@dataclass
class ConfigurationPlan:
    """The plan of one configuration: its candidate suspensions ranked (best first), the one the
    sensors were placed on (``tested``: a candidate's or the configuration's own suspension, or
    the configuration as it stands when it has none), its static state and modes, the target modes,
    the chosen sensors with their auto-MAC and the driving points (rows, best first)."""

    name: str
    base: Configuration
    layouts: list[LayoutResult]
    tested: str
    configuration: Configuration
    state: object
    modes: object
    targets: np.ndarray
    sensors: Sensors
    auto_mac: np.ndarray
    exciters: list[dict]
    notes: list[str] = field(default_factory=list)
    visibility: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def auto_mac_max(self) -> float:
        """Largest off-diagonal auto-MAC of the target modes at the chosen sensors."""
        a = np.asarray(self.auto_mac)
        return float(np.max(np.abs(a - np.diag(np.diag(a))))) if a.size > 1 else 0.0

    def layout_rows(self) -> list[dict]:
        """One row per candidate suspension, best first."""
        rows = []
        for k, r in enumerate(self.layouts):
            first = next((e for e in r.elastic if e.get("suspended_hz") is not None), None)
            rows.append({"rank": k + 1, "suspension": r.name, "acceptable": r.acceptable,
                         "highest_suspension_hz": float(r.suspension_hz.max()) if len(r.suspension_hz) else None,
                         "first_elastic_hz": r.first_elastic_hz, "separation": r.separation if r.state else None,
                         "first_elastic_shift_percent": None if first is None else first["suspended_shift_percent"],
                         "largest_elastic_shift_percent": _largest_shift(r),
                         "contaminated": ", ".join(e["label"] + (" (unpaired)" if e.get("unpaired") else "")
                                                   for e in r.elastic if e.get("contaminated")),
                         "cord_tension_N": ", ".join(f"{t:.3g}" for t in r.tensions),
                         "problems": "; ".join(r.problems)})
        return rows

    def target_rows(self) -> list[dict]:
        """The target modes of the tested configuration."""
        m = self.modes
        return [{"mode": int(j) + 1, "label": m.labels[j] if m.labels else "",
                 "frequency_hz": float(m.frequencies_hz[j]), "suspension_energy": float(m.energy_fractions[j, 4]),
                 "seen_by_candidates": float(v)} for j, v in zip(self.targets, self.visibility)]

    def sensor_rows(self) -> list[dict]:
        """The chosen sensors: node, direction and position on the deformed structure [m]."""
        index = {int(n): k for k, n in enumerate(self.modes.node_ids)}
        rows = []
        for k, s in enumerate(self.sensors):
            p = self.state.positions[index[int(s.node)]]
            rows.append({"sensor": k + 1, "name": s.name, "node": int(s.node), "direction": _axis(s.direction),
                         **{f"{a}_m": round(float(v), 9) for a, v in zip("xyz", p)}})
        return rows

    def to_dict(self) -> dict:
        return {"configuration": self.name, "tested_on": self.tested, "layouts": self.layout_rows(),
                "elastic": {r.name: r.elastic for r in self.layouts},
                "suspension_modes": {r.name: [{"label": lab, "frequency_hz": float(f)} for lab, f in zip(
                    r.suspension_labels, r.suspension_hz)] for r in self.layouts},
                "target_modes": self.target_rows(), "sensors": self.sensor_rows(),
                "auto_mac": np.asarray(self.auto_mac).tolist(), "auto_mac_max_offdiagonal": self.auto_mac_max,
                "exciters": self.exciters, "notes": self.notes}


@dataclass
class PlanResult:
    """The pre-test plan of a project: one ConfigurationPlan per planned configuration; files: the
    tables and JSON written ({name: path})."""

    project: Project
    settings: PlanSettings
    configurations: dict[str, ConfigurationPlan]
    output: Path
    files: dict[str, Path] = field(default_factory=dict)

    def to_dict(self) -> dict:
        from dataclasses import asdict
        return {"project": self.project.spec.project.name, "file": str(self.project.path),
                "settings": asdict(self.settings),
                "configurations": [c.to_dict() for c in self.configurations.values()]}


def _largest_shift(r: LayoutResult) -> float | None:
    """The signed shift [%] of the paired elastic mode the suspension moves most (None: none paired)."""
    shifts = [e["suspended_shift_percent"] for e in r.elastic if e.get("suspended_shift_percent") is not None]
    return max(shifts, key=abs) if shifts else None


def _axis(direction) -> str:
    d = np.asarray(direction, float)
    a = int(np.argmax(np.abs(d)))
    return ("+" if d[a] > 0 else "-") + AXES[a] if np.isclose(abs(d[a]), 1.0) else str(np.round(d, 3).tolist())


def load_plan_project(path: str | Path) -> Project:
    """The project file read for planning: as flexgvt.workflow.load_project, but configurations need
    no test data and the project no design variables (the test is still to be done); every [plan]
    node and configuration checked, naming the key."""
    from .project import load_project
    project = load_project(path, pretest=True)
    check_plan(project)
    return project


def check_plan(project: Project) -> None:
    """ProjectError naming the [plan] key that names an unknown configuration or node, or a
    suspension grid that cannot be built."""
    s: PlanSettings = project.spec.plan
    where = f"{project.path}: plan"
    known = list(project.configurations)
    for k, name in enumerate(s.configurations):
        if name not in project.configurations:
            raise ProjectError(f"{where}.configurations[{k}]: no configuration '{name}' in the project; it has "
                               f"{known}")
    ids = set(int(n) for n in project.model.node_ids)
    for key, nodes in (("sensor_nodes", s.sensor_nodes), ("exciter_nodes", s.exciter_nodes),
                       *((f"stations[{k}]", st) for k, st in enumerate(s.stations))):
        bad = [n for n in nodes if n not in ids]
        if bad:
            raise ProjectError(f"{where}.{key}: node(s) {bad} not in model '{project.model.name}' (node ids "
                               f"{min(ids)}-{max(ids)}); give node ids of the deck")
    if s.stations and not (s.stiffness and s.length):
        missing = " and ".join(k for k in ("stiffness", "length") if not getattr(s, k))
        raise ProjectError(f"{where}: stations are given without {missing}: list the candidate line rates "
                           "(stiffness = [\"5 N/m\", \"20 N/m\"]) and cord lengths (length = [\"2 m\"]) to try")
    if (s.stiffness or s.length) and not s.stations:
        raise ProjectError(f"{where}: stiffness and length are tried at the stations: add stations = [[node, "
                           "node], ...] (the nodes hung at once)")
    n_candidates = len(s.sensor_nodes or ids) * len(s.directions)
    if s.sensors > n_candidates:
        raise ProjectError(f"{where}.sensors: {s.sensors} sensors but only {n_candidates} candidates "
                           "(sensor_nodes x directions); lower sensors or add candidates")
    for name in (s.configurations or known):
        c = project.configurations[name]
        if s.stations and c.fixed:
            raise ProjectError(f"{where}.stations: configuration '{name}' fixes DOFs (nodes {sorted(c.fixed)}); a "
                               "suspension hangs a free structure: plan the suspension on configurations without "
                               "supports (plan.configurations)")


def candidate_layouts(project: Project, base: Configuration) -> list[Layout]:
    """Every [plan] station with every line rate and cord length, anchors straight above the
    attachments (against the configuration's gravity)."""
    s: PlanSettings = project.spec.plan
    model = project.model
    up = -np.asarray(base.gravity_direction, float) / np.linalg.norm(base.gravity_direction)
    layouts = []
    for nodes in s.stations:
        for k in s.stiffness:
            for length in s.length:
                line = Line((LineElement(f"{k:g} N/m line", k, length,
                                         allowed_load=float("inf") if s.allowed_load is None else s.allowed_load),))
                attach = [model.xyz[model.index_of([n])[0]] for n in nodes]
                layouts.append(Layout(f"{k:g} N/m, {length:g} m at nodes {', '.join(str(n) for n in nodes)}", tuple(
                    Attachment(int(n), line, tuple(float(v) for v in p + length * up)) for n, p in zip(nodes, attach))))
    return layouts


def _candidates(project: Project, nodes, directions: str) -> Sensors:
    from ..correlation.sensors import Sensor
    nodes = [int(n) for n in (nodes or project.model.node_ids)]
    return Sensors([Sensor(n, np.eye(3)[AXES.index(a)], name=f"{n}+{a}") for n in nodes for a in directions.upper()])


def plan_configuration(project: Project, name: str, progress: Callable[[str], None] = lambda s: None
                       ) -> ConfigurationPlan:
    """The plan of one configuration of ``project`` (see the module's docstring)."""
    s: PlanSettings = project.spec.plan
    model, base = project.model, project.configurations[name]
    where = f"{project.path}: plan (configuration '{name}')"
    layouts = candidate_layouts(project, base)
    results: list[LayoutResult] = []
    if layouts:
        progress(f"{name}: {len(layouts)} candidate suspension(s)")
        results = plan_suspension(model, layouts, n_modes=s.n_modes, energy_limit=s.energy_limit,
                                  shift_limit_percent=s.shift_limit_percent, base=base)
    if base.suspension:
        progress(f"{name}: the configuration's own suspension")
        own = base.with_(gravity=base.gravity or 1.0)
        results = rank(results + [assess(model, own, Layout(f"as configured ({name})", ()), s.n_modes,
                                         s.energy_limit, s.shift_limit_percent)])
    notes = []
    if base.suspension:
        tested, cfg = f"as configured ({name})", base.with_(gravity=base.gravity or 1.0)
    elif results:
        best = results[0]
        tested, cfg = best.name, best.configuration
        if not best.acceptable:
            notes.append(f"no candidate suspension is free of problems; sensors are placed on the best, "
                         f"'{best.name}': {'; '.join(best.problems)}")
        if cfg is None:
            raise ProjectError(f"{where}: no candidate suspension could be hung ({'; '.join(best.problems)}); change "
                               "plan.stiffness, plan.length or plan.stations")
    else:
        tested, cfg = "as configured (no suspension)", base
    progress(f"{name}: sensors and driving points on '{tested}'")
    try:
        try:
            state = solve_static(model, cfg)
        except FlexGVTError as exc_:
            if cfg.suspension or cfg.fixed:
                raise
            raise ProjectError(f"{where}: the configuration has no supports and no suspension ({exc_}); give "
                               "candidate suspensions (plan.stations, plan.stiffness, plan.length) or cords to the "
                               "configuration, or plan it free-free without loads (gravity = 0)") from None
        modes, targets = _targets(state, s, 6 + len(cfg.suspension))
        if not len(targets):
            raise ProjectError(f"{where}: no elastic mode"
                               + (f" in plan.band_hz = {list(s.band_hz)} Hz" if s.band_hz else "")
                               + f" among the {modes.n_modes} lowest modes ({modes.frequencies_hz.min():.3g}-"
                               f"{modes.frequencies_hz.max():.3g} Hz); widen or lower plan.band_hz")
        if len(targets) < s.n_modes:
            notes.append(f"{len(targets)} elastic target mode(s) of the {s.n_modes} asked"
                         + (f" in {list(s.band_hz)} Hz" if s.band_hz else ""))
        if s.sensors < len(targets):
            raise ProjectError(f"{where}: plan.sensors: {s.sensors} sensors cannot tell {len(targets)} target modes "
                               "apart; raise plan.sensors or lower plan.n_modes")
        cand = _candidates(project, s.sensor_nodes, s.directions)
        chosen, amac = place_sensors(modes, s.sensors, cand, targets)
        seen = _visibility(modes, cand, targets)
        exc = _candidates(project, s.exciter_nodes or s.sensor_nodes, s.exciter_directions or s.directions)
        residues = driving_residues(modes, exc, targets)
    except ModelError as exc_:
        raise ProjectError(f"{where}: {exc_}") from None
    order = np.argsort(-residues.min(axis=1), kind="stable")[: s.exciters]
    labels = [modes.labels[j] if modes.labels else f"mode {j + 1}" for j in targets]
    exciters = []
    for k, i in enumerate(order):
        r = residues[i]
        exciters.append({"rank": k + 1, "name": exc[i].name, "node": int(exc[i].node), "direction": _axis(
            exc[i].direction), "min_residue": float(r.min()), "weakest_mode": labels[int(np.argmin(r))],
            "mean_residue": float(r.mean()), "residues": {lab: float(v) for lab, v in zip(labels, r)}})
    faint = [f"{lab} ({100 * v:.1f} %)" for lab, v in zip(labels, seen) if v < 0.1]
    if faint:
        notes.append(f"the candidate sensor directions ({s.directions}) barely see {', '.join(faint)} (largest "
                     "reading over the mode's largest translation): add directions (plan.directions) or narrow "
                     "plan.band_hz to the modes they see")
    best = residues[order[0]]
    if best.min() < WEAK_RESIDUE:
        weak = int(np.argmin(best))
        other = exc[int(np.argmax(residues[:, weak]))].name
        notes.append(f"the best single driving point, {exciters[0]['name']}, drives '{labels[weak]}' at "
                     f"{100 * best.min():.2g} % of that mode's best point ({other}): add a second exciter at {other} "
                     "(a multiple-input test), or exciter candidates in other places or directions "
                     "(plan.exciter_nodes, plan.exciter_directions)")
    return ConfigurationPlan(name, base, results, tested, cfg, state, modes, targets, chosen, amac, exciters, notes,
                             seen)


def _targets(state, s: PlanSettings, n_extra: int, most: int = 400):
    """The modes about ``state`` and the indices of the target elastic modes (energy mostly in the
    structure, above 0 Hz, inside band_hz): more modes are solved until n_modes targets are found or
    the modes pass the band (at most ``most``)."""
    n = s.n_modes + n_extra
    while True:
        modes = solve_modes(state, n, damped=False)
        ok = (modes.energy_fractions[:, 4] <= 0.5) & (modes.frequencies_hz > 0)
        if s.band_hz is not None:
            ok &= (modes.frequencies_hz >= s.band_hz[0]) & (modes.frequencies_hz <= s.band_hz[1])
        targets = np.flatnonzero(ok)[: s.n_modes]
        if (len(targets) == s.n_modes or s.band_hz is None or modes.frequencies_hz.max() > s.band_hz[1]
                or n >= most or modes.n_modes < n):
            return modes, targets
        n = min(2 * n, most)


def _visibility(modes, candidates: Sensors, targets: np.ndarray) -> np.ndarray:
    """Per target mode: the largest candidate reading over the mode's largest nodal translation
    (1: some candidate reads the mode's full motion; near 0: the candidates' directions miss it)."""
    Phi = np.asarray(candidates.matrix(modes.node_ids, modes.state) @ modes.matrix()[:, targets])
    peak = np.linalg.norm(modes.shapes[targets, :, :3], axis=2).max(axis=1)
    return np.abs(Phi).max(axis=0) / np.where(peak > 0, peak, 1.0)


def plan_project(project: Project, out: Path | None = None, progress: Callable[[str], None] | None = None
                 ) -> PlanResult:
    """Plan every configuration of [plan] (default all); write layouts_<cfg>.csv, sensors_<cfg>.csv,
    exciters_<cfg>.csv and plan.json into ``out`` (default: the project's outputs.directory/pretest)."""
    from ..io.tables import write_csv
    progress = progress or (lambda s: None)
    s: PlanSettings = project.spec.plan
    names = list(s.configurations) or list(project.configurations)
    plans = {}
    for name in names:
        try:
            plans[name] = plan_configuration(project, name, progress)
        except ProjectError:
            raise
        except FlexGVTError as exc:
            raise ProjectError(f"{project.path}: plan (configuration '{name}'): {exc}") from None
    out = Path(out) if out is not None else project.output / "pretest"
    result = PlanResult(project, s, plans, out)
    out.mkdir(parents=True, exist_ok=True)
    taken: set[str] = set()
    for name, p in plans.items():
        slug = _slug(name, taken)
        for kind, rows in (("layouts", p.layout_rows()), ("sensors", p.sensor_rows()),
                           ("exciters", [{k: v for k, v in r.items() if k != "residues"} for r in p.exciters]),
                           ("targets", p.target_rows())):
            if rows:
                result.files[f"{kind}_{name}"] = write_csv(rows, out / f"{kind}_{slug}.csv")
    path = out / "plan.json"
    from ..updating.result import jsonable
    path.write_text(json.dumps(jsonable(result.to_dict()), indent=1))
    result.files["json"] = path
    return result


def _slug(text: str, taken: set[str]) -> str:
    import re
    base = re.sub(r"[^A-Za-z0-9_-]+", "_", text).strip("_")[:48] or "configuration"
    slug, k = base, 2
    while slug in taken:
        slug, k = f"{base}_{k}", k + 1
    taken.add(slug)
    return slug
