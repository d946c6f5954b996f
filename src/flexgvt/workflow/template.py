"""`flexgvt init`: a commented example project (every key explained) and, on request, a synthetic
GVT of the X-HALE-like aircraft's "as-built" airframe so that the example runs as it is."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import ModelError

HEADER = '''\
# flexgvt project: GVT data of several deformed configurations -> updated model -> free-flying
# prediction -> report. Run with `flexgvt run project.toml`. Paths are relative to this file.
# Quantities are SI numbers, or strings with a unit: "17.6 N/m", "800 g", "4.3 GPa".

[project]
name = "{name}"
description = "{description}"

[model]
case = "{case}"            # a built-in model (flexgvt.cases); or bdf = "wing.bdf" (Nastran bulk data)
# units = "mm-t-s"         # with bdf, the deck's units: SI (m-kg-s), mm-N-t-s (mm-t-s), in-lbf-s, ft-lbf-s
#                          # or a table: units = {{length = "mm", force = "N"}}
# [model.options]          # keyword arguments of the built-in case, e.g. n_per_section = 8; with bdf:
#                          # unsupported = "warn" reads a deck holding cards flexgvt skips (and lists them)

# Suspension points characterised on a block (docs/method.md section 2): stiffness and damping from the
# block's mass, damped frequency and damping ratio (lists = repeated tests, averaged).
[[suspension_tests]]
name = "left"
mass = "5.67 kg"
frequency_hz = 0.280
damping_ratio = 0.047

[[suspension_tests]]
name = "right"
mass = "5.67 kg"
frequency_hz = 0.283
damping_ratio = 0.067
'''

CONFIGURATION = '''
# A test configuration: starts from the model's configuration `from` (its suspension, boundary
# conditions and load factor) and changes what is given here. role = "update" (the model is
# updated against its data) or "check" (only compared: an unseen configuration).
[[configurations]]
name = "{name}"
from = "{source}"
role = "update"
# gravity = 1.0            # load factor on gravity
# fixed = {{ "12" = "123" }} # node id -> constrained components (a shaker stinger: translations)
# [[configurations.masses]] # extra masses of this test only (adapters, clips)
# node = 12
# mass = "15 g"
# name = "clip"            # how a mass variable (kind = "mass", configurations = [...]) names it
# [configurations.shaker]  # a shaker on a stinger: its moving mass, and what the stinger holds
# node = 12
# mass = "150 g"
# fixed = "123"            # a stiff stinger on the X-HALE held the translations (and removed plunge)
# [[configurations.forces]] # a test load (fixed direction, scaled with the load factor)
# node = 12
# force = [0.0, 0.0, "-5 N"]
{cords}
[configurations.test]
{data}
points = "case"            # test point -> FE node: "case" (the built-in case's sensors, point k = sensor k),
                           # "nodes" (point id = node id) or a CSV file point,node,dx,dy,dz [m]
band_hz = [0.1, 11.5]      # identification band
max_order = 60             # highest PolyMAX model order of the stabilisation diagram
# refine = true            # maximum-likelihood refinement with frequency/damping uncertainties
# select_hz = [0.96, 2.7]  # pick poles near these frequencies instead of the automatic selection
# use_modes = [2, 3, 4]    # keep only these identified modes (1-based)
'''

CORD = '''[[configurations.cords]]    # replaces the configuration's suspension when given
node = {node}
anchor = [{ax:.4f}, {ay:.4f}, {az:.4f}]   # fixed end of the line below the pulley [m]
block_test = "{block}"      # stiffness and damping from that block test (or stiffness =, damping =)
carries = "{carries:.3f} kg"  # unstretched length sized to carry this mass (or unstretched_length =)
'''

TAIL = '''
# Design variables: a property of model entities, normalised by its initial value (x = 1),
# bounded. kind = beam (E, G, rho or a section attribute of beam groups named by targets, which
# may be patterns like "wing_*"), mass (mass, offset_x/y/z of masses named by targets or with
# ids = [...]), spring (k1..k6, c1..c6 of springs named by targets or ids) or cord. Default bounds:
# [0.9, 1.1] (beam, mass), [0.5, 2.0] (spring), [0.8, 1.2] (cord).
{variables}
[objective]                # weights of the residual groups (each residual a relative error)
frequency = 1.0
mac = 0.0                  # weight of 1 - MAC of the paired modes
mac_floor = 0.5            # pairs below this MAC are not paired
# mac_min = 0.8            # constraint (slsqp, trust-constr) or penalty (least squares)
# mass_limits = 0.1        # mass properties within +-10 %
# [objective.measured_mass]
# mass = "11.35 kg"

[optimiser]
method = "least_squares"   # least_squares (Levenberg-Marquardt, then bounded), dogbox, trf, slsqp,
                           # trust-constr, nelder-mead
starts = 1                 # multi-start
max_iterations = 100       # function evaluations (the default)
tolerance = 1e-4           # relative, on the cost, step and gradient (default 1e-10): 1e-4 is a 0.01 % step
max_relative_std = 0.1     # variables the data know to no better than +-10 % are held (default 0.5)

[prediction]               # suspension removed: free-free modes, and proposed suspensions
free_free = true
proposed = [{proposed}]
n_modes = 10
{reference}
# [plan]                   # pre-test planning, `flexgvt plan project.toml` (no test data needed yet)
# stations = [[12, 30]]    # candidate suspension stations: the nodes hung at once
# stiffness = ["5 N/m", "18 N/m"]   # line rates tried at every station
# length = ["2 m", "20 m"] # cord lengths (anchor above each attachment)
# n_modes = 8              # elastic target modes (band_hz = [0.5, 10] to pick them by frequency)
# sensors = 12             # sensors placed by effective independence
# directions = "Z"         # sensor directions tried at every node (sensor_nodes = [...] to restrict)
# exciters = 3             # driving points listed, best first

[outputs]
directory = "results"      # report.html, updated.bdf, modes as UFF 55, CSV tables, the results store
# allow_outside = false    # true lets `directory` point outside this project's folder ("../x", "/data/...")
report = true
bdf = true
uff = true

# Staged updating (docs/workflow.md, "Stages"): without [[stages]] every configuration with role "update"
# is updated on at once with every [[variables]]. With them, the stages run in order, each from the model
# the previous one produced (bounds about the values it starts from; recentre = false: about this model).
# Every configuration with role "update" must be named by a stage. For example (your names):
# [[stages]]
# name = "components"      # component tests: fixed inputs (set) and/or weights (objective.measured_mass)
# set = {{ E = "4.3 GPa" }}  # a variable's targets set to this value (a tip-load modulus, a density)
# [[stages]]
# name = "GVT"
# configurations = ["outboard"]      # names of [[configurations]] (or its own [[stages.configurations]])
# variables = ["E"]                  # names of [[variables]] (or its own [[stages.variables]])
# bounds = {{ E = [0.8, 1.2] }}        # this stage's bounds
# [stages.optimiser]                 # this stage's [optimiser] (and [stages.objective]) keys
# max_iterations = 60
'''


def _toml_list(items) -> str:
    return ", ".join(json.dumps(i) for i in items)


def _toml_value(value) -> str:
    """A TOML value: booleans, numbers, strings, lists and tables (inline)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, (int, float)):
        return repr(value)
    return json.dumps(str(value))


