"""`update()`: the model updated against measured data in several configurations at once."""

from __future__ import annotations

import time
from typing import Callable, Sequence

import numpy as np

from ..errors import ModelError, SolverError
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
           n_modes: int | None = OptimiserSettings.n_modes, static_settings: StaticSettings | None = None,
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
    count (x0 = 1 plus seeded uniform points in the bounds; the best run wins); store: a
    flexgvt.updating.ResultsStore (SQLite) for the history and resuming; progress: called with each
    accepted iterate's history row (``callback``: its deprecated name); processes / scheduler:
    evaluate the configurations in that many local worker processes, or on a dask.distributed
    scheduler at that address (multi-start runs then run as parallel tasks instead); serial by
    default, which is faster for models of up to a few thousand elements (docs/benchmarks.md).
    The input model is not changed: the result holds an updated copy. The optimiser's defaults and
    limits are flexgvt.updating.OptimiserSettings'.
    """
    from .parallel import attach_workers, client_for
    if callback is not None:
        renamed("update(callback=...)", "update(progress=...)")
        progress = progress or callback
    OptimiserSettings(method, starts, seed, max_iterations, tolerance, n_modes)  # checks each value
    t0 = time.perf_counter()
    problem = UpdatingProblem(model, configurations, measured, variables, mass_target, objective, n_modes,
                              static_settings)
    outside = [v.name for v in problem.par.variables if not v.bounds[0] <= 1.0 <= v.bounds[1]]
    if outside:
        raise ModelError(f"updating: the initial point (x = 1) lies outside the bounds of {outside}; widen the "
                         "bounds to include the initial model or change the initial model")
    with client_for(processes, scheduler) as client:
        if client is not None and starts <= 1:
            attach_workers(problem, client)
        result = _run(problem, model, method, starts, seed, max_iterations, tolerance, store, progress, client)
    result.seconds = time.perf_counter() - t0
    return result


def _run(problem, model, method, starts, seed, max_iterations, tolerance, store, progress, client) -> UpdateResult:
    initial = problem.evaluate(problem.x0, gradient=True)
    # Every start pairs the measured modes against the initial point's pairing, and the answer is
    # evaluated with the winning run's own: runs that explored elsewhere do not relabel it.
    reference = problem.reference_of(initial)
    if store is not None:
        store.bind(fingerprint(problem, method))
    runs = []
    limits = {"max_iterations": int(max_iterations), "tolerance": float(tolerance)}  # a change continues the run
    for run, x0 in enumerate(starting_points(problem, max(1, starts), seed)):
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
        problem.set_pairing_reference(reference)
        try:
            out = minimise(problem, x0, method, store=store, run=run, max_iterations=max_iterations,
                           tolerance=tolerance, progress=progress)
        except SolverError as exc:
            if run == 0:  # the user's own starting point: nothing to compare with, say why
                raise
            runs.append(_unsolved_start(x0, x0, method, exc))  # the other starts go on
            continue
        problem.set_pairing_reference(out["reference"])
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
    best = min(runs, key=lambda r: r["objective"])
    if not np.isfinite(best["objective"]):
        raise SolverError("updating: no starting point could be solved; the first failure: "
                          + best["failures"][0][1])
    problem.set_pairing_reference(best.get("reference") or reference)
    final = problem.evaluate(best["x"], gradient=True)
    ident = identifiability(problem, final)
    updated = model.copy(f"{model.name} (updated)")
    configs = problem.par.apply(updated, final.x)
    mac = {}
    for name, p in final.configurations.items():
        a = initial.configurations[name]
        mac[name] = None if p.mac_matrix is None else (a.mac_matrix, p.mac_matrix)
    return UpdateResult(
        model=updated, configurations=configs, x=final.x.copy(), variables=variable_table(problem, final.x, ident),
        tables=configuration_tables(problem, initial, final), mac=mac, history=best["history"],
        identifiability=ident, initial=initial, final=final, method=best["method"], message=best["message"],
        success=best["success"], seconds=0.0, solves=problem.n_solves,
        gradients=problem.n_gradients,
        starts=[{"run": k, "x0": r["x0"], "objective": r["objective"], "message": r["message"],
                 "evaluations": r["evaluations"], "failures": len(r["failures"]), "resumed": r["resumed"]}
                for k, r in enumerate(runs)])


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
    out["x0"] = np.asarray(x0).tolist()
    out["history"] = [{k: v for k, v in row.items()} for row in out["history"]]
    return out
