"""The wingbox (fg.cases.wingbox, issue 31) against CalculiX S8R in the same run: for each
configuration, flexgvt's nonlinear static solution + 15 modes about it, and CalculiX's NLGEOM
static step + 15 modes in a PERTURBATION step on the same plates (mid-side nodes added), both with
the same imperfection of the compressed skin (bench/ccx_wingbox.py). CPU seconds of flexgvt's
process and of CalculiX's (its child rusage, all threads; OMP_NUM_THREADS=2) with wall times and
the load average before and after: on the shared machine wall time mostly measures the others.

    python bench/bench_wingbox.py --sizes 0.25 0.1 --json /tmp/bench_wingbox.json
    python bench/bench_wingbox.py --sizes 0.1 --ccx-timeout 1800      # stop CalculiX after 30 min wall
    python bench/bench_wingbox.py --sizes 0.1 --split --update --json out.json   # the issue's whole bench

--split: where flexgvt's time goes in each configuration (exclusive CPU and wall seconds of the
kernels, assembly, factorisation, triangular solves, ARPACK; bench_scale.Split). --update: then, in
the same process, the verification protocol's multi-configuration update at the first size (seed
1's mistuning, serial; bench_wingbox_update.measure: time per evaluation, per Jacobian, the whole run).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from ccx_driver import CcxTimeout, have_ccx, version  # noqa: E402
from bench_scale import Split  # noqa: E402
from bench_wingbox_update import measure  # noqa: E402
from ccx_wingbox import GRAVITY, global_pairs, run_calculix, run_flexgvt  # noqa: E402

import flexgvt as fg  # noqa: E402

N_MODES = 15


def warm_up():
    """Compile (or load from numba's cache) the kernels on a coarse box, outside the timings."""
    run_flexgvt(0.5, "minus_1g", 3)


def one(size: float, name: str, args) -> dict:
    case = fg.cases.wingbox(element_size=size)
    load = [os.getloadavg()[0]]
    if args.split:
        with Split() as split:
            f = run_flexgvt(size, name, N_MODES, case=case)
        total = f["static_cpu_s"] + f["modes_cpu_s"], f["static_wall_s"] + f["modes_wall_s"]
        f["split"] = [{"part": k, "cpu_s": c, "wall_s": w, "calls": n} for k, c, w, n in split.rows(*total)]
    else:
        f = run_flexgvt(size, name, N_MODES, case=case)
    f.pop("shapes_all", None)
    row = {"size": size, "configuration": name, "nodes": f["nodes"], "flexgvt": f}
    line = (f"{size:g} m {name}: flexgvt {f['static_cpu_s'] + f['modes_cpu_s']:.1f} s CPU (static "
            f"{f['static_cpu_s']:.1f} + modes {f['modes_cpu_s']:.1f}; wall "
            f"{f['static_wall_s'] + f['modes_wall_s']:.1f} s), tip {f['tip_w_m']:.4f} m")
    if have_ccx() and not args.no_ccx:
        try:
            c = run_calculix(size, name, N_MODES, case=case, timeout=args.ccx_timeout)
            row["calculix"] = c
            fc = f["static_cpu_s"] + f["modes_cpu_s"]
            row["cpu_ratio"] = c["cpu_s"] / fc
            row["pairs"] = global_pairs(f, c, 5)
            line += (f"; CalculiX {c['cpu_s']:.0f} s CPU ({c['wall_s']:.0f} s wall), tip "
                     f"{c.get('tip_w_m', 0.0):.4f} m; CalculiX / flexgvt CPU {row['cpu_ratio']:.0f}x; first global "
                     f"modes {[round(p['difference_percent'], 2) for p in row['pairs']]} %")
        except CcxTimeout as exc:
            row["calculix"] = {"stopped_cpu_s": exc.cpu_s, "stopped_wall_s": exc.wall_s}
            line += f"; CalculiX stopped after {exc.wall_s:.0f} s wall ({exc.cpu_s:.0f} s CPU)"
    load.append(os.getloadavg()[0])
    row["load_average"] = load
    print(line + f"; load {load[0]:.1f}-{load[1]:.1f}", flush=True)
    if args.split:
        print("| part | CPU [s] | wall [s] | calls |\n|---|---:|---:|---:|")
        for r in f["split"]:
            print(f"| {r['part']} | {r['cpu_s']:.2f} | {r['wall_s']:.2f} | {r['calls']} |")
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=float, nargs="+", default=[0.25, 0.1])
    parser.add_argument("--configurations", nargs="+", default=list(GRAVITY))
    parser.add_argument("--ccx-timeout", type=float, default=None, help="wall seconds per CalculiX run")
    parser.add_argument("--no-ccx", action="store_true")
    parser.add_argument("--split", action="store_true", help="where flexgvt's time goes (per configuration)")
    parser.add_argument("--update", action="store_true", help="then the multi-configuration update at the first size")
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    warm_up()
    out = {"ccx": version() if have_ccx() else "not installed", "cpus": os.cpu_count(), "rows": []}
    for size in args.sizes:
        for name in args.configurations:
            out["rows"].append(one(size, name, args))
            if args.json:
                Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    if args.update:
        load = os.getloadavg()[0]
        u = measure(args.sizes[0], update=True, processes=None)
        u["load_average"] = [load, os.getloadavg()[0]]
        out["update"] = u
        print(f"{args.sizes[0]:g} m multi-configuration update ({u['nodes']} nodes, serial): set-up "
              f"{u['setup_s']:.1f} s, evaluation {u['evaluation_s']:.1f} s wall ({u['evaluation_cpu_s']:.1f} s CPU), "
              f"Jacobian "
              f"{u['jacobian_s']:.1f} s wall ({u['jacobian_cpu_s']:.1f} s CPU), whole update {u['update_s']:.0f} s "
              f"wall ({u['update_cpu_s']:.0f} s CPU; {u['solves']} solves, {u['gradients']} Jacobians, largest "
              f"variable error {u['variable_error_percent']:.2g} %); load {load:.1f}-{u['load_average'][1]:.1f}",
              flush=True)
        if args.json:
            Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    if not have_ccx():
        print("CalculiX (ccx) is not installed: apt-get install calculix-ccx")
    totals = [(r["flexgvt"]["static_cpu_s"] + r["flexgvt"]["modes_cpu_s"], r["calculix"]["cpu_s"])
              for r in out["rows"] if "cpu_s" in r.get("calculix", {})]
    if totals:
        f, c = np.sum(totals, axis=0)
        print(f"all finished pairs: flexgvt {f:.1f} s CPU, CalculiX {c:.0f} s CPU ({c / f:.0f}x)")


if __name__ == "__main__":
    main()
