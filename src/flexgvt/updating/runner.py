"""`update()`: the model updated against measured data in several configurations at once."""

from __future__ import annotations

import time
import warnings
from dataclasses import replace
from typing import Callable, Sequence

import numpy as np

from ..errors import FlexGVTWarning, ModelError, SolverError, UpdatingError
from ..fem import StaticSettings
from ..model import Configuration, Model
from .optimise import as_reference, minimise, reference_arrays, starting_points
from .parallel import single_threaded
from .problem import UpdatingProblem
from .store import ResultsStore, fingerprint, pack, unpack
from .settings import OptimiserSettings, renamed
from .result import UpdateResult, configuration_tables, identifiability, variable_table
from .targets import MassTarget, Measured, Objective
from .variables import Variable


def update(model: Model, configurations: Sequence[Configuration], measured: Sequence[Measured],
           variables: Sequence[Variable], *, mass_target: MassTarget | None = None,
           objective: Objective | None = None, method: str = OptimiserSettings.method,
           starts: int = OptimiserSettings.starts, seed: int = OptimiserSettings.seed,
           max_iterations: int = OptimiserSettings.max_iterations, tolerance: float = OptimiserSettings.tolerance,
           n_modes: int | None = OptimiserSettings.n_modes,
           min_paired_fraction: float = OptimiserSettings.min_paired_fraction,
           unidentifiable: str = OptimiserSettings.unidentifiable,
           max_relative_std: float = OptimiserSettings.max_relative_std, static_settings: StaticSettings | None = None,
           store: ResultsStore | None = None,
           progress: Callable[[dict], None] | None = None, processes: int | None = None,
           scheduler: str | None = None, callback: Callable[[dict], None] | None = None) -> UpdateResult:
    """Update ``model`` so that its pre-stressed modes in every configuration match the measured ones.

    configurations: the test configurations (each with measured data); measured: one Measured per
    configuration; variables: design variables (flexgvt.updating.beam/mass/spring/cord);
    mass_target: measured mass properties; objective: weights and constraints; method:
    'least_squares' (default; alias 'lm': SciPy's least_squares with MINPACK's Levenberg-Marquardt on
    the residual vector and its exact Jacobian, continued by the bounded dogbox trust region from
    its answer if that lies outside the bounds; dogbox alone when there are fewer residuals than
    variables), 'dogbox' or 'trf' (SciPy's bounded trust regions
    from the start), 'slsqp', 'trust-constr' (analytic
    gradients, constraints enforced), 'nelder-mead' (penalties, no gradients); starts: multi-start
    count (x0 = 1 plus seeded uniform points in the bounds; the best run wins, and of runs equal to
    the tolerance the one nearest x0); store: a
    flexgvt.updating.ResultsStore (SQLite) for the history and resuming; progress: called with each
    accepted iterate's history row (``callback``: its deprecated name); processes / scheduler:
    evaluate the configurations in that many local worker processes, or on a dask.distributed
    scheduler at that address (multi-start runs then run as parallel tasks instead); serial by
    default, which is faster for models of up to a few thousand elements (docs/benchmarks.md).
    The input model is not changed: the result holds an updated copy. The optimiser's defaults and
    limits are flexgvt.updating.OptimiserSettings'.

    Measured modes that do not pair are reported with their reason (FlexGVTWarning,
    UpdateResult.unpaired, the tables' unpaired_reason); fewer than ``min_paired_fraction`` of a
    configuration's measured modes paired with the initial model's raises UpdatingError naming
    them. Variables the data do not constrain (flexgvt.updating.result.judge, with
    ``max_relative_std``) are held at their initial value and the problem is solved again without
    them (``unidentifiable='fix'``, up to three times), or only flagged (``'free'``); each row of
    UpdateResult.variables says whether its variable is identifiable and, if not, why.
    """
    from .parallel import attach_workers, client_for
    if callback is not None:
        renamed("update(callback=...)", "update(progress=...)")
        progress = progress or callback
    OptimiserSettings(method=method, starts=starts, seed=seed, max_iterations=max_iterations, tolerance=tolerance,
                      n_modes=n_modes, min_paired_fraction=min_paired_fraction, unidentifiable=unidentifiable,
                      max_relative_std=max_relative_std)  # checks each value
    t0 = time.perf_counter()
    problem = UpdatingProblem(model, configurations, measured, variables, mass_target, objective, n_modes,
                              static_settings)
    outside = [v.name for v in problem.par.variables if not v.bounds[0] <= 1.0 <= v.bounds[1]]
    if outside:
        raise ModelError(f"updating: the initial point (x = 1) lies outside the bounds of {outside}; widen the "
                         "bounds to include the initial model or change the initial model")
    settings = dict(method=method, starts=starts, seed=seed, max_iterations=max_iterations, tolerance=tolerance,
                    store=store, progress=progress, max_relative_std=max_relative_std)
    with client_for(processes, scheduler) as client:
        if client is not None and starts <= 1:
            attach_workers(problem, client)
        first = _run(problem, model, client=client, min_paired_fraction=min_paired_fraction, **settings)
        stages, held, notes = [(problem, first)], {}, []
        while unidentifiable == "fix" and len(stages) <= MAX_RESOLVES:
            last_problem, last = stages[-1]
            ident = last.identifiability
            out = [k for k, ok in enumerate(ident["identifiable"]) if not ok]
            if not out:
                break
            for k in out:
                held[last_problem.par.names[k]] = last.variables[k]
            free = [v for v in problem.par.variables if v.name not in held]
            lines = "".join(f"\n  {last_problem.par.names[k]}: {ident['reasons'][k]}" for k in out)
            notes.append(f"updating: {len(out)} variable(s) the data do not constrain are held at their initial "
                         f"value, and the problem is solved again with the other {len(free)} "
                         f"(unidentifiable='free' leaves them free):{lines}")
            warnings.warn(notes[-1], FlexGVTWarning, stacklevel=2)
            if not free:
                break
            again = UpdatingProblem(model, configurations, measured, free, mass_target, objective, n_modes,
                                    static_settings)
            if client is not None and starts <= 1:
                attach_workers(again, client)
            # From the last answer (the held variables back at 1): the free ones keep what the data
            # gave them. Not stored: its start depends on the last solve, which the store's key does not.
            start = np.array([last.x[last_problem.par.names.index(v.name)] for v in free])
            stages.append((again, _run(again, model, client=client, min_paired_fraction=0.0,
                                       **{**settings, "store": None}, start=start)))
        result = _merge(problem, model, stages, held) if held else first
    loose = [r["name"] for r in result.variables if not r["identifiable"] and not r.get("fixed")]
    if loose and unidentifiable == "fix":
        notes.append(f"updating: {loose} are still not identifiable after {MAX_RESOLVES} solves without the "
                     "variables found unconstrained; they are left free and flagged (see their rows' reasons)")
        warnings.warn(notes[-1], FlexGVTWarning, stacklevel=2)
    result.warnings = notes
    _warn_unpaired(result)
    _warn_unstable(result, [p for p, _ in stages])
    result.seconds = time.perf_counter() - t0
    return result


