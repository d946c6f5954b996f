"""The wingbox (fg.cases.wingbox) in flexgvt and in CalculiX S8R on the same plates, for
tests/fem/test_wingbox_calculix.py, bench/bench_wingbox.py and the stored references in tests/data.

    python bench/ccx_wingbox.py reference --sizes 0.25 --configurations minus_1g --json runs.json
    python bench/ccx_wingbox.py store runs.json bench_wingbox.json --json tests/data/wingbox_ccx.json

(store: the mesh sequence of every run given, and each configuration's finest run as its reference.)

The loaded configurations are post-buckled (the compressed skin wrinkles below 1 g), so both
solvers get the same stress-free geometry: the compressed skin (bottom at -1 g, top at 2.5 g and
in the combined case) offset along z by w0 = a sin(pi x / chord) sin(pi y / rib pitch), a = 0.8 mm
(a tenth of the skin: flexgvt's default imperfection size), one half-wave per bay across the chord and along the span
with the sign alternating from bay to bay (the continuous plate's buckling mode over ribs that
hold it out of plane), outward in the root bay. The function of position, not a mesh's buckling
shape, so every mesh of either solver carries the same imperfection.

Mode shapes are compared at points every mesh has: the box's four corners and the skins' mid-chord
at every rib station (translations). Global modes are those whose kinetic energy is mostly rigid
cross-section motion (fem.labels.section_fractions, local fraction below one half); the rest are
local skin modes.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from ccx_driver import Frequency, Static, run_ccx, s8r_deck, version  # noqa: E402

import flexgvt as fg  # noqa: E402
from flexgvt.cases.wingbox import CHORD, COMBINED_GRAVITY, DEPTH, SKIN, SPAN  # noqa: E402
from flexgvt.fem.labels import section_fractions  # noqa: E402

AMPLITUDE = 0.1 * SKIN  # [m]
GRAVITY = {"unloaded": None, "minus_1g": (0.0, 0.0, -1.0), "plus_2_5g": (0.0, 0.0, 2.5),
           "combined": COMBINED_GRAVITY}
COMPRESSED = {"minus_1g": -1.0, "plus_2_5g": 1.0, "combined": 1.0}  # z side of the compressed skin
CLASSES = ("OOP", "IP", "T", "EXT", "LOCAL")


def imperfection(name: str, amplitude: float = AMPLITUDE, rib_pitch: float = 0.5):
    """offsets(xyz (n, 3)) -> (n, 3) [m] of configuration ``name``'s compressed skin (None unloaded)."""
    if name not in COMPRESSED:
        return None
    side = COMPRESSED[name]

    def offsets(xyz):
        xyz = np.asarray(xyz, float)
        on = np.isclose(xyz[:, 2], side * DEPTH / 2, atol=1e-9)
        out = np.zeros_like(xyz)
        w = np.sin(np.pi * xyz[:, 0] / CHORD) * np.sin(np.pi * xyz[:, 1] / rib_pitch)
        out[on, 2] = side * amplitude * w[on]
        out[np.abs(out) < 1e-15] = 0.0
        return out

    return offsets


def configuration(case, name: str, amplitude: float = AMPLITUDE):
    """The case's configuration with the imperfection at the model's nodes (flexgvt)."""
    cfg = case.configurations[name]
    f = imperfection(name, amplitude)
    if f is None:
        return cfg
    d = f(case.model.xyz)
    rows = np.flatnonzero(np.any(d != 0.0, axis=1))
    return dataclasses.replace(cfg, imperfection={int(case.model.node_ids[i]): tuple(d[i]) for i in rows})


def points(model) -> tuple[np.ndarray, np.ndarray]:
    """Node ids of the comparison points (corners and skins' mid-chord at rib stations; in station
    order) and of the four tip corners."""
    xyz = model.xyz
    ids = model.node_ids
    out = []
    for y in np.arange(0.5, SPAN + 1e-9, 0.5):
        for x in (0.0, CHORD / 2, CHORD):
            for z in (-DEPTH / 2, DEPTH / 2):
                k = np.flatnonzero(np.all(np.abs(xyz - [x, y, z]) < 1e-7, axis=1))
                out.append(int(ids[k[0]]))
    out = np.array(out)
    tip = out[-6:][[0, 1, 4, 5]]
    return out, tip


