"""A project run's results (flexgvt.workflow.RunResult) as a ReportContent, and the report written
into the run's output folder (the face calls it: `flexgvt run`, `flexgvt demo`, users' scripts;
the workflow returns results and never renders): deformed shapes, stabilisation diagrams,
MAC matrices, frequency errors before and after, animated mode shapes (measured on analytical,
on the deformed geometry), design variables with their uncertainty, frequency versus load and
the free-flying prediction."""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path

import numpy as np

from ..fem import modes_versus_load, solve_modes, solve_static
from ..io.uff import shapes_at_points
from ..workflow import measured
from ..workflow.stages import mass_rows
from ..workflow.runner import write_results
from . import testdata
from .content import ConfigurationSection, Geometry, ModeShape, ReportContent, StabilisationData, StageSection
from .figures import variable_bars
from .html import write_report


def _geometry(model, positions):
    edges = [model.index_of(g.nodes) for g in model.beams]
    return Geometry(np.asarray(positions, float), np.concatenate(edges) if edges else np.zeros((0, 2), int))


def _measured_points(project, item, state):
    """Test points' deformed positions and measured real shapes (n_modes, p, 3), or (None, None)."""
    if item.shapes is None:
        return None, None
    points, shapes = shapes_at_points(np.real(item.shapes), item.outputs)
    node_map, offsets = project.sensors.get(item.configuration, ({}, {}))
    ids = list(state.system.cm.node_ids)
    xyz = []
    for p in points:
        k = ids.index(node_map.get(int(p), int(p)))
        xyz.append(state.positions[k] + state.rotations[k] @ np.asarray(offsets.get(int(p), np.zeros(3)), float))
    return np.asarray(xyz), shapes


def _stop_note(up) -> str:
    """The optimiser's message, and at the evaluation limit how far the objective still moved."""
    objective = [float(h["objective"]) for h in up.history]
    if "maximum number" not in str(up.message).lower() or len(objective) < 2:
        return str(up.message)
    k = min(10, len(objective) - 1)
    before, last = objective[-1 - k], objective[-1]
    fall = 100 * (before - last) / before if before > 0 else 0.0
    return (f"stopped at the evaluation limit (max_iterations); the objective fell {fall:.2g} % over its last {k} "
            "iterations" + (", still falling: raise max_iterations" if fall > 5 else ""))


def _frequency_rows(item, up, name: str, table: list[dict], zeta_model) -> tuple[list[dict], list[str]]:
    """The frequency and damping table of an updated configuration, and a note per unpaired mode."""
    rows, notes = [], []
    unpaired = any(not r.get("paired", r.get("updated_hz") is not None) for r in table)
    for i, r in enumerate(table):
        row = {"mode": r["mode"], "label": r["label"], "measured_hz": r["measured_hz"],
               "measured_std_hz": r.get("measured_std_hz")}
        row.update(testdata.measured_damping(item, i) if item is not None and i < item.n_modes else {})
        j = r.get("updated_mode")
        if zeta_model is not None:
            z = None if j is None or j - 1 >= len(zeta_model) else zeta_model[j - 1]
            row["model_damping_percent"] = None if z is None or not np.isfinite(z) else 100 * float(z)
        row.update({"initial_hz": r["initial_hz"], "updated_hz": r["updated_hz"],
                    "initial_error_percent": r["initial_error_percent"],
                    "updated_error_percent": r["updated_error_percent"],
                    "mac_initial": r["initial_mac"], "mac_updated": r["updated_mac"]})
        if unpaired:
            paired = r.get("paired", r.get("updated_hz") is not None)
            why = "" if paired else testdata.unpaired_reason(r, up, name)
            row["pairing"] = "paired" if paired else "unpaired" + (f": {why}" if why else "")
            if not paired:
                notes.append(f"measured mode {r['mode']} ({r['label'] or 'no label'}, {r['measured_hz']:.4g} Hz) "
                             "is unpaired" + (f": {why}" if why else " (no reason given by the updating result)"))
        rows.append(row)
    return rows, notes


