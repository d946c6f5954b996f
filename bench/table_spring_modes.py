"""Modes against load on a nonlinear root spring (issue 33): a 1 m aluminium strip (30 x 5 mm, 20
beam elements, 0.1 kg tip mass) on a 6-component hardening root spring given by force-deflection
tables (model.SpringTable), a fixed-direction tip load swept from 0 to --max-load N downwards. At each
load: the static state (the root spring's deflection on its table), the tangent of every table
component there, and the first modes about that state, tracked by MAC (fem.modes_versus_load);
beside them the same strip on a linear root spring of the tables' slopes at zero, so that what the
table adds to the geometric stiffening shows.

    python bench/table_spring_modes.py --out /tmp/tspring --json /tmp/tspring/modes.json

Writes modes_vs_load.csv and modes_vs_load.png into --out. The tables are the laws of the OpenSees
peer case (tests/fem/table_spring_peer.py, "soft"), k(1 + c d^2), sampled at 9 (translations) or 13
(rotations) points and interpolated by the monotone cubic (--segments: straight segments, whose
slope, and so the modes, jump at each point).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import flexgvt as fg
from flexgvt.model import SpringTable

L, N, TIP_MASS = 1.0, 20, 0.1
MATERIAL = fg.Material("aluminium", E=70e9, rho=2700.0, G=26e9)
SECTION = fg.RectangularSection(0.03, 0.005)
_U = np.linspace(-0.02, 0.02, 9)
_T = np.linspace(-0.3, 0.3, 13)
TABLES = {1: (_U, 2e5 * _U * (1 + 2e4 * _U**2)), 2: (_U, 1e5 * _U * (1 + 2e4 * _U**2)),
          3: (_U, 1e5 * _U * (1 + 2e4 * _U**2)), 4: (_T, 50 * _T * (1 + 20 * _T**2)),
          5: (_T, 20 * _T * (1 + 100 * _T**2)), 6: (_T, 300 * _T * (1 + 20 * _T**2))}
COMPONENTS = ("x", "y", "z", "rx", "ry", "rz")


def strip(tabled: bool, smooth: bool = True) -> tuple[fg.Model, int, int]:
    """(model, root node, tip node): the strip on the table root spring, or on the linear spring of
    the tables' slopes at zero."""
    model = fg.Model("strip on a table root spring" if tabled else "strip on a linear root spring")
    ids = model.add_nodes(np.c_[np.linspace(0, L, N + 1), np.zeros(N + 1), np.zeros(N + 1)])
    model.add_beams(np.c_[ids[:-1], ids[1:]], MATERIAL, SECTION)
    model.add_mass(int(ids[-1]), TIP_MASS)
    tables = {c: SpringTable.make(x, f, smooth=smooth) for c, (x, f) in TABLES.items()}
    if tabled:
        model.add_spring(int(ids[0]), None, tables=tables, name="root")
    else:
        model.add_spring(int(ids[0]), None, stiffness=[t.nominal_stiffness for t in tables.values()], name="root")
    return model, int(ids[0]), int(ids[-1])


def sweep(tabled: bool, loads: np.ndarray, n_modes: int, smooth: bool = True) -> dict:
    """Tip deflection, root deflections and tangents, tracked frequencies at each load."""
    model, root, tip = strip(tabled, smooth)
    cfg = fg.Configuration("tip load", forces=[fg.NodalLoad(tip, force=(0.0, 0.0, -float(loads[-1])))])
    tracking = fg.modes_versus_load(model, cfg, loads / loads[-1], n_modes=n_modes,
                                    settings=fg.StaticSettings(tolerance=1e-12))
    i_root, i_tip = model.index_of([root, tip], "bench")
    spring = model.springs[0]
    rows = []
    for k, P in enumerate(loads):
        d = tracking.modes[k].state.displacements  # rotations: the rotation vector (log of R)
        deflection = d[i_root]
        tangent = [float(spring.table_scale[c] * spring.tables[c].evaluate(deflection[c])[1])
                   if spring.tables[c] is not None else float(spring.stiffness[c]) for c in range(6)]
        rows.append({"load_N": float(P), "tip_z_m": float(d[i_tip, 2]), "tip_x_m": float(d[i_tip, 0]),
                     "root_deflection": deflection.tolist(), "root_tangent": tangent,
                     "frequencies_hz": tracking.frequencies_hz[k].tolist()})
    return {"labels": list(tracking.labels), "rows": rows}


