"""Updating benchmark on the shell wingbox: the verification protocol's multi-configuration problem
(fg.cases.wingbox; unloaded, -1 g and 2.5 g on their post-buckled paths; 5 shell variables; 8 modes
with shapes at 24 sensors, static tip deflections, mass properties): time per evaluation, per
Jacobian and their split, and the whole update, for this tree and (--before REF) for a git
revision in the same run (each in its own process, one after the other: the machine is shared, so
compare the ratios).

    python bench/bench_wingbox_update.py --size 0.25 --before 545f121 --update --write
    python bench/bench_wingbox_update.py --size 0.1 --processes 2
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TITLE = "## Model updating: the shell wingbox (issue 31)"
PHASES = (("flexgvt.updating.problem", "solve_static", "static solve"),
          ("flexgvt.updating.problem", "real_modes", "modes"),
          ("flexgvt.updating.blocks", "state_derivatives", "state derivatives (du/dp, dR/dp, dK/dp)"),
          ("flexgvt.updating.blocks", "modal_terms", "modes' state terms (dK/du)"),
          ("flexgvt.updating.blocks", "eigenvector_derivatives", "mode-shape derivatives"),
          ("flexgvt.updating.blocks", "_adjoints", "mode-shape derivatives"),
          ("flexgvt.updating.blocks", "_solver", "factorisation for the derivatives"))


def _timed(clock: dict):
    """Wrap the PHASES' functions (where this tree has them) to add their wall time to ``clock``."""
    import importlib
    for module, name, label in PHASES:
        mod = importlib.import_module(module)
        fn = getattr(mod, name, None)
        if fn is None:
            continue

        @functools.wraps(fn)
        def wrapper(*args, _fn=fn, _label=label, **kwargs):
            t, c = time.perf_counter(), time.process_time()
            try:
                return _fn(*args, **kwargs)
            finally:
                clock[_label] += time.perf_counter() - t
                clock[_label + " (CPU)"] += time.process_time() - c
        setattr(mod, name, wrapper)


def protocol(size: float, seed: int = 1):
    """The verify('wingbox') set-up at element size ``size`` [m]."""
    import flexgvt as fg
    from flexgvt import updating as up
    from flexgvt.updating.verify import _surrogate, _wingbox_setup
    ref, sensors, variables, train, _, tip = _wingbox_setup(size)
    variables = [type(v)(v.name, v.kind, v.attribute, v.targets, (0.9, 1.1)) for v in variables]
    x_m = 1.0 + np.random.default_rng(seed).uniform(-0.05, 0.05, len(variables))
    initial = ref.model.copy("initial")
    up.Parametrisation(ref.model, train, variables).apply(initial, x_m)
    data = _surrogate(ref.model, train, sensors, 8, tip)
    mp = fg.mass_properties(ref.model)
    target = up.MassTarget(mass=mp.mass, cg=tuple(mp.cg), inertia=tuple(np.diag(mp.inertia)))
    objective = up.Objective(frequency=1.0, mac=0.1, static=0.1, mass_limits=0.10)
    return ref, initial, train, data, variables, target, objective, x_m


def measure(size: float, update: bool, processes: int | None) -> dict:
    """Timings of this process's flexgvt (see the module docstring)."""
    import warnings

    from flexgvt import updating as up
    warnings.simplefilter("ignore")
    clock: dict = defaultdict(float)
    t0 = time.perf_counter()
    ref, initial, train, data, variables, target, objective, x_m = protocol(size)
    out = {"size": size, "nodes": len(ref.model.node_ids), "setup_s": time.perf_counter() - t0}
    _timed(clock)
    problem = up.UpdatingProblem(initial, train, data, variables, target, objective)
    t = time.perf_counter()
    problem.evaluate(problem.x0)
    out["first_evaluation_s"] = time.perf_counter() - t
    evals, jacs, split_e, split_j = [], [], defaultdict(float), defaultdict(float)
    cpu_e, cpu_j = [], []
    for step in (1.01, 0.99):  # design points near the start: warm-started solves
        x = problem.x0 * step
        clock.clear()
        t, c = time.perf_counter(), time.process_time()
        problem.evaluate(x)
        evals.append(time.perf_counter() - t)
        cpu_e.append(time.process_time() - c)
        for k, v in clock.items():
            split_e[k] += v / 2
        clock.clear()
        t, c = time.perf_counter(), time.process_time()
        problem.evaluate(x, gradient=True)
        jacs.append(time.perf_counter() - t)
        cpu_j.append(time.process_time() - c)
        for k, v in clock.items():
            split_j[k] += v / 2
    out.update(evaluation_s=float(np.mean(evals)), jacobian_s=float(np.mean(jacs)),
               evaluation_cpu_s=float(np.mean(cpu_e)), jacobian_cpu_s=float(np.mean(cpu_j)),
               evaluation_split=dict(split_e), jacobian_split=dict(split_j))
    if update:
        t, c = time.perf_counter(), time.process_time()
        result = up.update(initial, train, data, variables, mass_target=target, objective=objective,
                           processes=processes)
        out.update(update_s=time.perf_counter() - t, update_cpu_s=time.process_time() - c,
                   solves=int(result.solves), gradients=int(result.gradients),
                   variable_error_percent=float(100 * np.abs(result.x * x_m - 1).max()), processes=processes)
    return out