MAX_RESOLVES = 3  # solves again without the variables found unconstrained, at most this often


def _unpaired(problem: UpdatingProblem, point) -> dict[str, list[dict]]:
    """{configuration: the reasons (Unpaired.to_dict) of its measured modes left unpaired at point}."""
    return {name: [u.to_dict() for u in problem.pairing.explain(problem.measured[name], c)]
            for name, c in point.configurations.items() if np.any(c.paired < 0)}


def _check_pairing(problem: UpdatingProblem, initial, min_paired_fraction: float) -> None:
    """UpdatingError when fewer than min_paired_fraction of a configuration's measured modes pair."""
    bad = []
    for name, rows in _unpaired(problem, initial).items():
        n = len(problem.measured[name].frequencies_hz)
        if n - len(rows) < min_paired_fraction * n:
            lines = "\n".join(f"    mode {r['mode']}{' (' + r['label'] + ')' if r['label'] else ''} at "
                               f"{r['measured_hz']:.4g} Hz: {r['text']}" for r in rows)
            bad.append(f"  configuration '{name}': {n - len(rows)} of {n} measured modes pair\n{lines}")
    if bad:
        raise UpdatingError(
            "updating: fewer than {:.0%} (min_paired_fraction) of a configuration's measured modes pair with the "
            "initial model's:\n{}\nMend the cause (the test points' mapping to FE nodes, the labels, n_modes, "
            "mac_floor or max_frequency_ratio), or update on the modes that do pair by lowering "
            "min_paired_fraction: update(..., min_paired_fraction=0), or in a project file "
            "[optimiser] min_paired_fraction = 0"
            .format(min_paired_fraction, "\n".join(bad)))