def variable_blocks(rows) -> str:
    """[[variables]] tables of a project file, one per (name, kind, targets, attribute, bounds) row."""
    return "".join(f'[[variables]]\nname = "{name}"\nkind = "{kind}"\ntargets = [{_toml_list(targets)}]\n'
                   f'attribute = "{attribute}"\nbounds = [{bounds[0]}, {bounds[1]}]\n\n'
                   for name, kind, targets, attribute, bounds in rows)


def example_project(case_name: str = "xhale", data: dict[str, str] | None = None, reference: str | None = None,
                    name: str = "X-HALE-like aircraft, lab GVT on two suspension layouts",
                    modes: dict[str, tuple[str, str, list[str]]] | None = None,
                    options: dict | None = None) -> str:
    """The commented project text for a built-in case (its configurations 'outboard' and 'inboard'
    with the block-tested suspension, the case's design variables, bungee predictions). data:
    {configuration: UFF FRF file} (default data/<name>.uff); modes: {configuration: (JSON file, key,
    labels)} of modes already identified, used instead of FRFs; options: the case's keyword
    arguments (written as [model.options]; the cords' anchors are the case's with them)."""
    from .. import cases
    options = dict(options or {})
    case = cases.get(case_name, **options)
    g = 9.80665
    text = HEADER.format(name=name, case=case_name, description="updated on both configurations at once")
    if options:
        last = ('#                          # unsupported = "warn" reads a deck holding cards flexgvt skips (and lists '
                'them)\n')
        if last not in text:
            raise ModelError("example_project: the template's [model] block changed; cannot write [model.options]")
        values = "".join(f"{k} = {_toml_value(v)}\n" for k, v in options.items())
        text = text.replace(last, last + "[model.options]\n" + values, 1)
    layouts = [c for c in ("outboard", "inboard") if c in case.configurations]
    for c in layouts:
        cfg = case.configurations[c]
        cords = ""
        for cord, block in zip(cfg.suspension, ("left", "right")):
            carries = cord.stiffness * (np.linalg.norm(np.asarray(cord.anchor) - case.model.xyz[
                case.model.index_of([cord.node])[0]] - np.asarray(cord.offset)) - cord.unstretched_length) / g
            cords += CORD.format(node=cord.node, ax=cord.anchor[0], ay=cord.anchor[1], az=cord.anchor[2],
                                 block=block, carries=carries)
        if modes and c in modes:
            file, key, labels = modes[c]
            test = (f'modes = "{file}"   # modes already identified (UFF 55, .csv or .json)\n'
                    f'key = "{key}"              # the object holding them in the JSON file\n'
                    f'labels = [{_toml_list(labels)}]')
        else:
            file = (data or {}).get(c, f"data/{c}.uff")
            test = (f'frfs = "{file}"          # UFF 58 FRFs to identify (PolyMAX); or '
                    'modes = "modes.uff" / .csv / .json (already identified)')
        text += CONFIGURATION.format(name=c, source=c, cords=cords, data=test)
    variables = variable_blocks(case.references.get("design_variables", []))
    proposed = [c for c in ("bungee_outboard", "bungee_inboard") if c in case.configurations]
    ref = (f'reference = "{reference}"      # known free-free frequencies to score the prediction against\n'
           if reference else '# reference = "reference.json"  # known free-free frequencies to score against\n')
    return text + TAIL.format(variables=variables, proposed=_toml_list(proposed), reference=ref)