def _before(ref: str, args) -> dict:
    """measure() of git revision ``ref`` in a child process (its src exported to a temporary folder)."""
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "archive", ref, "src", "bench"], cwd=ROOT, capture_output=True, check=True)
        subprocess.run(["tar", "-x", "-C", tmp], input=archive.stdout, check=True)
        env = dict(os.environ, PYTHONPATH=str(Path(tmp) / "src"), MPLBACKEND="Agg")
        cmd = [sys.executable, str(Path(__file__)), "--size", str(args.size), "--json"]
        cmd += ["--update"] if args.update and not args.update_after_only else []
        done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
        return json.loads(done.stdout.strip().splitlines()[-1])


def _table(runs: dict) -> str:
    names = list(runs)
    rows = [("nodes", "nodes", "{:.0f}"), ("setup (reference, configurations, data) [s]", "setup_s", "{:.1f}"),
            ("first evaluation (cold) [s]", "first_evaluation_s", "{:.2f}"),
            ("evaluation (warm) [s]", "evaluation_s", "{:.2f}"), ("Jacobian [s]", "jacobian_s", "{:.2f}"),
            ("evaluation (warm), CPU [s]", "evaluation_cpu_s", "{:.2f}"),
            ("Jacobian, CPU [s]", "jacobian_cpu_s", "{:.2f}"),
            ("whole update [s]", "update_s", "{:.0f}"),
            ("whole update, CPU of this process [s]", "update_cpu_s", "{:.0f}"), ("solves / Jacobians", None, None),
            ("largest variable error [%]", "variable_error_percent", "{:.3f}")]
    head = "| | " + " | ".join(names) + (" | ratio |" if len(names) == 2 else " |")
    lines = [head, "|---" * (len(names) + 1 + (len(names) == 2)) + "|"]
    for label, key, fmt in rows:
        if key is None:
            cells = [f"{r['solves']} / {r['gradients']}" if "solves" in r else "" for r in runs.values()]
            ratio = ""
        else:
            vals = [r.get(key) for r in runs.values()]
            cells = [fmt.format(v) if v is not None else "" for v in vals]
            ratio = (f"{vals[0] / vals[1]:.1f}x" if len(vals) == 2 and None not in vals and vals[1] and
                     key.endswith("_s") else "")
        lines.append(f"| {label} | " + " | ".join(cells) + (f" | {ratio} |" if len(names) == 2 else " |"))
    for which, key in (("evaluation", "evaluation_split"), ("Jacobian", "jacobian_split")):
        labels = sorted({k for r in runs.values() for k in r[key]})
        for lab in labels:
            vals = [r[key].get(lab, 0.0) for r in runs.values()]
            ratio = f"{vals[0] / vals[1]:.1f}x" if len(vals) == 2 and vals[1] > 0 else ""
            lines.append(f"| {which}: {lab} [s] | " + " | ".join(f"{v:.2f}" for v in vals)
                         + (f" | {ratio} |" if len(names) == 2 else " |"))
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, default=0.25, help="element size [m]")
    ap.add_argument("--before", help="a git revision measured in the same run (its own process)")
    ap.add_argument("--update", action="store_true", help="also time the whole multi-configuration update")
    ap.add_argument("--update-after-only", action="store_true", help="the whole update for this tree only")
    ap.add_argument("--processes", type=int, help="worker processes for the whole update")
    ap.add_argument("--json", action="store_true", help="print one JSON line (used for --before)")
    ap.add_argument("--write", action="store_true", help="rewrite docs/benchmarks.md's section")
    args = ap.parse_args()
    if args.json:
        print(json.dumps(measure(args.size, args.update, args.processes)))
        return
    sys.path.insert(0, str(ROOT / "bench"))
    from benchdoc import machine_info, write_section
    runs = {}
    load0 = os.getloadavg()[0]
    if args.before:
        runs[f"before ({args.before})"] = _before(args.before, args)
    runs["this tree"] = measure(args.size, args.update or args.update_after_only, args.processes)
    load1 = os.getloadavg()[0]
    cpu, cores, vers = machine_info(("numpy", "scipy", "numba", "flexgvt"))
    text = (f"{TITLE}\n\n`python bench/bench_wingbox_update.py --size {args.size}"
            + (f" --before {args.before}" if args.before else "") + (" --update" if args.update else "")
            + (" --update-after-only" if args.update_after_only else "")
            + (f" --processes {args.processes}" if args.processes else "") + "`: "
            f"{cpu}, {cores} cores, load average {load0:.1f} at the start and {load1:.1f} at the end "
            f"(shared machine: compare the ratios); {', '.join(f'{k} {v}' for k, v in vers.items())}.\n\n"
            + _table(runs) + "\n")
    print(text)
    if args.write:
        write_section(TITLE + (f" at {args.size} m" if args.size != 0.25 else ""), text.replace(
            TITLE, TITLE + (f" at {args.size} m" if args.size != 0.25 else ""), 1))


if __name__ == "__main__":
    main()
