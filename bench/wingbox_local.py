"""The local-stiffness study of issue 31 (docs/updating.md, "The local-stiffness study"): the wingbox
whose reference has the root bay's bottom skin 20 % thinner than the model believes, updated on the
unloaded configuration alone and on unloaded, -1 g and 2.5 g (post-buckled) at once, judged on
every configuration and on the unseen combined case.

    python bench/wingbox_local.py --seeds 1 --element-size 0.25 --out bench/out/wingbox_local

Writes table.md (the design-variable errors and each configuration's largest frequency error per
model), verification_<seed>.json and errors_<seed>.png (report.plots.verification_errors) in --out.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

import flexgvt as fg
from flexgvt.report.plots import verification_errors


def _worst(errors) -> str:
    e = np.asarray(errors, float)
    lost = int(np.isnan(e).sum())
    text = f"{np.nanmax(np.abs(e)):.3g}" if lost < len(e) else "-"
    return text + (f" ({lost} unpaired)" if lost else "")


def table(v) -> str:
    e = v.variable_errors_percent
    held = {key: {r["name"] for r in getattr(v, key).variables if r.get("fixed")} for key in ("multi", "single")}
    lines = [f"Seed {v.seed}, {v.seconds:.0f} s wall.", "",
             "| design variable | initial [%] | multi-configuration [%] | single-configuration [%] |",
             "|---|---|---|---|"]
    for k, name in enumerate(v.names):
        m, s = (" (held)" if name in held[key] else "" for key in ("multi", "single"))
        lines.append(f"| {name} | {e['initial'][k]:+.3f} | {e['multi'][k]:+.3g}{m} | {e['single'][k]:+.3g}{s} |")
    lines += ["", "| configuration | seen by | largest frequency error: initial [%] | multi [%] | single [%] |",
              "|---|---|---|---|---|"]
    for name, row in v.configurations.items():
        seen = " and ".join(row["seen_by"]) or "neither (unseen)"
        lines.append(f"| {name} | {seen} | {_worst(row['initial_error_percent'])} | "
                     f"{_worst(row['multi_error_percent'])} | {_worst(row['single_error_percent'])} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--element-size", type=float, default=0.25)
    ap.add_argument("--factor", type=float, default=0.8, help="the reference bay's thickness against the others'")
    ap.add_argument("--out", type=Path, default=Path("bench/out/wingbox_local"))
    ap.add_argument("--no-bay-variable", action="store_true", help="the five variables only: the model cannot "
                    "represent the local difference")
    ap.add_argument("--tolerance", type=float, default=None)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    parts = [f"wingbox_local, element size {args.element_size:g} m, bay factor {args.factor:g}, "
             f"{'five variables (no bay variable)' if args.no_bay_variable else 'six variables'}, tolerance "
             f"{args.tolerance or 'default'}; "
             f"load average {os.getloadavg()[0]:.1f} at the start (2 cores shared)"]
    for seed in args.seeds:
        t0, c0 = time.perf_counter(), time.process_time()
        v = fg.updating.verify("wingbox_local", seed=seed, element_size=args.element_size, local=args.factor,
                               bay_variable=not args.no_bay_variable, tolerance=args.tolerance)
        print(v.summary(), flush=True)
        (args.out / f"verification_{seed}.json").write_text(json.dumps(v.to_dict(), indent=1))
        verification_errors(v).savefig(args.out / f"errors_{seed}.png", dpi=120)
        parts += ["", table(v), "", f"CPU {time.process_time() - c0:.0f} s, wall {time.perf_counter() - t0:.0f} s; "
                  f"load average {os.getloadavg()[0]:.1f} at the end."]
        (args.out / "table.md").write_text("\n".join(parts) + "\n")
    print("\n".join(parts))


if __name__ == "__main__":
    main()