def ratio_panel(ax, solid: dict, dashed: dict, title: str) -> None:
    """Each tracked mode's f / f(0) against the load: the sweep ``solid`` (its rows' load_N and
    frequencies_hz, and its labels) as lines with points, ``dashed`` in the same colours."""
    loads = [r["load_N"] for r in solid["rows"]]
    f_s = np.array([r["frequencies_hz"] for r in solid["rows"]])
    f_d = np.array([r["frequencies_hz"] for r in dashed["rows"]])
    labels = solid["labels"] or [f"mode {j + 1}" for j in range(f_s.shape[1])]
    for j in range(f_s.shape[1]):
        colour = f"C{j}"
        ax.plot(loads, f_s[:, j] / f_s[0, j], "-o", color=colour, ms=3, label=f"{labels[j]} ({f_s[0, j]:.2f} Hz)")
        ax.plot(loads, f_d[:, j] / f_d[0, j], "--", color=colour, lw=1)
    ax.set_xlabel("tip load [N]")
    ax.set_ylabel("f / f(0)")
    ax.set_title(title)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)


def figure(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4.2), layout="constrained")
    ax, bx = fig.subplots(1, 2)
    ratio_panel(ax, result["table"], result["linear"], "modes against load: table root spring (solid), linear (dashed)")
    x, f = TABLES[5]
    table = SpringTable.make(x, f, smooth=result["smooth"])
    fine = np.linspace(x[0], x[-1], 301)
    bx.plot(fine, table.evaluate(fine)[0], "k-", lw=1, label="ry table (root bending)")
    bx.plot(x, f, "k.")
    th = [r["root_deflection"][4] for r in result["table"]["rows"]]
    m = [float(table.evaluate(t)[0]) for t in th]
    bx.plot(th, m, "o", color="C3", label="static states")
    bx.plot(x, f[5] / x[5] * x, ":", color="grey", label="slope at zero")
    bx.set_xlabel("root rotation ry [rad]")
    bx.set_ylabel("root moment [N m]")
    bx.set_title("root spring: where each load puts it")
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    fig.savefig(path, dpi=120)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=None, help="folder for modes_vs_load.csv and .png")
    parser.add_argument("--json", type=Path, default=None, help="write the results here")
    parser.add_argument("--max-load", type=float, default=10.0, help="largest tip load [N]")
    parser.add_argument("--levels", type=int, default=11, help="load levels from 0")
    parser.add_argument("--modes", type=int, default=4)
    parser.add_argument("--segments", action="store_true", help="straight segments instead of the monotone cubic")
    args = parser.parse_args(argv)
    loads = np.linspace(0.0, args.max_load, args.levels)
    t0 = time.perf_counter()
    result = {"table": sweep(True, loads, args.modes, not args.segments), "linear": sweep(False, loads, args.modes),
              "smooth": not args.segments}
    result["time_s"] = time.perf_counter() - t0
    head = "load [N]  tip z [m]  root ry [rad]  k_ry [N m/rad]  " + "  ".join(
        f"f{j + 1} [Hz] (linear)" for j in range(args.modes))
    lines = [head]
    for rt, rl in zip(result["table"]["rows"], result["linear"]["rows"]):
        freqs = "  ".join(f"{a:7.3f} ({b:7.3f})" for a, b in zip(rt["frequencies_hz"], rl["frequencies_hz"]))
        lines.append(f"{rt['load_N']:8.2f}  {rt['tip_z_m']:9.4f}  {rt['root_deflection'][4]:13.4f}  "
                     f"{rt['root_tangent'][4]:14.2f}  {freqs}")
    print("\n".join(lines))
    print(f"({result['time_s']:.1f} s)")
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        with open(args.out / "modes_vs_load.csv", "w") as fh:
            fh.write("load_N,tip_z_m,root_ry_rad,k_ry_Nm_per_rad," + ",".join(
                f"f{j + 1}_table_hz,f{j + 1}_linear_hz" for j in range(args.modes)) + "\n")
            for rt, rl in zip(result["table"]["rows"], result["linear"]["rows"]):
                values = [rt["load_N"], rt["tip_z_m"], rt["root_deflection"][4], rt["root_tangent"][4]]
                values += [v for pair in zip(rt["frequencies_hz"], rl["frequencies_hz"]) for v in pair]
                fh.write(",".join(f"{v:.9g}" for v in values) + "\n")
        figure(result, args.out / "modes_vs_load.png")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=1))
    return result


if __name__ == "__main__":
    main()