def corners_every_metre(shapes) -> np.ndarray:
    """(n_modes, 64, 3) of comparison-point shapes (n_modes, 192, 3): the four corners at y = 1, 2, ... 16 m
    (what tests/data/wingbox_ccx.json stores of the reference's modes)."""
    s = np.asarray(shapes).reshape(len(shapes), 32, 6, 3)
    return s[:, 1::2][:, :, [0, 1, 4, 5]].reshape(len(shapes), 64, 3)


def node_masses(model) -> np.ndarray:
    """Translational masses [kg] at the model's nodes (each quad's mass split over its corners)."""
    pos = {int(n): k for k, n in enumerate(model.node_ids)}
    m = np.zeros(len(model.node_ids))
    for g in model.shells:
        p = g.property
        idx = np.vectorize(pos.get)(g.nodes)
        x = model.xyz[idx]
        area = 0.5 * np.linalg.norm(np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]), axis=1)
        em = area * (p.membrane.rho * p.thickness + p.nsm)
        np.add.at(m, idx.ravel(), np.repeat(em / 4, 4))
    return m


def classify(shapes: np.ndarray, xyz: np.ndarray, mass: np.ndarray) -> tuple[list[str], np.ndarray]:
    """Class (OOP, IP, T, EXT, LOCAL) of translational mode shapes (n_modes, n, 3) by their kinetic
    energy's section fractions (local when half or more is no rigid cross-section motion)."""
    phi = np.concatenate([shapes, np.zeros_like(shapes)], axis=2)
    fr = section_fractions(phi, xyz, mass)
    return [("LOCAL" if f[4] >= 0.5 else CLASSES[int(np.argmax(f[:4]))]) for f in fr], fr


def run_flexgvt(element_size: float, name: str, n_modes: int = 15, case=None) -> dict:
    """flexgvt at ``element_size``: static (with the imperfection) + n_modes; CPU and wall seconds."""
    case = case or fg.cases.wingbox(element_size=element_size)
    cfg = configuration(case, name)
    pts, tip = points(case.model)
    w0, c0 = time.perf_counter(), time.process_time()
    state = fg.solve_static(case.model, cfg)
    w1, c1 = time.perf_counter(), time.process_time()
    modes = fg.solve_modes(state, n_modes)
    w2, c2 = time.perf_counter(), time.process_time()
    rows = [state.node(int(n)) for n in pts]
    shapes = np.asarray(modes.shapes)[:, rows, :3]
    all_shapes = np.asarray(modes.shapes)[:, :, :3]
    cls, _ = classify(all_shapes, case.model.xyz, node_masses(case.model))
    return {"solver": "flexgvt", "element_size": element_size, "configuration": name,
            "nodes": int(len(case.model.node_ids)),
            "mass_kg": float(fg.mass_properties(case.model).mass),
            "tip_w_m": float(np.mean(state.displacements[[state.node(int(n)) for n in tip], 2])) if GRAVITY[name]
            else 0.0,
            "frequencies_hz": modes.frequencies_hz.tolist(), "labels": list(modes.labels), "classes": cls,
            "shapes": shapes.tolist(), "static_cpu_s": c1 - c0, "modes_cpu_s": c2 - c1,
            "static_wall_s": w1 - w0, "modes_wall_s": w2 - w1,
            "stable": state.instability is None or bool(getattr(state.instability, "recovered", False)),
            "cautions": list(state.cautions)}