def _check_rows(res, name: str, item) -> list[dict]:
    """The table of a check configuration: measured against the initial and the updated model."""
    first = res.checks.get("initial", {}).get(name, [])
    after = {r["mode"]: r for r in res.checks.get("updated", {}).get(name, [])}
    rows = []
    for i, r in enumerate(first):
        u = after.get(r["mode"], {})
        row = {"mode": r["mode"], "label": r["label"], "measured_hz": r["measured_hz"],
               "measured_std_hz": None if item.frequency_std_hz is None else float(item.frequency_std_hz[i])}
        row.update(testdata.measured_damping(item, i))
        row.update({"initial_hz": r["analytical_hz"], "updated_hz": u.get("analytical_hz"),
                    "initial_error_percent": r["error_percent"], "updated_error_percent": u.get("error_percent"),
                    "mac_initial": r["mac"], "mac_updated": u.get("mac")})
        if r["analytical_hz"] is None or (after and u.get("analytical_hz") is None):
            row["pairing"] = "unpaired" + (f": {testdata.unpaired_reason(r, None, name)}"
                                           if testdata.unpaired_reason(r, None, name) else "")
        rows.append(row)
    return rows


def _update_of(res, name: str):
    """The UpdateResult that updated on configuration ``name``: the last stage's that did, or the run's."""
    for stage in reversed(getattr(res, "stages", None) or []):
        if stage.update is not None and name in stage.update.tables:
            return stage.update
    return res.update


def _section(res, name: str):
    project, up = res.project, _update_of(res, name)
    model = res.model
    item = res.identified.get(name)
    role = next(c.role for c in project.spec.configurations if c.name == name)
    rows, mac0, mac1, modes, state, notes, comac = [], None, None, [], None, [], []
    configuration = (up.configurations if up is not None else {}).get(name, project.configurations[name])
    if up is not None and name in up.tables:
        cp = up.final.configurations[name]
        state = cp.state
        fe = cp.modes()
        zeta = testdata.model_damping(state, fe, fe.n_modes)
        rows, notes = _frequency_rows(item, up, name, up.tables[name], zeta)
        if up.mac.get(name) is not None:
            mac0, mac1 = up.mac[name]
        xyz, meas = _measured_points(project, item, state) if item is not None else (None, None)
        for i, j in enumerate(cp.paired):
            if j < 0:
                continue
            modes.append(ModeShape(
                f"{rows[i]['label'] or fe.labels[j]} ({rows[i]['measured_hz']:.3f} Hz measured)",
                float(fe.frequencies_hz[j]), fe.shapes[j, :, :3], measured_hz=rows[i]["measured_hz"],
                mac=rows[i]["mac_updated"], measured_xyz=xyz,
                measured_displacement=None if meas is None else _aligned(meas[i], fe, j, xyz, state)))
        if item is not None and item.shapes is not None:
            comac = testdata.comac_rows(item, measured(item, project).sensors, fe, cp.paired)
    else:
        state = solve_static(model, configuration)
        fe = solve_modes(state, 12, damped=False)
        modes = [ModeShape(f"{fe.labels[j]}", float(fe.frequencies_hz[j]), fe.shapes[j, :, :3])
                 for j in range(min(8, fe.n_modes))]
        if item is not None and name in res.checks.get("initial", {}):
            rows = _check_rows(res, name, item)
            for r in rows:  # unlabelled test modes take the label of the updated model's paired mode
                if not r["label"] and r["updated_hz"]:
                    j = int(np.argmin(np.abs(fe.frequencies_hz - r["updated_hz"])))
                    if abs(fe.frequencies_hz[j] - r["updated_hz"]) <= 1e-6 * r["updated_hz"]:
                        r["label"] = fe.labels[j]
            notes = [f"measured mode {r['mode']} ({r['measured_hz']:.4g} Hz) is {r['pairing']}" for r in rows
                     if r.get("pairing")]
    d = None if item is None else item.diagram
    stab = None if not d else StabilisationData(d["frequencies_hz"], d["indicator"], d["orders"], d["poles_hz"],
                                                d["stable"], d["selected_hz"])
    n_a = 0 if mac1 is None else mac1.shape[1]
    labels_a = [f"{j + 1}: {fe.labels[j]} {fe.frequencies_hz[j]:.2f} Hz" if j < fe.n_modes else f"FE {j + 1}"
                for j in range(n_a)]
    labels_m = []
    if item is not None:
        labels_m = [f"{i + 1}: {f:.2f} Hz" for i, f in enumerate(item.frequencies_hz)]
    frfs, why = ([], "") if item is None else testdata.frf_comparisons(project, name, item)
    if why:
        notes.append(why if frfs else f"measured and synthesised FRFs not shown: {why}")
    return ConfigurationSection(
        name, _geometry(model, model.xyz), _geometry(model, state.positions), rows, mac0, mac1,
        labels_m if (mac1 is not None or (item is not None and item.shapes is not None)) else [], labels_a, stab,
        modes, role=role, test_modes=[] if item is None else testdata.test_mode_rows(item, [r["label"] for r in rows]),
        auto_mac=None if item is None else testdata.test_auto_mac(item), comac=comac,
        setup=testdata.setup_tables(project, name, configuration, item), frfs=frfs, notes=notes)