def write_example(folder: Path, seed: int = 7, progress: Callable[[str], None] = lambda s: None,
                  snr_db: float = 30.0, *, log: Callable[[str], None] | None = None) -> list[Path]:
    """Synthetic GVT of the X-HALE-like 'as-built' airframe in both suspension layouts (two
    references, noise), the as-built free-free frequencies as reference.json, and the project.
    progress: receives one line per file written (``log``: its deprecated name)."""
    from ..updating.settings import renamed
    if log is not None:
        renamed("write_example(log=...)", "write_example(progress=...)")
        progress = log
    log = progress
    from .. import cases
    from ..fem import solve_modes, solve_static
    from ..io.uff import TestGeometry, write_uff
    from ..model import Configuration
    from .synthetic import synthetic_gvt

    folder = Path(folder)
    (folder / "data").mkdir(parents=True, exist_ok=True)
    truth = cases.xhale(as_built=True, seed=seed)
    refs = driving_points(truth.model, truth.sensors)
    files, data = [], {}
    for c in ("outboard", "inboard"):
        gvt = synthetic_gvt(truth.model, truth.configurations[c], truth.sensors, refs, f_max_hz=12.0, snr_db=snr_db,
                            seed=seed)
        pts = np.array(sorted(gvt.point_xyz))
        path = write_uff(folder / "data" / f"{c}.uff", frfs=gvt.frfs,
                         geometry=TestGeometry(pts, np.array([gvt.point_xyz[p] for p in pts])))
        files.append(path)
        data[c] = f"data/{c}.uff"
        log(f"synthetic GVT '{c}': {gvt.frfs.H.shape[1]} channels x {gvt.frfs.H.shape[2]} references, "
            f"{len(gvt.frfs.frequencies_hz)} lines, {snr_db:g} dB")
    free = solve_modes(solve_static(truth.model, Configuration("free_free")), 16, damped=False)
    elastic = np.flatnonzero(free.frequencies_hz > 0)[:10]
    ref = {"about": "free-free modes of the as-built airframe (the truth the prediction is scored against)",
           "free_free": {"frequencies_hz": free.frequencies_hz[elastic].tolist(),
                         "labels": [free.labels[k] for k in elastic]}}
    (folder / "reference.json").write_text(json.dumps(ref, indent=1))
    files.append(folder / "reference.json")
    (folder / "project.toml").write_text(example_project("xhale", data, "reference.json"))
    files.append(folder / "project.toml")
    return files


