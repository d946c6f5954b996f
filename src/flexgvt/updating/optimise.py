"""Optimiser drivers: sensitivity-based least squares (default: Levenberg-Marquardt, continued
inside the bounds by a trust region when needed), SLSQP and trust-constr with analytic
gradients, Nelder-Mead with penalties (the original work's baseline), multi-start.

A design point where a configuration does not converge returns non-finite residuals to SciPy's
trust regions (they shrink the step and try again), large residuals to Levenberg-Marquardt (the
step is rejected and the damping raised) and a large objective to the scalar methods; the
optimiser never sees an exception from the solver.
"""

from __future__ import annotations

import json
import time
from dataclasses import replace
from typing import Callable

import numpy as np
from scipy.optimize import Bounds, NonlinearConstraint, least_squares, minimize

from ..errors import ModelError, SolverError
from .problem import DesignPointFailure, Point, UpdatingProblem
from .settings import METHODS, OptimiserSettings
from .store import pack, unpack

_PENALTY = 1e3  # weight of a violated constraint in the penalised objectives


class _Replayed:
    """An evaluation answered from the store: what the optimiser received, without the structure."""

    def __init__(self, x: np.ndarray, data: dict):
        self.x = x
        self.residuals = data["residuals"]
        self.constraints = data["constraints"]
        self.jacobian = data.get("jacobian")
        self.constraint_jacobian = data.get("constraint_jacobian")
        self.summary = json.loads(str(data["summary"]))
        self.configurations = None

    @property
    def objective(self) -> float:
        return float(self.residuals @ self.residuals)


def continuation(problem: UpdatingProblem) -> dict[str, np.ndarray]:
    """What the next evaluation of ``problem`` depends on besides x, as arrays: each configuration's
    last equilibrium (the warm start: positions, rotations) and pairing reference (fit, shapes)."""
    return reference_arrays({"states": problem.states, "pairing": problem.pairing.reference})


def reference_arrays(reference: dict) -> dict[str, np.ndarray]:
    """A pairing reference (UpdatingProblem.reference_of) as arrays, continuation's layout."""
    out = {}
    for k, (name, s) in enumerate(sorted(reference.get("states", {}).items())):
        out[f"state_name{k}"], out[f"positions{k}"], out[f"rotations{k}"] = np.array(name), s.positions, s.rotations
    for k, (name, (fit, shapes)) in enumerate(sorted(reference.get("pairing", {}).items())):
        out[f"pair_name{k}"], out[f"fit{k}"], out[f"shapes{k}"] = np.array(name), np.array(fit, float), shapes
    return out


def as_reference(problem: UpdatingProblem, arrays: dict[str, np.ndarray]) -> dict:
    """continuation / reference_arrays back into a reference for set_pairing_reference: the states
    are the problem's own (their compiled systems) at the stored positions and rotations."""
    states, pairing = {}, {}
    k = 0
    while f"state_name{k}" in arrays:
        name = str(arrays[f"state_name{k}"])
        if name in problem.states:
            states[name] = replace(problem.states[name], positions=arrays[f"positions{k}"].copy(),
                                   rotations=arrays[f"rotations{k}"].copy())
        k += 1
    k = 0
    while f"pair_name{k}" in arrays:
        pairing[str(arrays[f"pair_name{k}"])] = (float(arrays[f"fit{k}"]), arrays[f"shapes{k}"].copy())
        k += 1
    return {"states": states, "pairing": pairing}


def _restore(problem: UpdatingProblem, arrays: dict[str, np.ndarray]) -> None:
    """Set the problem's continuation (warm starts and pairing references) exactly to ``arrays``."""
    ref = as_reference(problem, arrays)
    problem.states.update(ref["states"])
    problem.pairing.reference = ref["pairing"]
    problem.cache.clear()