def _aligned(meas, fe, j, xyz, state):
    """The measured shape (p, 3) scaled and signed to the analytical one at the test points, so the
    two move together in the animation (least-squares scale)."""
    pos = state.positions
    near = [int(np.argmin(np.linalg.norm(pos - x, axis=1))) for x in xyz]
    ana = fe.shapes[j, near, :3]
    a, m = ana.ravel(), np.real(meas).ravel()
    scale = float(a @ m) / float(m @ m) if float(m @ m) > 0 else 1.0
    return np.real(meas) * scale


def _variable_rows(up) -> list[dict]:
    """The design-variable rows of an UpdateResult (kind, attribute, SI unit, values, bounds, status)."""
    variables = []
    for r in up.variables:
        std = r["std"]
        variables.append({"name": r["name"], "attribute": f"{r.get('kind', '')} {r.get('attribute', '')}".strip(),
                          "unit": testdata.variable_unit(r.get("kind", ""), r.get("attribute", "")),
                          "initial": r["initial"], "updated": r["final"],
                          "change_percent": r["change_percent"],
                          "std_percent": None if std is None or not r["initial"] else 100 * std / abs(r["initial"]),
                          "bounds": (r["lower"], r["upper"]), "at_bound": r["at_bound"],
                          "identifiable": r["identifiable"]})
    for row, status in zip(variables, variable_bars(variables)["status"]):
        row["status"] = status
    return variables


def _stage_sections(res) -> list[StageSection]:
    """A StageSection per stage of a staged run: its data and settings, fixed inputs, variables and the
    frequency table of each configuration it updated on."""
    out = []
    for s in getattr(res, "stages", None) or []:
        st, up = s.stage, s.update
        data = list(st.configurations)
        target = st.objective.measured_mass
        if target is not None and any(getattr(target, k) is not None for k in ("mass", "cg", "inertia")):
            data.append("measured mass properties (" + ", ".join(k for k in ("mass", "cg", "inertia")
                                                                  if getattr(target, k) is not None) + ")")
        summary = [("data", ", ".join(data) or "none (fixed inputs only)")]
        if st.description:
            summary.insert(0, ("description", st.description))
        frequencies, notes = {}, []
        if up is not None:
            summary += [("bounds", "about the values the stage starts from" if st.recentre else
                         "about the project's initial model"),
                        ("updating", f"{len(up.variables)} variables, {up.method}: {_stop_note(up)}"),
                        ("objective", f"{up.initial.objective:.4g} -> {up.final.objective:.4g} in "
                                      f"{_iterations(up)} ({up.solves} solves, {up.seconds:.1f} s)"
                                      + (" (read back from the store)" if s.resumed else ""))]
            for name, table in up.tables.items():
                rows, why = _frequency_rows(res.identified.get(name), up, name, table, None)
                frequencies[name] = rows
                notes += [f"{name}: {w}" for w in why]
        out.append(StageSection(st.name, summary, s.fixed, [] if up is None else _variable_rows(up), frequencies,
                                notes, mass_rows(st, up)))
    return out


