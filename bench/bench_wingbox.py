"""The wingbox (fg.cases.wingbox, issue 31) against CalculiX S8R in the same run: for each
configuration, flexgvt's nonlinear static solution + 15 modes about it, and CalculiX's NLGEOM
static step + 15 modes in a PERTURBATION step on the same plates (mid-side nodes added), both with
the same imperfection of the compressed skin (bench/ccx_wingbox.py). CPU seconds of flexgvt's
process and of CalculiX's (its child rusage, all threads; OMP_NUM_THREADS=2) with wall times and
the load average before and after: on the shared machine wall time mostly measures the others.

    python bench/bench_wingbox.py --sizes 0.25 0.1 --json /tmp/bench_wingbox.json
    python bench/bench_wingbox.py --sizes 0.1 --ccx-timeout 1800      # stop CalculiX after 30 min wall

The full multi-configuration update's time is bench/bench_wingbox_update.py's.
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
from ccx_wingbox import GRAVITY, global_pairs, run_calculix, run_flexgvt  # noqa: E402

import flexgvt as fg  # noqa: E402

N_MODES = 15


def warm_up():
    """Compile (or load from numba's cache) the kernels on a coarse box, outside the timings."""
    run_flexgvt(0.5, "minus_1g", 3)


def one(size: float, name: str, args) -> dict:
    case = fg.cases.wingbox(element_size=size)
    load = [os.getloadavg()[0]]
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
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=float, nargs="+", default=[0.25, 0.1])
    parser.add_argument("--configurations", nargs="+", default=list(GRAVITY))
    parser.add_argument("--ccx-timeout", type=float, default=None, help="wall seconds per CalculiX run")
    parser.add_argument("--no-ccx", action="store_true")
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    warm_up()
    out = {"ccx": version() if have_ccx() else "not installed", "cpus": os.cpu_count(), "rows": []}
    for size in args.sizes:
        for name in args.configurations:
            out["rows"].append(one(size, name, args))
            if args.json:
                Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    update = Path(__file__).with_name("bench_wingbox_update.py")
    if not update.exists():
        print("the multi-configuration update's time: bench/bench_wingbox_update.py (not here yet)")
    if not have_ccx():
        print("CalculiX (ccx) is not installed: apt-get install calculix-ccx")
    totals = [(r["flexgvt"]["static_cpu_s"] + r["flexgvt"]["modes_cpu_s"], r["calculix"]["cpu_s"])
              for r in out["rows"] if "cpu_s" in r.get("calculix", {})]
    if totals:
        f, c = np.sum(totals, axis=0)
        print(f"all finished pairs: flexgvt {f:.1f} s CPU, CalculiX {c:.0f} s CPU ({c / f:.0f}x)")


if __name__ == "__main__":
    main()