def _warn_unstable(result: UpdateResult, problems: list[UpdatingProblem]) -> None:
    """One FlexGVTWarning per configuration whose equilibrium was unstable at some design points
    evaluated in this process: its loads pass a bifurcation with nothing to choose the branch, and a
    solve warm-started from an unstable state can stay on it, so its residuals follow the solves'
    history; the same lines go to result.warnings."""
    counts: dict[str, int] = {}
    for problem in problems:
        for name, n in problem.unstable.items():
            counts[name] = counts.get(name, 0) + n
    for name, n in counts.items():
        text = (f"updating: configuration '{name}': the equilibrium was unstable (a negative eigenvalue of its "
                f"tangent) at {n} of the design points evaluated: its loads pass a bifurcation with nothing to "
                "choose the branch, and the residuals there depend on where each solve started. Give the "
                "configuration the imperfection a test article has (Configuration.imperfection; the one "
                "solve_static(..., settings=StaticSettings(buckling='continue')) finds is in its state's "
                "configuration), or lower its loads below the bifurcation")
        result.warnings.append(text)
        warnings.warn(text, FlexGVTWarning, stacklevel=3)


def _warn_unpaired(result: UpdateResult) -> None:
    """One FlexGVTWarning listing the measured modes left unpaired (at the initial model, and at the
    updated one where that differs); the same lines go to result.warnings."""
    for when, label in (("initial", "the initial model"), ("updated", "the updated model")):
        table = result.unpaired.get(when, {})
        if not table or (when == "updated" and table == result.unpaired.get("initial")):
            continue
        lines = [f"  configuration '{name}', mode {r['mode']}{' (' + r['label'] + ')' if r['label'] else ''} at "
                 f"{r['measured_hz']:.4g} Hz: {r['text']}" for name, rows in table.items() for r in rows]
        text = (f"updating: {len(lines)} measured mode(s) do not pair with {label}'s and are left out of the "
                "objective:\n" + "\n".join(lines))
        result.warnings.append(text)
        warnings.warn(text, FlexGVTWarning, stacklevel=3)


def _merge(problem: UpdatingProblem, model: Model, stages: list, held: dict[str, dict]) -> UpdateResult:
    """The result over every variable: the last stage's answer for the free ones, the initial value
    for those held (their rows say why), the first stage's rank and singular values."""
    last_problem, last = stages[-1]
    first = stages[0][1]
    names = problem.par.names
    if len(held) == len(names):  # nothing left to update: the initial model, evaluated
        updated = model.copy(f"{model.name} (updated)")
        configs = problem.par.apply(updated, problem.x0)
        base = replace(first, model=updated, configurations=configs, x=problem.x0.copy(), final=first.initial,
                       tables=configuration_tables(problem, first.initial, first.initial),
                       mac={n: None if m is None else (m[0], m[0]) for n, m in first.mac.items()},
                       history=first.history[:1], message="every variable held: nothing left to update")
        free_index = {}
    else:
        base = last
        free_index = {n: k for k, n in enumerate(last_problem.par.names)}
    rows, x, std, ok, why = [], np.ones(len(names)), [], [], []
    for k, name in enumerate(names):
        if name in held:
            r = dict(held[name])
            r.update(final=r["initial"], x=1.0, change_percent=0.0 if r["initial"] else None, at_bound=False,
                     identifiable=False, fixed=True)
        else:
            r = dict(base.variables[free_index[name]])
            x[k] = base.x[free_index[name]]
        rows.append(r)
        std.append(r["std_normalised"])
        ok.append(r["identifiable"])
        why.append(r["reason"])
    ident = dict(first.identifiability)
    ident.update(std_normalised=np.array(std, float), identifiable=np.array(ok, bool), reasons=why,
                 unidentifiable=[n for n, o in zip(names, ok) if not o], held=list(held),
                 sigma_source=base.identifiability.get("sigma_source"),
                 final={k: base.identifiability.get(k) for k in ("rank", "n_variables", "condition_number")})
    history = [{**h, "x": [h["x"][free_index[n]] if n in free_index else 1.0 for n in names]}
               for h in base.history] if free_index else base.history
    stage_rows = [{"variables": list(p.par.names), "objective": {"initial": r.initial.objective,
                                                                 "final": r.final.objective},
                   "iterations": len(r.history) - 1, "message": str(r.message), "solves": r.solves}
                  for p, r in stages]
    final = base.final
    if free_index:  # the answer over every variable: the held ones' columns zero (the data do not see them)
        cols = [free_index.get(n) for n in names]

        def wide(A):
            if A is None:
                return None
            out = np.zeros((A.shape[0], len(names)))
            for k, c in enumerate(cols):
                if c is not None:
                    out[:, k] = A[:, c]
            return out
        final = replace(final, x=x.copy(), jacobian=wide(final.jacobian),
                        constraint_jacobian=wide(final.constraint_jacobian))
    return replace(base, x=x, variables=rows, identifiability=ident, history=history, final=final,
                   initial=first.initial,
                   solves=sum(r.solves for _, r in stages), gradients=sum(r.gradients for _, r in stages),
                   stages=stage_rows, warnings=[],
                   # every stage's starts: the first (stored, resumable) one says whether the run resumed
                   starts=[s for _, r in stages for s in r.starts],
                   unpaired=last.unpaired if base is last else {"initial": first.unpaired.get("initial", {}),
                                                                 "updated": first.unpaired.get("initial", {})})


