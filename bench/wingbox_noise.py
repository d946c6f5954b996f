"""Issue 31's verification protocol on noisy surrogate data (docs/updating.md, "Noisy data"): the
wingbox's reference data (frequencies, shapes at the skin sensors, static tip deflections, mass
properties) perturbed by seeded Gaussian noise of a realistic GVT, then the multi- and
single-configuration updates of verify() on them, judged on every configuration and on the unseen
combined case (whose data stay exact: it is the truth the predictions are scored against).

    python bench/wingbox_noise.py --case wingbox --seeds 1 2 3 --noise-seeds 1 2 [--element-size 0.25]
        [--frequency-std 0.002] [--shape-std 0.02] [--static-std 0.01] [--mass-std 0.002]
        [--inertia-std 0.01] [--out bench/out/wingbox_noise]

Noise (each a relative standard deviation): frequencies (each measured frequency; the updates are
told it, Measured.frequency_std_hz, so it weighs the frequencies and sets the variables' stds),
shapes (of each mode's largest sensor reading, added to every reading), static deflections, the
mass, the three moments of inertia; the cg coordinates' noise is a fraction of the mass's rms
spread along each axis (the length flexgvt divides a cg error by: updating.masstargets). Writes table.md and
noise_<case>_<seed>_<noise seed>.json in --out.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from flexgvt import updating as up
from flexgvt.updating.masstargets import mass_spread


def noisy(protocol, rng: np.random.Generator, args) -> object:
    """The protocol with its training data and mass properties perturbed (the unseen data exact)."""
    data = []
    for m in protocol.data:
        f = m.frequencies_hz * (1 + args.frequency_std * rng.standard_normal(len(m.frequencies_hz)))
        shapes = m.shapes
        if shapes is not None:
            scale = np.abs(shapes).max(axis=1, keepdims=True)
            shapes = shapes + args.shape_std * scale * rng.standard_normal(shapes.shape)
        static = {k: v * (1 + args.static_std * rng.standard_normal()) for k, v in m.static.items()}
        data.append(replace(m, frequencies_hz=f, shapes=shapes, static=static,
                            frequency_std_hz=args.frequency_std * m.frequencies_hz))
    t = protocol.mass_target
    spread = mass_spread(t.mass, t.inertia)  # [m] along x, y, z
    target = replace(t, mass=t.mass * (1 + args.mass_std * rng.standard_normal()),
                     cg=tuple(np.asarray(t.cg) + args.cg_std * spread * rng.standard_normal(3)),
                     inertia=tuple(np.asarray(t.inertia) * (1 + args.inertia_std * rng.standard_normal(3))))
    return replace(protocol, data=data, mass_target=target)


def row(v, seed: int, noise_seed: int) -> str:
    e = v.variable_errors_percent
    unseen = v.prediction
    worst = {k: float(np.nanmax(np.abs(unseen[f"{k}_error_percent"]))) for k in ("multi", "single")}
    held = {k: sum(bool(r.get("fixed")) for r in getattr(v, k).variables) for k in ("multi", "single")}
    note = {k: f" ({n} held)" if n else "" for k, n in held.items()}
    return (f"| {seed} | {noise_seed} | {np.abs(e['initial']).max():.2f} | {np.abs(e['multi']).max():.3f}"
            f"{note['multi']} | {np.abs(e['single']).max():.3f}{note['single']} | {worst['multi']:.3f} | "
            f"{worst['single']:.3f} |")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", choices=("wingbox", "wingbox_local"), default="wingbox")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--noise-seeds", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--element-size", type=float, default=0.25)
    ap.add_argument("--frequency-std", type=float, default=0.002)
    ap.add_argument("--shape-std", type=float, default=0.02)
    ap.add_argument("--static-std", type=float, default=0.01)
    ap.add_argument("--mass-std", type=float, default=0.002)
    ap.add_argument("--inertia-std", type=float, default=0.01)
    ap.add_argument("--cg-std", type=float, default=0.002)
    ap.add_argument("--tolerance", type=float, default=None)
    ap.add_argument("--out", type=Path, default=Path("bench/out/wingbox_noise"))
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    protocol = up.verification_protocol(args.case, element_size=args.element_size)
    head = [f"{args.case}, element size {args.element_size:g} m; noise: frequencies {100 * args.frequency_std:g} %, "
            f"shapes {100 * args.shape_std:g} % of each mode's largest reading, static {100 * args.static_std:g} %, "
            f"mass {100 * args.mass_std:g} %, inertia {100 * args.inertia_std:g} %, cg {100 * args.cg_std:g} % of the "
            f"mass spread; "
            f"set-up {time.perf_counter() - t0:.0f} s; load average {os.getloadavg()[0]:.1f} at the start",
            "", "| seed | noise seed | initial max var. error [%] | multi max var. error [%] | single max var. "
            "error [%] | unseen, multi max freq. error [%] | unseen, single [%] |", "|---|---|---|---|---|---|---|"]
    rows, variables = [], []
    for seed in args.seeds:
        for ns in args.noise_seeds:
            rng = np.random.default_rng([seed, ns])
            t1 = time.perf_counter()
            v = up.verify(args.case, seed=seed, protocol=noisy(protocol, rng, args), tolerance=args.tolerance)
            print(v.summary(), f"\n  ({time.perf_counter() - t1:.0f} s)", flush=True)
            (args.out / f"noise_{args.case}_{seed}_{ns}.json").write_text(json.dumps(v.to_dict(), indent=1))
            rows.append(row(v, seed, ns))
            e = v.variable_errors_percent
            variables.append(f"| {seed} | {ns} | " + " | ".join(
                f"{e['multi'][k]:+.2f} / {e['single'][k]:+.2f}" for k in range(len(v.names))) + " |")
            names = v.names
            text = head + rows + ["", "Each variable's error, multi / single [%]:", "",
                                  "| seed | noise seed | " + " | ".join(names) + " |",
                                  "|---|---|" + "---|" * len(names)] + variables
            text.append(f"\nwhole run {time.perf_counter() - t0:.0f} s wall; load average {os.getloadavg()[0]:.1f} "
                        "at the end")
            (args.out / "table.md").write_text("\n".join(text) + "\n")
    print("\n".join(text))


if __name__ == "__main__":
    main()