def run_calculix(element_size: float, name: str, n_modes: int = 15, nice: int = 0, keep: Path | None = None,
                 case=None, first: float = 0.1, largest: float = 0.25, timeout: float | None = None) -> dict:
    """CalculiX S8R on the same plates at ``element_size`` (static NLGEOM with the imperfection, then
    PERTURBATION modes; unloaded: modes only)."""
    case = case or fg.cases.wingbox(element_size=element_size)
    model = case.model
    pts, tip = points(model)
    loads = tuple((int(f.node), d + 1, float(v)) for f in case.configurations[name].forces
                  for d, v in enumerate(tuple(f.force) + tuple(f.moment)) if v)
    steps = ([Static(GRAVITY[name], first, largest, tuple(int(n) for n in tip), loads)] if GRAVITY[name] else []) + \
        [Frequency(n_modes)]
    deck, info = s8r_deck(model, case.references["root_nodes"], steps, imperfection(name))
    r = run_ccx(deck, name, keep=keep, nice=nice, timeout=timeout, shapes_of=[int(n) for n in model.node_ids])
    return calculix_result(r, case, name, element_size, info["n_nodes"])


def calculix_result(r, case, name: str, element_size: float, n_nodes: int) -> dict:
    """run_calculix's answer from a CcxRun (ccx_driver.run_ccx or read_run)."""
    model = case.model
    pts, tip = points(model)
    corner = [int(n) for n in model.node_ids]
    shapes_all = np.array([r.shapes[n] for n in corner]).transpose(1, 0, 2)  # (modes, corners, 3)
    cls, _ = classify(shapes_all, model.xyz, node_masses(model))
    out = {"solver": "calculix", "element_size": element_size, "configuration": name,
           "nodes": n_nodes, "frequencies_hz": r.frequencies_hz.tolist(), "classes": cls,
           "shapes": np.array([r.shapes[int(n)] for n in pts]).transpose(1, 0, 2).tolist(),
           "cpu_s": r.cpu_s, "wall_s": r.wall_s, "peak_rss_mb": r.peak_rss_mb}
    if GRAVITY[name]:
        out["tip_w_m"] = float(np.mean([r.displacements[int(n)][2] for n in tip]))
        out["mass_kg"] = r.mass_kg  # the elements' (EMAS): the root's RF total of expanded shells is not the weight
    return out


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """MAC between the rows of a (n, m) and b (k, m)."""
    return (a @ b.T) ** 2 / np.outer(np.sum(a * a, axis=1), np.sum(b * b, axis=1))


def global_pairs(test: dict, reference: dict, n: int = 5, least_mac: float = 0.8) -> list[dict]:
    """The first ``n`` global modes of ``reference`` (classes not LOCAL) each paired with the test's
    mode of highest MAC at the comparison points: frequencies, difference [%], MAC, classes."""
    A = np.asarray(test["shapes"]).reshape(len(test["frequencies_hz"]), -1)
    B = np.asarray(reference["shapes"]).reshape(len(reference["frequencies_hz"]), -1)
    M = mac(B, A)
    out = []
    for k, cls in enumerate(reference["classes"]):
        if cls == "LOCAL":
            continue
        j = int(np.argmax(M[k]))
        fr, ft = reference["frequencies_hz"][k], test["frequencies_hz"][j]
        out.append({"reference_mode": k + 1, "test_mode": j + 1, "reference_hz": fr, "test_hz": ft,
                    "difference_percent": 100 * (ft / fr - 1), "mac": float(M[k, j]),
                    "reference_class": cls, "test_class": test["classes"][j], "paired": bool(M[k, j] >= least_mac)})
        if len(out) == n:
            break
    return out


_IMPERFECTION = next(p for p in __doc__.split("\n\n") if p.startswith("The loaded"))


def _head() -> dict:
    return {"ccx": version(), "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="minutes"),
            "element": "S8R (quads of fg.cases.wingbox with mid-side nodes), carried mass as the skins' density "
                       "raised by nsm / t", "imperfection": _IMPERFECTION.replace("\n", " ")}