def _best_run(runs: list[dict], x0: np.ndarray, slack: float) -> dict:
    """The run with the least objective; among runs within ``slack`` of it (the tolerance times the
    initial objective: answers equal to round-off, as when several starts fit the data exactly with
    more variables than data), the one nearest the initial point, so that what the data do not
    decide stays nearest where it started and round-off does not choose the answer."""
    best = min(runs, key=lambda r: r["objective"])
    if not np.isfinite(best["objective"]):
        return best
    tied = [r for r in runs if r["objective"] <= best["objective"] + slack]
    return min(tied, key=lambda r: (float(np.linalg.norm(np.asarray(r["x"], float) - x0)), r["objective"]))


def _run(problem, model, *, method, starts, seed, max_iterations, tolerance, store, progress, client,
         min_paired_fraction, max_relative_std, start=None) -> UpdateResult:
    initial = problem.evaluate(problem.x0, gradient=True)
    _check_pairing(problem, initial, min_paired_fraction)
    # Every start pairs the measured modes against the initial point's pairing, and the answer is
    # evaluated with the winning run's own: runs that explored elsewhere do not relabel it.
    reference = problem.reference_of(initial)
    if store is not None:
        store.bind(fingerprint(problem, method))
    runs = []
    limits = {"max_iterations": int(max_iterations), "tolerance": float(tolerance)}  # a change continues the run
    points = starting_points(problem, max(1, starts), seed)
    if start is not None:
        points[0] = start
    for run, x0 in enumerate(points):
        done = store.finished(run, limits) if store is not None else None
        if done is not None:  # finished before: its answer, evaluated from where the run evaluated it
            ref = reference if done["reference"] is None else as_reference(problem, unpack(done["reference"]))
            problem.set_pairing_reference(ref)
            runs.append({"x": done["x"], "history": store.history(run), "message": done["message"],
                         "success": done["success"],
                         "evaluations": 0, "failures": [], "method": done["method"], "resumed": True,
                         "objective": problem.evaluate(done["x"]).objective, "x0": np.asarray(x0).tolist(),
                         "reference": ref if done["reference"] is not None else
                         problem.reference_of(problem.evaluate(done["x"]))})
            continue
        if client is not None and starts > 1:  # independent runs as parallel tasks, collected below
            runs.append(client.submit(_remote_start, problem, x0, method, max_iterations, tolerance, pure=False))
            continue
        # An interrupted run starts again from x0 too: the store answers the evaluations it recorded.
        problem.set_pairing_reference(reference, keep=initial if run == 0 and start is None else None)
        try:
            out = minimise(problem, x0, method, store=store, run=run, max_iterations=max_iterations,
                           tolerance=tolerance, progress=progress)
        except SolverError as exc:
            if run == 0:  # the user's own starting point: nothing to compare with, say why
                raise
            runs.append(_unsolved_start(x0, x0, method, exc))  # the other starts go on
            continue
        # Without a store nothing evaluates the answer again later: its own solve is the final point
        # (kept with its Jacobian). With one, it is solved again from the stored warm start, as a
        # later call that finds the run finished does, so that both give the same numbers.
        problem.set_pairing_reference(out["reference"], keep=out.get("point") if store is None else None)
        out["objective"] = problem.evaluate(out["x"]).objective
        out["resumed"] = out.get("replayed", 0) > 0
        out["x0"] = np.asarray(x0).tolist()
        if store is not None:
            store.finish(run, out["x"], out["objective"], out["method"], str(out["message"]),
                         reference=pack(reference_arrays(out["reference"])), iterations=len(out["history"]),
                         success=bool(out["success"]), limits=limits)
            out["history"] = store.history(run)
        runs.append(out)
    for run, item in enumerate(runs):
        if not isinstance(item, dict):  # a parallel start
            out = item.result()
            if out.get("unsolved"):
                runs[run] = out
                continue
            problem.set_pairing_reference(out["reference"])
            out["objective"] = problem.evaluate(out["x"]).objective
            out["resumed"] = False
            if store is not None:
                store.finish(run, out["x"], out["objective"], out["method"], str(out["message"]), limits=limits)
            runs[run] = out
    best = _best_run(runs, problem.x0, tolerance * initial.objective)
    if not np.isfinite(best["objective"]):
        raise SolverError("updating: no starting point could be solved; the first failure: "
                          + best["failures"][0][1])
    problem.set_pairing_reference(best.get("reference") or reference,
                                  keep=best.get("point") if store is None else None)
    final = problem.evaluate(best["x"], gradient=True)
    ident = identifiability(problem, final, max_relative_std)
    updated = model.copy(f"{model.name} (updated)")
    configs = problem.par.apply(updated, final.x)
    mac = {}
    for name, p in final.configurations.items():
        a = initial.configurations[name]
        mac[name] = None if p.mac_matrix is None else (a.mac_matrix, p.mac_matrix)
    return UpdateResult(
        model=updated, configurations=configs, x=final.x.copy(), variables=variable_table(problem, final.x, ident),
        tables=configuration_tables(problem, initial, final, problem.pairing), mac=mac, history=best["history"],
        identifiability=ident, initial=initial, final=final, method=best["method"], message=best["message"],
        success=best["success"], seconds=0.0, solves=problem.n_solves,
        gradients=problem.n_gradients,
        starts=[{"run": k, "x0": r["x0"], "x": np.asarray(r["x"], float).tolist(), "objective": r["objective"],
                 "message": r["message"],
                 "evaluations": r["evaluations"], "failures": len(r["failures"]), "resumed": r["resumed"]}
                for k, r in enumerate(runs)],
        unpaired={"initial": _unpaired(problem, initial), "updated": _unpaired(problem, final)})


def _unsolved_start(start, x0, method: str, exc: Exception) -> dict:
    """A multi-start run whose random start the structure cannot be solved at: reported in
    UpdateResult.starts, never the answer."""
    return {"x": np.asarray(start, float), "history": [], "message": f"start not solved: {exc}", "success": False,
            "evaluations": 1, "failures": [(np.asarray(start, float), str(exc))], "method": method,
            "resumed": False, "objective": np.inf, "x0": np.asarray(x0).tolist(), "unsolved": True}


@single_threaded
def _remote_start(problem, x0, method, max_iterations, tolerance) -> dict:
    """One multi-start run in a worker (a copy of the problem travels with the task)."""
    try:
        out = minimise(problem, np.asarray(x0, float), method, max_iterations=max_iterations, tolerance=tolerance)
    except SolverError as exc:
        return _unsolved_start(x0, x0, method, exc)
    out["reference"] = {"pairing": out["reference"]["pairing"], "states": {}}  # states stay in the worker
    out["point"] = None
    out["x0"] = np.asarray(x0).tolist()
    out["history"] = [{k: v for k, v in row.items()} for row in out["history"]]
    return out
