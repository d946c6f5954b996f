"""The swept wing's root spring stiffening under a tip load (issue 33, the original work's future
work on load-dependent boundary conditions): fg.cases.swept_wing on the shaker table with an upward
tip load swept from 0 to --max-load N, its root spring's bending components (M_x out of plane, M_z
in plane) either linear (Table 5.7's values) or following moment-rotation tables whose tangent
doubles at --hardening rad (cases.swept_wing.root_hardening_tables: a chosen law, nothing was
published). At each load: the tip deflection, the root rotation and the root spring's tangent
there, and the first modes about that static state, tracked by MAC (fem.modes_versus_load).

    python bench/swept_wing_root_load.py --out /tmp/sw-root --json /tmp/sw-root/modes.json

Writes modes_vs_load.csv and modes_vs_load.png into --out.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import flexgvt as fg
from table_spring_modes import ratio_panel  # bench/ beside this script


def sweep(hardening: float | None, loads: np.ndarray, n_modes: int, n_wing: int) -> dict:
    """Tip deflection, root rotation and tangent (M_x), tracked frequencies at each load."""
    case = fg.cases.swept_wing(n_wing=n_wing, root_hardening=hardening, tip_load=float(loads[-1]))
    model = case.model
    tracking = fg.modes_versus_load(model, case.configurations["tip_load"], loads / loads[-1], n_modes=n_modes,
                                    settings=fg.StaticSettings(tolerance=1e-10))
    i_clamp, i_tip = model.index_of([case.references["clamp_node"], case.references["tip_node"]], "bench")
    spring = model.springs[[s.name for s in model.springs].index("root_spring")]
    rows = []
    for k, load in enumerate(loads):
        d = tracking.modes[k].state.displacements
        rx = float(d[i_clamp, 3])
        table = spring.tables[3]
        tangent = (float(spring.table_scale[3] * table.evaluate(rx)[1]) if table is not None
                   else float(spring.stiffness[3]))
        rows.append({"load_N": float(load), "tip_z_m": float(d[i_tip, 2]), "root_rx_rad": rx,
                     "k_mx_Nm_per_rad": tangent, "frequencies_hz": tracking.frequencies_hz[k].tolist()})
    return {"labels": list(tracking.labels), "rows": rows}


def figure(result: dict, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4.2), layout="constrained")
    ax, bx = fig.subplots(1, 2)
    ratio_panel(ax, result["hardening"], result["linear"], "swept wing: hardening root spring (solid), linear (dashed)")
    for key, style in (("hardening", "-o"), ("linear", "--s")):
        rows = result[key]["rows"]
        bx.plot([r["load_N"] for r in rows], [r["tip_z_m"] for r in rows], style, ms=3, label=f"tip z, {key} root")
    bx.set_xlabel("tip load [N]")
    bx.set_ylabel("tip deflection [m]")
    bx.set_title("static tip deflection")
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    fig.savefig(path, dpi=120)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=None, help="folder for modes_vs_load.csv and .png")
    parser.add_argument("--json", type=Path, default=None, help="write the results here")
    parser.add_argument("--max-load", type=float, default=40.0, help="largest tip load [N]")
    parser.add_argument("--levels", type=int, default=9, help="load levels from 0")
    parser.add_argument("--modes", type=int, default=5)
    parser.add_argument("--hardening", type=float, default=0.02, help="root rotation where the tangent doubles [rad]")
    parser.add_argument("--n-wing", type=int, default=20, help="beam elements along the wing panel")
    args = parser.parse_args(argv)
    loads = np.linspace(0.0, args.max_load, args.levels)
    t0 = time.perf_counter()
    result = {"hardening_rad": args.hardening,
              "hardening": sweep(args.hardening, loads, args.modes, args.n_wing),
              "linear": sweep(None, loads, args.modes, args.n_wing)}
    result["time_s"] = time.perf_counter() - t0
    labels = result["hardening"]["labels"]
    print("load [N]  tip z [m] (linear)  root rx [rad]  k_Mx [N m/rad]  " + "  ".join(
        f"{lab} [Hz] (linear)" for lab in labels))
    for rh, rl in zip(result["hardening"]["rows"], result["linear"]["rows"]):
        freqs = "  ".join(f"{a:7.3f} ({b:7.3f})" for a, b in zip(rh["frequencies_hz"], rl["frequencies_hz"]))
        print(f"{rh['load_N']:8.1f}  {rh['tip_z_m']:7.4f} ({rl['tip_z_m']:7.4f})  {rh['root_rx_rad']:13.4f}  "
              f"{rh['k_mx_Nm_per_rad']:14.1f}  {freqs}")
    print(f"({result['time_s']:.1f} s)")
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        with open(args.out / "modes_vs_load.csv", "w") as fh:
            fh.write("load_N,tip_z_m,tip_z_linear_m,root_rx_rad,k_mx_Nm_per_rad," + ",".join(
                f"{lab.replace(' ', '_')}_hz,{lab.replace(' ', '_')}_linear_hz" for lab in labels) + "\n")
            for rh, rl in zip(result["hardening"]["rows"], result["linear"]["rows"]):
                values = [rh["load_N"], rh["tip_z_m"], rl["tip_z_m"], rh["root_rx_rad"], rh["k_mx_Nm_per_rad"]]
                values += [v for pair in zip(rh["frequencies_hz"], rl["frequencies_hz"]) for v in pair]
                fh.write(",".join(f"{v:.6g}" for v in values) + "\n")
        figure(result, args.out / "modes_vs_load.png")
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=1))
    return result


if __name__ == "__main__":
    main()