def driving_points(model, sensors: dict) -> list[str]:
    """Two references that drive bending and torsion of both wings: the vertical sensor farthest
    outboard on the right near the leading edge, and the vertical one nearest mid-semi-span on the
    left near the trailing edge."""
    rows = []
    for name, (node, offset, d) in sensors.items():
        if abs(np.asarray(d, float)[2]) > 0.99:
            xyz = model.xyz[model.index_of([node])[0]] + np.asarray(offset, float)
            rows.append((name, xyz))
    if len(rows) < 2:
        return list(sensors)[:2]
    span = max(abs(x[1]) for _, x in rows)
    first = max(rows, key=lambda r: (round(r[1][1], 3), -r[1][0]))[0]
    second = min(rows, key=lambda r: (abs(r[1][1] + span / 2), -r[1][0]))[0]
    return [first, second]


def write_modes_example(folder: Path, seed: int = 7) -> list[Path]:
    """Modes already identified, beside a `write_example` project: the as-built airframe's modes at the
    case's test points (first 12 of each layout, shapes from the node translations) as
    modes/outboard.json (the {"key", "data"} layout `flexgvt run` caches), modes/inboard.csv,
    modes/outboard.uff (UFF 55 with geometry) and modes/points.csv (point,node,dx,dy,dz [m]), for
    projects with ``modes = ...`` test data (examples, robustness tests)."""
    from .. import cases
    from ..fem import solve_modes, solve_static
    from ..io.uff import ModalResults, TestGeometry, write_uff
    from .project import case_points

    folder = Path(folder)
    (folder / "modes").mkdir(parents=True, exist_ok=True)
    truth = cases.xhale(as_built=True, seed=seed)
    node_map, offsets = case_points(truth)
    points = np.array(sorted(node_map))
    rows = truth.model.index_of([node_map[p] for p in points])
    files = []
    for c in ("outboard", "inboard"):
        m = solve_modes(solve_static(truth.model, truth.configurations[c]), 12, damped=False)
        shapes = m.shapes[:, rows, :3]  # (modes, points, 3)
        outputs = [[int(p), d + 1] for p in points for d in range(3)]
        flat = shapes.reshape(len(shapes), -1)
        damping = np.full(len(shapes), 0.02)
        if c == "outboard":
            data = {"configuration": c, "source": "synthetic", "frequencies_hz": m.frequencies_hz.tolist(),
                    "damping_ratio": damping.tolist(), "labels": list(m.labels), "outputs": outputs,
                    "shapes_real": flat.tolist(), "shapes_imag": np.zeros_like(flat).tolist()}
            files.append(folder / "modes" / "outboard.json")
            files[-1].write_text(json.dumps({"key": "synthetic", "data": data}))
            xyz = truth.model.xyz[rows] + np.array([offsets[p] for p in points])
            files.append(write_uff(folder / "modes" / "outboard.uff", geometry=TestGeometry(points, xyz),
                                   modes=ModalResults(m.frequencies_hz, damping, shapes, points)))
        else:
            head = ["mode", "frequency_hz", "damping_ratio", "label"] + [f"{p}+{'XYZ'[d - 1]}" for p, d in outputs]
            lines = [",".join(head)] + [",".join([str(k + 1), f"{f:.8g}", "0.02", m.labels[k]] +
                                                 [f"{v:.6g}" for v in flat[k]])
                                        for k, f in enumerate(m.frequencies_hz)]
            files.append(folder / "modes" / "inboard.csv")
            files[-1].write_text("\n".join(lines) + "\n")
    lines = ["point,node,dx,dy,dz"] + [f"{p},{node_map[p]},{offsets[p][0]:.6g},{offsets[p][1]:.6g},{offsets[p][2]:.6g}"
                                       for p in points]
    files.append(folder / "modes" / "points.csv")
    files[-1].write_text("\n".join(lines) + "\n")
    return files
