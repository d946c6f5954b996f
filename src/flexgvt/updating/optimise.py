"""Optimiser drivers: sensitivity-based least squares (default: Levenberg-Marquardt, continued
inside the bounds by a trust region when needed), SLSQP and trust-constr with analytic
gradients, Nelder-Mead with penalties (the original work's baseline), multi-start.

A design point where a configuration does not converge returns non-finite residuals to SciPy's
trust regions (they shrink the step and try again), large residuals to Levenberg-Marquardt (the
step is rejected and the damping raised) and a large objective to the scalar methods; the
optimiser never sees an exception from the solver.
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np
from scipy.optimize import Bounds, NonlinearConstraint, least_squares, minimize

from ..errors import ModelError, SolverError
from .problem import DesignPointFailure, Point, UpdatingProblem

METHODS = ("least_squares", "lm", "dogbox", "trf", "slsqp", "trust-constr", "nelder-mead")
_PENALTY = 1e3  # weight of a violated constraint in the penalised objectives


class _Driver:
    """Wraps the problem for SciPy: caching, failure handling, history and the store."""

    def __init__(self, problem: UpdatingProblem, store=None, run: int = 0, callback: Callable | None = None):
        self.problem = problem
        self.store = store
        self.run = run
        self.callback = callback
        self.history: list[dict] = []
        self.failures: list[tuple[np.ndarray, str]] = []
        self.best: Point | None = None  # lowest objective plus constraint penalty seen
        self.best_merit = np.inf
        self.evaluations = 0
        self.failure_value = np.nan  # residuals returned at a design point that cannot be solved

    def point(self, x, gradient=False) -> Point | None:
        self.evaluations += 1
        try:
            p = self.problem.evaluate(np.asarray(x, float), gradient=gradient)
        except DesignPointFailure as exc:
            self.failures.append((np.array(x, float), str(exc)))
            return None
        merit = p.objective + _PENALTY * float(np.sum(np.maximum(0.0, -p.constraints) ** 2))
        par = self.problem.par
        inside = bool(np.all(p.x >= par.lower - 1e-12) and np.all(p.x <= par.upper + 1e-12))
        if inside and (self.best is None or merit < self.best_merit):  # an unbounded method's excursion never wins
            self.best, self.best_merit = p, merit
        return p

    def record(self, p: Point) -> None:
        """One accepted iterate: history row and a store transaction."""
        row = {"iteration": len(self.history), "x": p.x.tolist(), "objective": p.objective,
               "residuals": p.residuals.tolist(), "time_s": time.perf_counter(),
               "frequencies_hz": {n: c.frequencies_hz[np.maximum(c.paired, 0)].tolist()
                                  for n, c in p.configurations.items()},
               "mac": {n: np.nan_to_num(c.mac, nan=-1.0).tolist() for n, c in p.configurations.items()}}
        self.history.append(row)
        if self.store is not None:
            self.store.record(self.run, row)
        if self.callback is not None:
            self.callback(row)

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


def minimise(problem: UpdatingProblem, x0: np.ndarray, method: str = "least_squares", store=None, run: int = 0,
             max_iterations: int = 100, tolerance: float = 1e-10, callback: Callable | None = None) -> dict:
    """One optimiser run from x0 (normalised); returns x, the driver's history and SciPy's message."""
    if method not in METHODS:
        raise ModelError(f"updating: method '{method}' must be one of {METHODS}")
    par = problem.par
    x0 = np.asarray(x0, float)
    outside = np.flatnonzero((x0 < par.lower) | (x0 > par.upper))
    if len(outside):
        raise ModelError("updating: the initial point lies outside the bounds of " + ", ".join(
            f"'{par.names[i]}' ({x0[i]:.4g} not in [{par.lower[i]:.4g}, {par.upper[i]:.4g}])" for i in outside)
            + "; widen the bounds or start inside them")
    drv = _Driver(problem, store, run, callback)
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
    return {"x": np.asarray(x, float), "reference": problem.reference_of(drv.best), "history": drv.history,
            "message": message, "success": success,
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