def cmd_reference(args):
    out = {"source": "python bench/ccx_wingbox.py reference " + " ".join(sys.argv[2:]), **_head(), "runs": []}
    if args.json and Path(args.json).exists():
        out["runs"] = json.loads(Path(args.json).read_text())["runs"]
    for size in args.sizes:
        for name in args.configurations:
            r = run_calculix(size, name, args.modes, nice=args.nice,
                             keep=Path(args.keep) / f"{name}_{size:g}" if args.keep else None)
            r.pop("shapes") if args.no_shapes else None
            out["runs"] = [x for x in out["runs"] if not (x["element_size"] == size and x["configuration"] == name)]
            out["runs"].append(r)
            print(f"ccx {size} {name}: {r['cpu_s']:.0f} s CPU, tip {r.get('tip_w_m', 0):.4f}, "
                  f"f {np.round(r['frequencies_hz'][:10], 4).tolist()} {r['classes'][:10]}", flush=True)
            if args.json:
                Path(args.json).write_text(json.dumps(out, indent=1))


def cmd_store(args):
    """tests/data/wingbox_ccx.json from reference runs' JSON files: the mesh sequence and, for each
    configuration, the finest mesh's run as the reference (shapes at the corners every metre). An
    existing --json file is merged into: its configurations and meshes stay unless a run replaces them."""
    runs, head = [], _head()
    old = json.loads(Path(args.json).read_text()) if Path(args.json).exists() else {}
    for path in args.inputs:
        data = json.loads(Path(path).read_text())
        if "rows" in data:  # a bench/bench_wingbox.py result: its CalculiX runs
            data = {"source": "python bench/bench_wingbox.py", "ccx": data["ccx"], "runs": [
                r["calculix"] for r in data["rows"] if "frequencies_hz" in r.get("calculix", {})]}
        runs += data["runs"]
    sequence, reference = old.get("mesh_sequence", {}), old.get("reference", {})
    for r in sorted(runs, key=lambda r: -r["element_size"]):
        name = r["configuration"]
        keys = ("nodes", "tip_w_m", "mass_kg", "cpu_s")
        sequence.setdefault(name, {})[f"{r['element_size']:g}"] = {
            **{k: r[k] for k in keys if k in r}, "frequencies_hz": [round(f, 5) for f in r["frequencies_hz"]],
            "classes": r["classes"]}
        if name in reference and reference[name]["element_size"] < r["element_size"]:
            continue  # a finer stored reference stands
        reference[name] = {"element_size": r["element_size"], **{k: r[k] for k in ("tip_w_m", "mass_kg") if k in r},
                           "frequencies_hz": r["frequencies_hz"], "classes": r["classes"],
                           "shapes": np.round(corners_every_metre(r["shapes"]), 6).tolist()}
    out = dict(head)
    out["sources"] = old.get("sources", []) + [
        json.loads(Path(p).read_text()).get("source", f"python bench/bench_wingbox.py ({p})") for p in args.inputs]
    out["points"] = ("shapes: (modes, 64, 3) translations of the box's corners (x 0 and 1 m, z -0.08 and 0.08 m, "
                     "in that order) at y = 1, 2, ... 16 m")
    out["flexgvt_mesh"] = args.flexgvt_mesh
    masses = [r["mass_kg"] for r in runs if r.get("mass_kg") == r.get("mass_kg") and "mass_kg" in r]
    out["mass_kg"] = masses[0] if masses else None  # CalculiX's EMAS (every mesh: the same plates)
    out["mesh_sequence"], out["reference"] = sequence, reference
    Path(args.json).write_text(json.dumps(out, indent=0))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command", choices=("reference", "store"))
    parser.add_argument("inputs", nargs="*", help="store: the reference runs' JSON files")
    parser.add_argument("--flexgvt-mesh", type=float, default=0.1, help="store: flexgvt's converged-enough mesh")
    parser.add_argument("--sizes", type=float, nargs="+", default=[0.25])
    parser.add_argument("--configurations", nargs="+", default=list(GRAVITY))
    parser.add_argument("--modes", type=int, default=15)
    parser.add_argument("--nice", type=int, default=10)
    parser.add_argument("--no-shapes", action="store_true")
    parser.add_argument("--json")
    parser.add_argument("--keep", help="folder to keep CalculiX's files in")
    args = parser.parse_args()
    {"reference": cmd_reference, "store": cmd_store}[args.command](args)


if __name__ == "__main__":
    main()
