"""Issue 31's verification protocol on the coarse post-buckled wingbox (0.25 m: two elements per rib
bay, the loaded configurations buckle): one shared reference (verification_protocol), then each seed's
multi- and single-configuration updates; per seed the iterations, Jacobians, solves, CPU and wall
times, the largest variable and unseen-case errors; --trace prints each accepted iterate of the
multi-configuration update (objective, step, the residual rows that dominate).

    python bench/wingbox_protocol.py --seeds 1 2 3 [--element-size 0.25] [--tolerance 1e-6] [--trace]
    python bench/wingbox_protocol.py --processes 3 --tolerance 1e-3   # as the test: verify_seeds, a worker per seed

With --processes the whole run's CPU time counts the workers' too (os.times' children).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from flexgvt import updating as up


def _trace(result) -> None:
    last = None
    for row in result.history:
        x = np.asarray(row["x"])
        r = np.asarray(row["residuals"])
        names = result.final.residual_names
        top = np.argsort(-np.abs(r))[:3]
        step = "" if last is None else f" |dx| {np.linalg.norm(x - last):.2e}"
        print(f"    it {row['iteration']:3d} objective {row['objective']:.3e}{step}  "
              f"x {np.array2string(x, precision=6)}  largest: " + ", ".join(f"{names[i]} {r[i]:+.1e}" for i in top))
        last = x


def _parallel(args, w0: float, c0: float) -> None:
    runs = up.verify_seeds("wingbox", args.seeds, processes=args.processes, element_size=args.element_size,
                           tolerance=args.tolerance)
    for v in runs:
        e = {k: np.abs(np.asarray(x, float)) for k, x in v["variable_errors_percent"].items()}
        m = v["multi"]
        print(f"seed {v['seed']}: {v['cpu_seconds']:.1f} s CPU in its worker; multi {len(m['history']) - 1} "
              f"iterations, {m['gradients']} Jacobians, {m['solves']} solves ({m['message']}); single "
              f"{len(v['single']['history']) - 1 if 'history' in v['single'] else '-'} iterations")
        print(f"    max |variable error|: multi {e['multi'].max():.1e} %, single {e['single'].max():.1e} %; unseen "
              f"case, max |frequency error|: multi {max(abs(x) for x in v['prediction']['multi_error_percent']):.1e} "
              f"%, single {max(abs(x) for x in v['prediction']['single_error_percent']):.1e} %")
    t = os.times()
    print(f"whole protocol: {time.perf_counter() - w0:.1f} s wall, {time.process_time() - c0:.1f} s CPU here + "
          f"{t.children_user + t.children_system:.1f} s CPU in the workers; load average at end: "
          f"{os.getloadavg()[0]:.1f}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--element-size", type=float, default=0.25)
    ap.add_argument("--tolerance", type=float, default=1e-6)
    ap.add_argument("--trace", action="store_true")
    ap.add_argument("--processes", type=int, default=None, help="the seeds in this many worker processes")
    args = ap.parse_args(argv)
    print(f"load average at start: {os.getloadavg()[0]:.1f} (2 cores shared)")
    w0, c0 = time.perf_counter(), time.process_time()
    if args.processes:
        _parallel(args, w0, c0)
        return
    protocol = up.verification_protocol("wingbox", element_size=args.element_size)
    print(f"set-up (reference, buckling continuations, surrogate data): {time.perf_counter() - w0:.1f} s wall, "
          f"{time.process_time() - c0:.1f} s CPU")
    for seed in args.seeds:
        w, c = time.perf_counter(), time.process_time()
        v = up.verify("wingbox", seed=seed, protocol=protocol, tolerance=args.tolerance)
        e = v.variable_errors_percent
        m, s = v.multi, v.single
        print(f"seed {seed}: {time.perf_counter() - w:.1f} s wall, {time.process_time() - c:.1f} s CPU; "
              f"multi {len(m.history) - 1} iterations, {m.gradients} Jacobians, {m.solves} solves, {m.seconds:.1f} s "
              f"({m.message}); single {len(s.history) - 1} iterations, {s.gradients} Jacobians, {s.solves} solves, "
              f"{s.seconds:.1f} s")
        print(f"    variables {v.names}: initial {np.round(e['initial'], 3)} %; max |error| multi "
              f"{np.abs(e['multi']).max():.1e} %, single {np.abs(e['single']).max():.1e} %")
        print(f"    unseen combined case, max |frequency error|: multi "
              f"{np.nanmax(np.abs(v.prediction['multi_error_percent'])):.1e} %, single "
              f"{np.nanmax(np.abs(v.prediction['single_error_percent'])):.1e} %")
        if args.trace:
            _trace(m)
    print(f"whole protocol: {time.perf_counter() - w0:.1f} s wall, {time.process_time() - c0:.1f} s CPU; "
          f"load average at end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
