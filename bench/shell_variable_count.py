"""Does a Jacobian's cost grow with the number of shell variables? (issue 30: "the Jacobian cost must
not grow with the number of shell variables"). The wingbox (fg.cases.wingbox, skins split by rib
bay) at -1 g on its post-buckled path, 8 modes with shapes at the protocol's 24 sensors and the tip
deflection: one Jacobian at the initial point (its evaluation done first) with the skins' thickness
as one variable, and as one variable per rib bay (64), beside rho, E, the ribs' and the spars'
thickness. Times are the best of --repeat Jacobians, each on a fresh problem.

    python bench/shell_variable_count.py [--size 0.25] [--repeat 2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from flexgvt.updating import UpdatingProblem, shell
from flexgvt.updating.verify import _surrogate, _wingbox_setup


def jacobian_seconds(case, train, data, variables, repeat: int) -> tuple[float, float]:
    """(best wall, its CPU) seconds of one Jacobian at x0 with ``variables``."""
    best = (np.inf, np.inf)
    for _ in range(repeat):
        problem = UpdatingProblem(case.model, train, data, variables)
        problem.evaluate(problem.x0)
        w, c = time.perf_counter(), time.process_time()
        problem.evaluate(problem.x0, gradient=True)
        best = min(best, (time.perf_counter() - w, time.process_time() - c))
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=float, default=0.25, help="element size [m]")
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    case, sensors, _, train, _, tip = _wingbox_setup(args.size, local=1.0)
    train = [c for c in train if c.name == "minus_1g"]
    data = _surrogate(case.model, train, sensors, 8, tip)
    bays = sorted(g.name for g in case.model.shells if g.name.startswith("skin_"))
    common = [shell("rho", "*", "rho"), shell("E", "*", "E"), shell("t_ribs", "ribs", "thickness"),
              shell("t_spars", "spar_*", "thickness")]
    rows = []
    for label, skins in (("skins as one variable", [shell("t_skins", bays, "thickness")]),
                         (f"one per rib bay ({len(bays)})", [shell(f"t_{b}", b, "thickness") for b in bays])):
        variables = common + skins
        wall, cpu = jacobian_seconds(case, train, data, variables, args.repeat)
        rows.append((label, len(variables), wall, cpu))
    print(f"wingbox {args.size} m, -1 g, {len(case.model.node_ids)} nodes; one Jacobian (best of {args.repeat})")
    print("| shell variables | count | Jacobian wall [s] | CPU [s] | CPU per variable [s] |")
    print("|---|---:|---:|---:|---:|")
    for label, n, wall, cpu in rows:
        print(f"| {label} | {n} | {wall:.2f} | {cpu:.2f} | {cpu / n:.3f} |")
    print(f"ratio (per bay / one): wall {rows[1][2] / rows[0][2]:.2f}x, CPU {rows[1][3] / rows[0][3]:.2f}x "
          f"for {rows[1][1] / rows[0][1]:.1f}x the variables")


if __name__ == "__main__":
    main()