def _iterations(up) -> str:
    """'54 iterations', or over the solves of the identifiability holds: '54 + 0 iterations (30, then 15
    variables)' (the history shown is the last solve's)."""
    solves = up.stages or []
    if len(solves) < 2:
        return f"{len(up.history) - 1} iterations"
    return (f"{' + '.join(str(r['iterations']) for r in solves)} iterations "
            f"({', then '.join(str(len(r['variables'])) for r in solves)} variables)")


def build_report_content(res):
    """A ReportContent for a RunResult."""
    project, up = res.project, res.update
    spec = project.spec
    summary = [("project", f"{spec.project.name} ({project.path.name})"), ("model", project.model.name),
               ("configurations", ", ".join(f"{c.name} ({c.role})" for c in spec.configurations))]
    for name, item in res.identified.items():
        summary.append((f"test data {name}", f"{len(item.frequencies_hz)} modes from {item.source}"))
    variables, history = [], []
    staged = getattr(res, "stages", None) or []
    for k, s in enumerate(staged):  # one line per stage; the final stage's updating is one of them
        u = s.update
        summary.append((f"stage {k + 1}: {s.stage.name}", f"{len(s.fixed)} fixed inputs set" if u is None else
                        f"{len(u.variables)} variables on {', '.join(s.stage.configurations) or 'the mass properties'}"
                        f": objective {u.initial.objective:.4g} -> {u.final.objective:.4g} in {_iterations(u)}; "
                        f"{_stop_note(u)}"))
    if up is not None and not staged:
        summary += [("updating", f"{len(up.variables)} variables, {up.method}: {_stop_note(up)}"),
                    ("objective", f"{up.initial.objective:.4g} -> {up.final.objective:.4g} in "
                                  f"{_iterations(up)} ({up.solves} solves, {up.seconds:.1f} s)")]
    if up is not None:
        variables = _variable_rows(up)
        history = [float(h["objective"]) for h in up.history]
    summary.append(("run time", ", ".join(f"{k} {v:.1f} s" for k, v in res.timings.items())))
    sections = [_section(res, c.name) for c in spec.configurations]
    evolution = None
    first = next((c.name for c in spec.configurations), None)
    if first is not None:
        cfg = (up.configurations if up is not None else project.configurations).get(first,
                                                                                      project.configurations[first])
        if cfg.gravity:
            tr = modes_versus_load(res.model, cfg, np.linspace(0.0, cfg.gravity, 6), 12)
            evolution = {"load_factors": tr.load_factors, "frequencies_hz": tr.frequencies_hz,
                         "labels": list(tr.labels)}
    prediction, title, modes, bounds = [], "Free-flying prediction", {}, None
    if "updated" in res.predictions or "initial" in res.predictions:
        key = "updated" if "updated" in res.predictions else "initial"
        bounds = res.predictions[key].uncertainty
        init = {r["free_mode"]: r for r in res.predictions.get("initial", res.predictions[key]).rows}
        for r in res.predictions[key].rows:
            row = {"mode": r["free_mode"], "label": r["label"]}
            if key == "updated" and r["free_mode"] in init:
                row["initial_free_hz"] = init[r["free_mode"]]["free_hz"]
                if "reference_hz" in init[r["free_mode"]]:
                    row["initial_error_percent"] = init[r["free_mode"]]["error_percent"]
            row.update(_interval_columns({k: v for k, v in r.items() if k not in ("free_mode", "label")
                                          and not k.endswith("_mac")}, bounds))
            prediction.append(row)
        title = f"Free-flying prediction ({key} model)"
        modes = _mode_lists(res.predictions[key].modes)
    notes = ["Free-flying prediction: free_hz is the model with the suspension removed (free-free, free fall); "
             "each <configuration>_hz is that suspended or proposed configuration's mode paired with it by "
             "mass-weighted MAC, with the shift the suspension causes."] if prediction else []
    if bounds and "failed" in bounds:
        notes.append(f"Confidence bounds were not computed: {bounds['failed']}")
    elif bounds:
        notes.append(f"Confidence bounds: each <value> {_level(bounds)} column is the {_level(bounds)} interval of "
                     f"that frequency ({bounds['method']}; sigma {bounds['sigma']:.3g} from the "
                     f"{bounds['sigma_source']}; docs/updating.md). A blank bound: a direction neither the data "
                     "nor a prior constrain.")
    if modes:
        notes.append("Every mode of each predicted configuration: its free-free partner by mass-weighted MAC, or "
                     "none (a mode of the suspended aircraft no free-free mode resembles); suspension modes "
                     "(energy mostly in the cords) marked.")
    if up is not None and up.identifiability.get("unidentifiable"):
        notes.append(f"variables the data cannot see: {up.identifiability['unidentifiable']}")
    stages = _stage_sections(res)
    final = next((s.stage for s in reversed(staged) if s.update is not None), None)
    whose = "" if final is None else f" (stage {final.index + 1}: {final.name})"  # the final updating stage's
    if stages:
        summary.insert(3, ("stages", " -> ".join(f"{k + 1}. {s.name}" for k, s in enumerate(stages))))
        notes.append("Staged updating: each stage starts from the model the previous one produced; the "
                     "configuration sections show the stage that last updated on them, the design variables and "
                     "history the final updating stage's, the prediction the final model's.")
    return ReportContent(f"flexgvt: {spec.project.name}", summary, sections, variables, history, evolution,
                         prediction, title, notes, modes, stages, "Design variables" + whose,
                         "Optimiser history" + whose)


