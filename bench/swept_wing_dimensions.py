"""The swept wing's printed-frame dimensions (docs/swept_wing.md, "Chosen dimensions"): the wall
thickness and the closed nose cell's extent of fg.cases.swept_wing, chosen against the original
work's as-designed FE model (Table 5.1, configuration 1 skin on: 1 OOP, 1 T, 1 IP, 2 OOP), never
against the GVT tables. For every candidate (walls 0.4-0.8 mm, cells to 10, 15, 20 % chord) the
case is built with the as-designed materials (as_designed=True) on the as-designed clamp, and its
first modes of those four kinds are compared with Table 5.1; the smallest rms error is the choice.

    python bench/swept_wing_dimensions.py --json /tmp/sw-dims.json [--stick]

--stick: the stick model on the spar line (part_offsets=False), as the choice was first made.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import flexgvt as fg

WALLS = (0.0004, 0.0005, 0.0006, 0.0007, 0.0008)  # m
CELLS = (0.10, 0.15, 0.20)  # chord fraction of the closed nose cell
KINDS = ("1 OOP", "1 T", "1 IP", "2 OOP")


def candidate(wall: float, cell: float, part_offsets: bool, target: dict, n_wing: int) -> dict:
    """One candidate's four frequencies [Hz] (first mode of each kind) and rms error [%] against Table 5.1."""
    case = fg.cases.swept_wing(n_wing=n_wing, as_designed=True, part_offsets=part_offsets,
                               properties={"printed_wall": wall, "closed_cell_x": cell})
    modes = fg.solve_modes(fg.solve_static(case.model, case.configurations["as_designed_clamp"]), 8)
    labels = [lab.split("/")[0] for lab in modes.labels]
    f = [float(modes.frequencies_hz[labels.index(k)]) if k in labels else float("nan") for k in KINDS]
    err = [100 * (x / target[k] - 1) for x, k in zip(f, KINDS)]
    return {"wall_m": wall, "closed_cell_x": cell, "frequencies_hz": f, "errors_percent": err,
            "rms_percent": float(np.sqrt(np.mean(np.square(err))))}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, default=None, help="write the candidates as JSON")
    parser.add_argument("--stick", action="store_true", help="the stick model on the spar line (part_offsets=False)")
    parser.add_argument("--n-wing", type=int, default=20, help="wing elements (the case's default)")
    args = parser.parse_args(argv)
    published = fg.cases.swept_wing(n_wing=2, n_body=2, n_fin=2).references["published"]["as_designed_hz"]
    target = {k: published[k] for k in KINDS}
    t0 = time.perf_counter()
    rows = [candidate(w, c, not args.stick, target, args.n_wing) for w in WALLS for c in CELLS]
    best = min(rows, key=lambda r: r["rms_percent"])
    print("Table 5.1 (skin on): " + " / ".join(f"{target[k]:.2f}" for k in KINDS) + " Hz (" + ", ".join(KINDS) + ")")
    for r in rows:
        mark = "  <- chosen" if r is best else ""
        print(f"wall {r['wall_m'] * 1e3:.1f} mm, cell to {r['closed_cell_x']:.2f}: "
              + " / ".join(f"{x:6.2f}" for x in r["frequencies_hz"]) + f" Hz, rms {r['rms_percent']:5.2f} %{mark}")
    out = {"model": "stick (part_offsets=False)" if args.stick else "part_offsets", "table_5_1_hz": target,
           "candidates": rows, "chosen": best, "seconds": time.perf_counter() - t0}
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
