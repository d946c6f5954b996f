"""Continuum reference for the mass-frame question (issue 23): the cantilever strip of docs/method.md
case 3 (1.5 m x 50 mm x 3 mm aluminium) as CalculiX S8R shells (or C3D20R bricks with --bricks N
layers), unloaded and after a geometrically nonlinear -1 g step (and a 3 g one: three times the
self-weight along -z, fg.cases.cantilever_strip's flatwise_3g), and the ratios f(-1 g) / f(unloaded)
of the mode each -1 g mode grows from (paired by MAC of the mid-surface displacements).

    python bench/calculix_strip.py --chord 8 --span 300 --json tests/data/mass_frame/ccx_s8r_8x300.json

Needs `ccx` (Debian: apt-get install calculix-ccx). tests/fem/test_mass_frame.py runs a coarse mesh
when it is installed.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from ccx_driver import read_frd_displacements, read_frequencies  # noqa: E402

L, B, T = 1.5, 0.05, 0.003
E, NU, RHO = 70e9, 0.33, 2700.0
CASES = {"unloaded": 0.0, "minus_1g": 1.0, "minus_3g": 3.0}  # gravity along -z [g]


def mesh(n_chord: int, n_span: int):
    """S8R mesh of the strip in the x-y plane (chord x, span y): node ids, coordinates, elements."""
    ids, xyz = {}, []
    for j in range(2 * n_span + 1):
        for i in range(2 * n_chord + 1):
            if i % 2 and j % 2:  # S8R has no centre node
                continue
            ids[i, j] = len(xyz) + 1
            xyz.append((-B / 2 + B * i / (2 * n_chord), L * j / (2 * n_span), 0.0))
    elements = []
    for j in range(n_span):
        for i in range(n_chord):
            a, b = 2 * i, 2 * j
            corners = [ids[a, b], ids[a + 2, b], ids[a + 2, b + 2], ids[a, b + 2]]
            mids = [ids[a + 1, b], ids[a + 2, b + 1], ids[a + 1, b + 2], ids[a, b + 1]]
            elements.append(corners + mids)
    return ids, np.array(xyz), elements


def brick_mesh(n_chord: int, n_span: int, n_thick: int):
    """C3D20R mesh of the strip (chord x, span y, thickness z): node ids, coordinates, elements, root nodes."""
    ids, xyz = {}, []
    for k in range(2 * n_thick + 1):
        for j in range(2 * n_span + 1):
            for i in range(2 * n_chord + 1):
                if (i % 2) + (j % 2) + (k % 2) > 1:  # 20-node bricks: no face or body centres
                    continue
                ids[i, j, k] = len(xyz) + 1
                xyz.append((-B / 2 + B * i / (2 * n_chord), L * j / (2 * n_span), -T / 2 + T * k / (2 * n_thick)))
    elements = []
    for k in range(n_thick):
        for j in range(n_span):
            for i in range(n_chord):
                a, b, c = 2 * i, 2 * j, 2 * k
                n = lambda di, dj, dk: ids[a + di, b + dj, c + dk]  # noqa: E731
                elements.append([n(0, 0, 0), n(2, 0, 0), n(2, 2, 0), n(0, 2, 0), n(0, 0, 2), n(2, 0, 2), n(2, 2, 2),
                                 n(0, 2, 2), n(1, 0, 0), n(2, 1, 0), n(1, 2, 0), n(0, 1, 0), n(1, 0, 2), n(2, 1, 2),
                                 n(1, 2, 2), n(0, 1, 2), n(0, 0, 1), n(2, 0, 1), n(2, 2, 1), n(0, 2, 1)])
    root = [v for (i, j, k), v in ids.items() if j == 0]
    return np.array(xyz), elements, root


def write_input(path: Path, n_chord: int, n_span: int, n_modes: int, gravity: float, bricks: int = 0) -> np.ndarray:
    """A CalculiX input: S8R shells (bricks=0) or C3D20R bricks with ``bricks`` layers through the
    thickness, with an NLGEOM static step under ``gravity`` g along -z first when it is not 0."""
    if bricks:
        xyz, elements, root = brick_mesh(n_chord, n_span, bricks)
        kind, section, fix = "C3D20R", ["*SOLID SECTION, ELSET=EALL, MATERIAL=AL"], "ROOT, 1, 3"
    else:
        ids, xyz, elements = mesh(n_chord, n_span)
        root = [n for (i, j), n in ids.items() if j == 0]
        kind, section, fix = "S8R", ["*SHELL SECTION, ELSET=EALL, MATERIAL=AL", f"{T}"], "ROOT, 1, 6"
    lines = ["*NODE"] + [f"{k + 1}, {x:.10g}, {y:.10g}, {z:.10g}" for k, (x, y, z) in enumerate(xyz)]
    lines += [f"*ELEMENT, TYPE={kind}, ELSET=EALL"]
    for e, el in enumerate(elements):  # at most 16 entries per line
        items = [str(e + 1)] + [str(v) for v in el]
        lines += ([", ".join(items[:16]) + ("," if len(items) > 16 else "")]
                  + ([", ".join(items[16:])] if len(items) > 16 else []))
    lines += ["*NSET, NSET=ROOT"] + [", ".join(map(str, root[k:k + 12])) for k in range(0, len(root), 12)]
    lines += ["*MATERIAL, NAME=AL", "*ELASTIC", f"{E:.6g}, {NU}", "*DENSITY", f"{RHO}"] + section + ["*BOUNDARY", fix]
    if gravity:
        lines += ["*STEP, NLGEOM, INC=200", "*STATIC", "0.05, 1.0, 1e-5, 0.1", "*DLOAD",
                  f"EALL, GRAV, {9.80665 * gravity:.10g}, 0., 0., -1.",
                  "*NODE FILE", "U", "*END STEP", "*STEP, PERTURBATION"]
    else:
        lines += ["*STEP"]
    lines += ["*FREQUENCY", f"{n_modes}", "*NODE FILE", "U", "*END STEP"]
    path.write_text("\n".join(lines) + "\n")
    return xyz


def read_mode_shapes(frd: Path, n_modes: int) -> np.ndarray:
    """(n_modes, n_points, 3) displacements of the last n_modes DISP blocks of a .frd file, at every
    node CalculiX writes (the shell's expanded nodes, numbered the same in both runs)."""
    blocks = read_frd_displacements(frd)[-n_modes:]
    return np.array([[b[n] for n in sorted(b)] for b in blocks])


def run(n_chord: int, n_span: int, n_modes: int = 15, keep: Path | None = None, bricks: int = 0,
        cases: tuple[str, ...] = ("unloaded", "minus_1g")) -> dict:
    """CalculiX's frequencies for ``cases`` (keys of CASES; 'unloaded' and 'minus_1g' are needed for
    the ratios) and the ratios f(-1 g) / f(unloaded)."""
    if shutil.which("ccx") is None:
        raise RuntimeError("CalculiX (ccx) is not installed: apt-get install calculix-ccx")
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(keep or tmp)
        work.mkdir(parents=True, exist_ok=True)
        for name in cases:
            write_input(work / f"{name}.inp", n_chord, n_span, n_modes, CASES[name], bricks)
            t0 = time.perf_counter()
            subprocess.run(["ccx", name], cwd=work, check=True, capture_output=True, text=True,
                           env={"OMP_NUM_THREADS": "2", "PATH": "/usr/bin:/bin"})
            out[name] = {"frequencies_hz": read_frequencies(work / f"{name}.dat"),
                         "shapes": read_mode_shapes(work / f"{name}.frd", n_modes),
                         "seconds": time.perf_counter() - t0}
    u, g = out["unloaded"], out["minus_1g"]
    A = u["shapes"].reshape(n_modes, -1)
    Bm = g["shapes"].reshape(n_modes, -1)
    mac = (A @ Bm.T) ** 2 / np.outer(np.sum(A * A, axis=1), np.sum(Bm * Bm, axis=1))
    origin = np.argmax(mac, axis=0)  # the unloaded mode each -1 g mode resembles most
    ratios = {int(k + 1): {"from_unloaded_mode": int(origin[k] + 1), "mac": float(mac[origin[k], k]),
                           "ratio": float(g["frequencies_hz"][k] / u["frequencies_hz"][origin[k]])}
              for k in range(n_modes)}
    return {"mesh": f"C3D20R {n_chord} x {n_span} x {bricks}" if bricks else f"S8R {n_chord} x {n_span}",
            **{f"{name}_hz": out[name]["frequencies_hz"].tolist() for name in cases}, "ratios": ratios,
            "seconds": {name: out[name]["seconds"] for name in cases}}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--chord", type=int, default=8)
    parser.add_argument("--span", type=int, default=300)
    parser.add_argument("--modes", type=int, default=15)
    parser.add_argument("--bricks", type=int, default=0, help="C3D20R bricks with this many layers through the "
                        "thickness instead of S8R shells")
    parser.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES),
                        help="load cases (unloaded and minus_1g are always run: the ratios need them)")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    cases = tuple(dict.fromkeys(["unloaded", "minus_1g", *args.cases]))
    result = run(args.chord, args.span, args.modes, bricks=args.bricks, cases=cases)
    for k, r in result["ratios"].items():
        print(f"-1 g mode {k:2d}: {result['minus_1g_hz'][k - 1]:9.3f} Hz, "
              f"from unloaded mode {r['from_unloaded_mode']:2d} "
              f"(MAC {r['mac']:.3f}), ratio {r['ratio']:.4f}")
    for name in cases[2:]:
        print(f"{name}: " + ", ".join(f"{f:.3f}" for f in result[f"{name}_hz"]) + " Hz")
    print(f"CalculiX time: {result['seconds']}")
    if args.json:
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