class _Driver:
    """Wraps the problem for SciPy: caching, failure handling, history and the store.

    Every evaluation is numbered; with a store, each is recorded with what SciPy received and the
    problem's continuation after it (see flexgvt.updating.store). A repeated design point is
    answered from this record, and a Jacobian asked for at a point solved before without one is
    computed from that point's own continuation, so the numbers never depend on what was cached:
    a resumed run, answered from the store up to where the first one stopped, goes on exactly as
    the uninterrupted run did.
    """

    def __init__(self, problem: UpdatingProblem, store=None, run: int = 0, progress: Callable | None = None):
        self.problem = problem
        self.store = store
        self.run = run
        self.progress = progress
        self.history: list[dict] = []
        self.failures: list[tuple[np.ndarray, str]] = []
        self.best: Point | _Replayed | None = None  # lowest objective plus constraint penalty seen
        self.best_seq = -1
        self.best_merit = np.inf
        self.best_fresh = False  # the best point was solved in this run from continuation_before(best_seq)
        self.evaluations = 0
        self.replayed = 0
        self.failure_value = np.nan  # residuals returned at a design point that cannot be solved
        self.log = store.evaluations(run) if store is not None else []
        self.stored_history = {int(r["iteration"]): r for r in store.history(run)} if store is not None else {}
        self.rows: list[dict] = []  # this run's evaluations: key, gradient, data, continuation
        self.setup = continuation(problem)  # the continuation before the first evaluation

    # ---------------------------------------------------------------- evaluations
    def point(self, x, gradient=False) -> Point | _Replayed | None:
        x = self.problem.par.check(np.array(x, float))
        seq = self.evaluations
        self.evaluations += 1
        key = x.tobytes()
        row = self._replay(seq, key, gradient)
        if row is None:
            row = self._compute(seq, x, key, gradient)
        self.rows.append(row)
        data = row["data"]
        if "failure" in data:
            self.failures.append((x.copy(), str(data["failure"])))
            return None
        p = row.pop("point", None) or _Replayed(x.copy(), data)  # the record keeps no structures (memory)
        merit = p.objective + _PENALTY * float(np.sum(np.maximum(0.0, -p.constraints) ** 2))
        par = self.problem.par
        inside = bool(np.all(p.x >= par.lower - 1e-12) and np.all(p.x <= par.upper + 1e-12))
        if inside and (self.best is None or merit < self.best_merit):  # an unbounded method's excursion never wins
            self.best, self.best_merit, self.best_seq = p, merit, seq
            self.best_fresh = bool(row.get("fresh")) and isinstance(p, Point)
        return p

    def _replay(self, seq: int, key: bytes, gradient: bool) -> dict | None:
        """Evaluation ``seq`` from the store when the record has it (same x, a Jacobian if asked)."""
        if seq >= len(self.log):
            if self.log and seq == len(self.log):  # the record ends here: where the first run stopped
                _restore(self.problem, self._continuation_before(seq))
            return None
        row = self.log[seq]
        if row["x"] == key and (row["gradient"] or not gradient):
            self.replayed += 1
            return {"key": key, "gradient": row["gradient"], "data": row["data"], "continuation": row["continuation"]}
        # The run no longer follows the record (numerics changed since): compute on from here.
        self.store.discard(self.run, seq, len(self.history))
        del self.log[seq:]
        self.stored_history = {}
        _restore(self.problem, self._continuation_before(seq))
        return None

    def _continuation_before(self, seq: int) -> dict[str, np.ndarray]:
        for row in reversed(self.rows[:seq]):
            if row["continuation"] is not None:
                c = row["continuation"]
                return unpack(c) if isinstance(c, bytes) else c
        return self.setup

    def _compute(self, seq: int, x: np.ndarray, key: bytes, gradient: bool) -> dict:
        before = [r for r in self.rows if r["key"] == key]
        if before and (before[-1]["gradient"] or not gradient):  # asked before: the same answer
            row = {**before[-1], "continuation": None}
        elif before:  # solved before without a Jacobian: its Jacobian, about that very solve
            hit = self.problem.cache.get(key)
            if hit is not None:  # the solve is at hand (evaluate leaves the continuation alone then)
                row = self._evaluate(x, key, True)
            else:  # that solve again, from its own warm start: the same numbers
                first = next(i for i, r in enumerate(self.rows) if r["key"] == key)
                now = self._continuation_before(len(self.rows))
                _restore(self.problem, self._continuation_before(first))
                row = self._evaluate(x, key, True)
                _restore(self.problem, now)
            row["continuation"] = None
        else:
            row = self._evaluate(x, key, gradient)
        if self.store is not None:
            cont = row["continuation"]
            self.store.record_evaluation(self.run, seq, x, row["gradient"], row["data"],
                                         None if cont is None else pack(cont))
        return row

    def _evaluate(self, x: np.ndarray, key: bytes, gradient: bool) -> dict:
        fresh = self.problem.cache.get(key) is None  # solved now, from the continuation at hand
        try:
            p = self.problem.evaluate(x, gradient=gradient)
        except DesignPointFailure as exc:
            return {"key": key, "gradient": gradient, "data": {"failure": np.array(str(exc))},
                    "continuation": continuation(self.problem)}
        data = {"residuals": p.residuals, "constraints": p.constraints, "summary": np.array(json.dumps(_summary(p)))}
        if gradient:
            data["jacobian"], data["constraint_jacobian"] = p.jacobian, p.constraint_jacobian
        return {"key": key, "gradient": gradient, "data": data, "continuation": continuation(self.problem),
                "point": p, "fresh": fresh}

    def best_reference(self) -> dict:
        """The pairing reference of the best point (UpdatingProblem.reference_of), from that point
        solved again from its own warm start: the same whether it was computed or replayed (a point
        solved in this run from that very warm start is its own answer: not solved again)."""
        if self.best_fresh:
            return self.problem.reference_of(self.best)
        _restore(self.problem, self._continuation_before(self.best_seq))
        return self.problem.reference_of(self.problem.evaluate(np.asarray(self.best.x, float)))

    def record(self, p: Point | _Replayed) -> None:
        """One accepted iterate: history row and a store transaction."""
        k = len(self.history)
        summary = p.summary if p.configurations is None else _summary(p)
        row = {"iteration": k, "x": p.x.tolist(), "objective": p.objective,
               "residuals": p.residuals.tolist(), "time_s": time.perf_counter(), **summary}
        self.history.append(row)
        old = self.stored_history.get(k)
        if self.store is not None and (old is None or old["x"] != row["x"]):
            self.store.record(self.run, row)
        if self.progress is not None:
            self.progress(row)

    # ---------------------------------------------------------------- least squares
    def residuals(self, x):
        p = self.point(x)
        if p is None:
            return np.full(self._n_res, self.failure_value)
        r = np.r_[p.residuals, self._penalties(p)]
        if not self.history or p.objective < self.history[-1]["objective"]:
            self.record(p)
        return r

    def jacobian(self, x):
        p = self.point(x, gradient=True)
        if p is None:  # cannot happen after residuals() succeeded at x; keep SciPy going anyway
            return np.zeros((self._n_res, len(x)))
        return np.vstack([p.jacobian, self._penalty_jacobian(p)])

    def _penalties(self, p: Point) -> np.ndarray:
        """Hinge residuals sqrt(penalty) * max(0, -c) for the inequality constraints c >= 0."""
        return np.sqrt(_PENALTY) * np.maximum(0.0, -p.constraints)

    def _penalty_jacobian(self, p: Point) -> np.ndarray:
        if len(p.constraints) == 0:
            return np.zeros((0, len(p.x)))
        active = (p.constraints < 0)[:, None]
        return np.where(active, -np.sqrt(_PENALTY) * p.constraint_jacobian, 0.0)

    # ---------------------------------------------------------------- scalar objective
    def objective(self, x):
        p = self.point(x)
        if p is None:
            return 1e10
        if not self.history or p.objective < self.history[-1]["objective"]:
            self.record(p)
        return p.objective

    def objective_gradient(self, x):
        p = self.point(x, gradient=True)
        if p is None:
            return np.zeros(len(x))
        return 2 * p.jacobian.T @ p.residuals

    def penalised(self, x):
        p = self.point(x)
        if p is None:
            return 1e10
        value = p.objective + _PENALTY * float(np.sum(np.maximum(0.0, -p.constraints) ** 2))
        if not self.history or value < self.history[-1]["objective"]:
            self.record(p)
        return value

    def constraints(self, x):
        p = self.point(x)
        return p.constraints if p is not None else np.full(self._n_con, -1.0)

    def constraint_jacobian(self, x):
        p = self.point(x, gradient=True)
        return p.constraint_jacobian if p is not None else np.zeros((self._n_con, len(x)))


