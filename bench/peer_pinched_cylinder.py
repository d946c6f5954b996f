"""Independent solver on Sze, Liu & Lo's (2004) pinched cylinder with snap-through (their 3.6):
OpenSees ASDShellQ4 (corotational, MITC-type shear, EAS membrane, Hughes-Brezzi drilling) on the
very eighth that tests/fem/test_sze_benchmarks.py's pinched_cylinder() builds for flexgvt, followed
past the snap by displacement control at the load point. Prints -W_A and U_B at the table's load
levels against the paper's S4R 48 x 48 table.

    python bench/peer_pinched_cylinder.py --mesh 48 [--step 1.0] [--json out.json]

Needs openseespy (pip install openseespy; its Linux wheel needs Debian's libblas3 liblapack3), in a
separate venv, e.g. /work/venv-peer/bin/python bench/peer_pinched_cylinder.py --mesh 48. Without it
the script says so and exits 0. When flexgvt is importable too, the peer's nodes, elements,
supports and load are first checked equal to flexgvt's model. The paths measured on 2026-11-27
(32 x 32 and 48 x 48, about 1 h wall each on the shared machine; docs/shells.md, "Pinched cylinder
against an independent solver") are in bench/peer_pinched_cylinder_opensees.json.
"""

from __future__ import annotations

import argparse
import ast
import json
import sys
import time
from pathlib import Path

import numpy as np

R, L, T, E, NU = 100.0, 200.0, 1.0, 30e3, 0.3
P_EIGHTH = 3e3  # a quarter of one of the two 12,000 pinching forces
TESTS = Path(__file__).resolve().parents[1] / "tests" / "fem"


def table() -> np.ndarray:
    """The paper's table (P/Pmax, -W_A, U_B) as tests/fem/test_sze_benchmarks.py holds it (read
    from its source, so this script needs no flexgvt)."""
    src = (TESTS / "test_sze_benchmarks.py").read_text()
    for node in ast.parse(src).body:
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") == "PINCHED":
            return np.array(ast.literal_eval(node.value.args[0]))
    raise SystemExit("PINCHED table not found in tests/fem/test_sze_benchmarks.py")


def mesh(n: int):
    """The eighth (axis y, 0 <= y <= L/2, 0 <= theta <= 90 deg from x towards z), node numbering,
    quads and supports exactly as _cylinder_eighth / pinched_cylinder: (xyz, ids, quads, fixed)."""
    y, th = np.linspace(0, L / 2, n + 1), np.linspace(0, np.pi / 2, n + 1)
    TH, Y = np.meshgrid(th, y)
    ids = np.arange(1, TH.size + 1).reshape(TH.shape)
    xyz = np.c_[(R * np.cos(TH)).ravel(), Y.ravel(), (R * np.sin(TH)).ravel()]
    quads = np.array([[ids[j, i], ids[j + 1, i], ids[j + 1, i + 1], ids[j, i + 1]]
                      for j in range(n) for i in range(n)])
    fixed: dict[int, set[int]] = {}
    # z = 0 plane: uz, rx, ry; x = 0 plane: ux, ry, rz; mid-length y = L/2: uy, rx, rz;
    # rigid diaphragm at the end y = 0: ux, uz (radial and tangential), axial and rotations free
    for nodes, dofs in ((ids[:, 0], (3, 4, 5)), (ids[:, -1], (1, 5, 6)), (ids[-1], (2, 4, 6)),
                        (ids[0], (1, 3))):
        for k in nodes:
            fixed.setdefault(int(k), set()).update(dofs)
    return xyz, ids, quads, fixed


