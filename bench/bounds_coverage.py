"""Coverage of the prediction's confidence bounds on the synthetic demo (`flexgvt demo`) over seeds:
how often the as-built truth (free-free modes and the 20 m bungee configurations' modes, paired with
the prediction by full-shape MAC as the demo scores them) lies inside the updated model's interval,
for the default settings and for variants (no widening to the fit, no prior).

    python bench/bounds_coverage.py --seeds 1-10 --out /tmp/coverage

Each seed's demo project is written to <out>/d<seed> (reused when there: the run resumes from its
store, so a second call only recomputes the bounds). docs/updating.md quotes its output.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from flexgvt import cases
from flexgvt.fem import solve_modes, solve_static
from flexgvt.model import Configuration
from flexgvt.updating import UncertaintySettings
from flexgvt.workflow import load_project, run
from flexgvt.workflow.bounds import add_bounds
from flexgvt.workflow.demo import SCORED_MODES, demo_project, score_against_truth

VARIANTS = {"default (linear)": UncertaintySettings(),
            "no widening to the fit": UncertaintySettings(scale_to_fit=False),
            "no prior": UncertaintySettings(prior="none")}


def _elastic(modes):
    """Suspension and rigid-body modes (energy mostly in the cords or rigid) set to 0 Hz, as the demo scores."""
    return replace(modes, frequencies_hz=np.where(modes.energy_fractions[:, 4] > 0.5, 0.0, modes.frequencies_hz))


def _seeds(text: str) -> list[int]:
    a, _, b = text.partition("-")
    return list(range(int(a), int(b or a) + 1))


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1-10", help="seeds, 'a-b' or one")
    parser.add_argument("--out", type=Path, default=Path("coverage-output"))
    args = parser.parse_args(argv)
    found = {k: [] for k in VARIANTS}  # (kind, seed, label, truth, predicted, low, high)
    fits = []
    for seed in _seeds(args.seeds):
        folder = args.out / f"d{seed}"
        if not (folder / "project.toml").is_file():
            demo_project(folder, seed, progress=lambda s: None)
        res = run(load_project(folder / "project.toml"))
        pred = res.predictions["updated"]
        truth = cases.xhale(as_built=True, seed=seed)
        free_truth = solve_modes(solve_static(truth.model, Configuration("free_free")), SCORED_MODES + 8,
                                 damped=False)
        bungee = {name: solve_modes(solve_static(truth.model, truth.configurations[name]), 20, damped=False)
                  for name in res.project.spec.prediction.proposed}
        for variant, settings in VARIANTS.items():
            add_bounds(res.project, res.update, pred, res.identified, settings)
            if variant.startswith("default"):
                u = pred.uncertainty
                fits.append((seed, u["sigma"], u["chi2_per_dof"], u["dof"]))
            for s in score_against_truth(free_truth, pred.free):
                r = min(pred.rows, key=lambda r: abs(r["free_hz"] - s["predicted_hz"]))
                found[variant].append(("free-free", seed, s["label"], s["truth_hz"], r["free_hz"],
                                       r["free_low_hz"], r["free_high_hz"]))
            for name, tm in bungee.items():
                modes = pred.modes[name]
                for s in score_against_truth(_elastic(tm), _elastic(pred.proposed[name])):
                    m = min(modes, key=lambda m: abs(m["frequency_hz"] - s["predicted_hz"]))
                    found[variant].append((name, seed, s["label"], s["truth_hz"], m["frequency_hz"], m["low_hz"],
                                           m["high_hz"]))
        print(f"seed {seed}: sigma {fits[-1][1]:.3g} (chi2/dof of the measured scatter {fits[-1][2]:.0f}, "
              f"{fits[-1][3]:.1f} dof)", flush=True)
    summary = {}
    for variant, rows in found.items():
        print(f"\n{variant}")
        for kind in sorted({r[0] for r in rows}) + ["all"]:
            sel = [r for r in rows if kind in ("all", r[0])]
            # a missing bound: unbounded (a direction nothing constrains), which covers
            inside = [lo is None or hi is None or lo <= t <= hi for _, _, _, t, f, lo, hi in sel]
            half = [100 * (hi - lo) / 2 / f for _, _, _, t, f, lo, hi in sel if lo is not None and hi is not None]
            err = [100 * abs(f - t) / t for _, _, _, t, f, lo, hi in sel]
            summary[(variant, kind)] = float(np.mean(inside))
            print(f"  {kind:16s} {len(sel):3d} modes: coverage {100 * np.mean(inside):5.1f} %, unbounded "
                  f"{len(sel) - len(half):2d}, median half-width {np.median(half) if half else float('nan'):.3f} %, "
                  f"median |error| {np.median(err):.3f} %")
    return {"coverage": summary, "fits": fits}


if __name__ == "__main__":
    main()