def _summary(p: Point) -> dict:
    """Per-configuration paired frequencies and MAC of a point (what a history row shows)."""
    return {"frequencies_hz": {n: c.frequencies_hz[np.maximum(c.paired, 0)].tolist()
                               for n, c in p.configurations.items()},
            "mac": {n: np.nan_to_num(c.mac, nan=-1.0).tolist() for n, c in p.configurations.items()}}


def minimise(problem: UpdatingProblem, x0: np.ndarray, method: str = OptimiserSettings.method, store=None,
             run: int = 0, max_iterations: int = OptimiserSettings.max_iterations,
             tolerance: float = OptimiserSettings.tolerance, progress: Callable | None = None) -> dict:
    """One optimiser run from x0 (normalised); returns x, the driver's history and SciPy's message.
    progress: called with each accepted iterate's history row."""
    if method not in METHODS:
        raise ModelError(f"updating: method '{method}' must be one of {METHODS}")
    par = problem.par
    x0 = np.asarray(x0, float)
    outside = np.flatnonzero((x0 < par.lower) | (x0 > par.upper))
    if len(outside):
        raise ModelError("updating: the initial point lies outside the bounds of " + ", ".join(
            f"'{par.names[i]}' ({x0[i]:.4g} not in [{par.lower[i]:.4g}, {par.upper[i]:.4g}])" for i in outside)
            + "; widen the bounds or start inside them")
    drv = _Driver(problem, store, run, progress)
    first = drv.point(x0, gradient=method != "nelder-mead")
    if first is None:
        raise SolverError(f"updating: the initial design point cannot be solved: {drv.failures[-1][1]}")
    drv._n_res = len(first.residuals) + len(first.constraints)
    drv._n_con = len(first.constraints)
    drv.record(first)
    t0 = time.perf_counter()
    if method in ("least_squares", "lm", "trf", "dogbox"):
        common = dict(jac=drv.jacobian, x_scale="jac", ftol=tolerance, xtol=tolerance, gtol=tolerance,
                      max_nfev=max_iterations)
        out = None
        if method in ("least_squares", "lm") and drv._n_res >= len(x0):
            # MINPACK's Levenberg-Marquardt: on the cantilever verification 7-9 Jacobians where SciPy's
            # bounded trust regions took 12-26 (dogbox) and 47-66 (trf). It knows no bounds: its answer
            # is kept when it lies inside them, else dogbox continues from there inside the bounds.
            # With fewer residuals than variables MINPACK refuses: dogbox alone, whose trust-region
            # steps from x0 keep the variables the data cannot see where they were.
            drv.failure_value = 1e3  # a failed trial point must raise the cost, not poison MINPACK with NaN
            out = least_squares(drv.residuals, x0, method="lm", **common)
            drv.failure_value = np.nan
            if np.any(out.x < par.lower) or np.any(out.x > par.upper):
                x0, out = np.clip(out.x, par.lower, par.upper), None
        if out is None:
            out = least_squares(drv.residuals, x0, bounds=(par.lower, par.upper),
                                method="trf" if method == "trf" else "dogbox", **common)
        x, message, success = out.x, out.message, out.status > 0
    elif method in ("slsqp", "trust-constr"):
        cons = []
        if drv._n_con:
            cons = [NonlinearConstraint(drv.constraints, 0.0, np.inf, jac=drv.constraint_jacobian)]
        opts = {"maxiter": max_iterations}
        if method == "slsqp":
            opts["ftol"] = tolerance
        else:
            opts.update(gtol=tolerance, xtol=tolerance)
        out = minimize(drv.objective, x0, jac=drv.objective_gradient, bounds=Bounds(par.lower, par.upper),
                       constraints=cons, method=method.upper() if method == "slsqp" else method, options=opts)
        x, message, success = out.x, str(out.message), bool(out.success)
    else:
        out = minimize(drv.penalised, x0, bounds=Bounds(par.lower, par.upper), method="Nelder-Mead",
                       options={"maxfev": max_iterations * (len(x0) + 1), "xatol": 1e-6, "fatol": tolerance,
                                "adaptive": len(x0) > 5})
        x, message, success = out.x, str(out.message), bool(out.success)
    drv.point(x)  # SciPy's final iterate competes with every point seen; a failed trial never wins
    x = drv.best.x
    return {"x": np.asarray(x, float), "reference": drv.best_reference(), "history": drv.history,
            "point": drv.best if drv.best_fresh else None,  # the reference's own point (solved in this run)
            "message": message, "success": success, "replayed": drv.replayed,
            "evaluations": drv.evaluations, "failures": drv.failures, "seconds": time.perf_counter() - t0,
            "method": method}


def starting_points(problem: UpdatingProblem, n: int, seed: int = 0) -> np.ndarray:
    """x0 = 1 and n - 1 points drawn uniformly inside the bounds (seeded)."""
    rng = np.random.default_rng(seed)
    par = problem.par
    pts = [np.ones(len(par))]
    for _ in range(n - 1):
        pts.append(rng.uniform(par.lower, par.upper))
    return np.array(pts)