def same_as_flexgvt(n: int) -> str:
    """Compare with flexgvt's own model when flexgvt imports; returns a line saying what was checked."""
    try:
        sys.path.insert(0, str(TESTS))
        import test_sze_benchmarks as sze
    except ImportError:
        return "flexgvt not importable here: model not cross-checked"
    xyz, ids, quads, fixed = mesh(n)
    model, config, points = sze.pinched_cylinder(n, n)
    assert np.allclose(model.xyz, xyz, atol=1e-12)
    assert np.array_equal(np.asarray(model.node_ids), ids.ravel())
    (group,) = model.shells
    prop = group.property
    assert np.array_equal(group.nodes, quads), "elements differ"
    assert (prop.thickness, prop.membrane.E, prop.membrane.nu, prop.shear_ratio) == (T, E, NU, 5 / 6)
    fg_fixed = {int(k): {int(c) for c in v} for k, v in config.fixed.items()}
    assert fg_fixed == fixed, "supports differ"
    assert [(f.node, tuple(f.force)) for f in config.forces] == [(int(ids[-1, -1]), (0, 0, -P_EIGHTH))]
    assert points == {"A": int(ids[-1, -1]), "B": int(ids[-1, 0])}
    return "nodes, quads, section, supports, load and points equal flexgvt's pinched_cylinder()"