def _level(bounds: dict) -> str:
    return f"{100 * bounds['confidence']:g}%"


def _interval_columns(row: dict, bounds: dict | None) -> dict:
    """<value>_low_hz and <value>_high_hz as one '<value> 95% [Hz]' column of (low, high) after <value>_hz."""
    if not bounds or "failed" in bounds:
        return row
    out = {}
    for k, v in row.items():
        if k.endswith(("_low_hz", "_high_hz")):
            continue
        out[k] = v
        base = k[:-3] if k.endswith("_hz") else None
        if base is not None and f"{base}_low_hz" in row:
            lo, hi = row[f"{base}_low_hz"], row[f"{base}_high_hz"]
            out[f"{base}_{_level(bounds)}_hz"] = _interval(lo, hi)
    return out


def _interval(lo: float | None, hi: float | None) -> str | None:
    """'low–high' [Hz] as the report writes frequencies; None when a bound is missing (unbounded)."""
    from .html import format_value
    return None if lo is None or hi is None else f"{format_value('_hz', lo)}\u2013{format_value('_hz', hi)}"


def _mode_lists(modes: dict) -> dict:
    """The report's rows of each predicted configuration's full mode list."""
    out = {}
    for name, rows in modes.items():
        out[name] = [{"mode": m["mode"], "label": m["label"], "frequency_hz": m["frequency_hz"],
                      **({"interval_hz": _interval(m["low_hz"], m["high_hz"])} if "low_hz" in m else {}),
                      "free-free_mode": None if m["free_mode"] is None else f"{m['free_mode']} ({m['free_label']})",
                      "mac": m["mac"], "suspension": m["suspension"]} for m in rows]
    return out


def write_project_report(res, out: Path | None = None) -> Path:
    """report.html (self-contained), figures/*.png and tables/*.csv of a RunResult in ``out``
    (default: the project's output folder), each file written atomically (a killed run leaves whole
    files); adds the report to ``res.files`` and rewrites results.json to list it."""
    t0 = time.perf_counter()
    out = Path(res.project.output if out is None else out)
    path = write_report_atomic(build_report_content(res), out)
    res.files.pop("results", None)  # listed after the report, as when the run wrote both
    res.files["report"] = str(path)
    res.timings["report"] = time.perf_counter() - t0
    write_results(res, out)
    return path


def write_report_atomic(content, out: Path) -> Path:
    """flexgvt.report.write_report into a staging folder beside ``out``, then each file renamed into
    ``out`` (figures and tables first, report.html last): every file is whole at any moment."""
    stage = out / f".report-{os.getpid()}"
    shutil.rmtree(stage, ignore_errors=True)
    try:
        html = write_report(content, stage)
        for sub in ("figures", "tables"):
            if (stage / sub).is_dir():
                (out / sub).mkdir(exist_ok=True)
                for f in sorted((stage / sub).iterdir()):
                    os.replace(f, out / sub / f.name)
        os.replace(html, out / html.name)
    finally:
        shutil.rmtree(stage, ignore_errors=True)
    return out / html.name