def solve(n: int, step: float, max_w: float, time_cap: float, tol: float = 1e-4,
          partial: Path | None = None):
    """Displacement control of the load point's inward motion in steps of `step` [length] up to
    `max_w`, Newton to a displacement correction of `tol` [length], recording (lambda, -W_A, U_B)
    after each step (and writing the path so far to `partial`, if given, as JSON). Returns (path
    array, wall seconds)."""
    import openseespy.opensees as ops

    xyz, ids, quads, fixed = mesh(n)
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for k, p in zip(ids.ravel(), xyz):
        ops.node(int(k), *map(float, p))
    for k, dofs in fixed.items():
        ops.fix(k, *[int(d in dofs) for d in range(1, 7)])
    ops.section("ElasticMembranePlateSection", 1, E, NU, T, 0.0)
    for e, q in enumerate(quads, 1):
        ops.element("ASDShellQ4", e, *map(int, q), 1, "-corotational")
    A, B = int(ids[-1, -1]), int(ids[-1, 0])
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(A, 0.0, 0.0, -P_EIGHTH, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", tol, 60, 0)
    ops.algorithm("KrylovNewton")
    ops.analysis("Static")
    path = [(0.0, 0.0, 0.0)]
    # control the load point's inward motion; where it stalls (a fold of lambda and W_A both),
    # control U_B's outward motion until W_A has passed the stall by a step, then A again
    control, w_stall = (A, 3, -1.0), None
    t0, h = time.perf_counter(), step
    while path[-1][1] < max_w and time.perf_counter() - t0 < time_cap:
        ops.integrator("DisplacementControl", *control[:2], control[2] * h)
        if ops.analyze(1) != 0:  # OpenSees reverts to the last committed state itself
            if h >= step / 64:
                h /= 2
            elif control[0] == A:
                control, w_stall, h = (B, 1, 1.0), path[-1][1], step / 4
                print(f"  load point stalled at -W_A {w_stall:.3f}: controlling U_B", flush=True)
            else:
                print(f"  U_B control stalled too at -W_A {path[-1][1]:.3f}, U_B {path[-1][2]:.3f}")
                break
            continue
        path.append((ops.getLoadFactor(1), -ops.nodeDisp(A, 3), ops.nodeDisp(B, 1)))
        h = min(step, 1.5 * h)
        if partial is not None:
            partial.write_text(json.dumps({"mesh": n, "partial": True, "path": path}))
        if control[0] == B and path[-1][1] > w_stall + step:
            control = (A, 3, -1.0)
            print(f"  back to the load point at -W_A {path[-1][1]:.3f}", flush=True)
        if len(path) % 20 == 0:
            print(f"  step {len(path) - 1}: lambda {path[-1][0]:.4f}, -W_A {path[-1][1]:.3f}, U_B {path[-1][2]:.3f}, "
                  f"{time.perf_counter() - t0:.0f} s", flush=True)
    ops.wipe()
    return np.array(path), time.perf_counter() - t0


def at_levels(path: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """(-W_A, U_B) where lambda first rises through each level along the path (flexgvt's rule for
    arc-length levels): lambda, -W_A and U_B as cubics in the path's length in (-W_A, U_B) through
    the four recorded points around the crossing; NaN where the path never reaches the level."""
    lam = path[:, 0]
    arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(path[:, 1:], axis=0).T))]
    out = np.full((len(levels), 2), np.nan)
    for i, lv in enumerate(levels):
        up = np.flatnonzero((lam[:-1] < lv) & (lam[1:] >= lv))
        if not len(up):
            continue
        k = up[0]
        sl = slice(max(k - 1, 0), min(k + 3, len(path)))
        deg = len(arc[sl]) - 1
        roots = np.roots(np.polyfit(arc[sl], lam[sl] - lv, deg))
        roots = roots[np.isreal(roots)].real
        roots = roots[(roots >= arc[k] - 1e-9) & (roots <= arc[k + 1] + 1e-9)]
        a = roots.min() if len(roots) else np.interp(lv, lam[k:k + 2], arc[k:k + 2])
        out[i] = [np.polyval(np.polyfit(arc[sl], path[sl, c], deg), a) for c in (1, 2)]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", type=int, default=48, help="elements along each side of the eighth")
    ap.add_argument("--step", type=float, default=1.0, help="load-point displacement per step")
    ap.add_argument("--max-w", type=float, default=86.0, help="stop at this -W_A (the table ends at 83.1)")
    ap.add_argument("--time-cap", type=float, default=7200.0, help="wall seconds before giving up")
    ap.add_argument("--tol", type=float, default=1e-4, help="Newton's displacement-correction norm")
    ap.add_argument("--json", type=Path, help="write the path and the levels here")
    args = ap.parse_args()
    try:
        import openseespy.opensees  # noqa: F401
    except ImportError as exc:
        print(f"skipped: openseespy is not installed in this Python ({exc}); "
              "pip install openseespy in a separate venv and run the script with its python")
        return
    print(same_as_flexgvt(args.mesh))
    tab = table()
    path, wall = solve(args.mesh, args.step, args.max_w, args.time_cap, args.tol, args.json)
    lam = path[:, 0]
    falls = np.flatnonzero(np.diff(lam) < 0)
    print(f"\nOpenSees ASDShellQ4 corotational, {args.mesh} x {args.mesh} eighth, displacement control "
          f"(step {args.step}): {len(path) - 1} steps, {wall:.1f} s wall")
    if len(falls):
        k = falls[0]
        print(f"  lambda falls first after {lam[k]:.4f} (-W_A {path[k, 1]:.3f}); lowest after it "
              f"{lam[k:].min() if len(lam[k:]) else lam[k]:.4f}")
    else:
        print("  lambda rises monotonically along the path (no limit point)")
    got = at_levels(path, tab[:, 0])
    ref = tab[:, 1:]
    err = (got - ref) / np.maximum(np.abs(ref), 0.02 * np.abs(ref).max(axis=0))
    print("  P/Pmax     -W_A      ref  err %       U_B      ref  err %")
    for lv, g, r, e in zip(tab[:, 0], got, ref, err):
        if np.isnan(g[0]):
            print(f"  {lv:6.3f} not reached")
            continue
        print(f"  {lv:6.3f} {g[0]:8.3f} {r[0]:8.3f} {100 * e[0]:+6.2f}  {g[1]:8.3f} {r[1]:8.3f} {100 * e[1]:+6.2f}")
    if args.json:
        args.json.write_text(json.dumps({"mesh": args.mesh, "step": args.step, "wall_s": wall,
                                         "path": path.tolist(), "levels": tab[:, 0].tolist(),
                                         "at_levels": got.tolist()}, indent=1))


if __name__ == "__main__":
    main()
