"""Arc-length continuation of a static load path past limit points (Riks; Crisfield's cylindrical
constraint): the load factor lambda becomes an unknown and each increment moves a fixed distance
along the path in displacement space, so the path can pass a maximum of the load (snap-through of
a shallow arch or a pinched shell) where load control stops.

solve_static (fem.static) calls :func:`trace` when ``StaticSettings(control="arc-length")``. The
driver works on a System with its evaluate / tangent / update, as Newton's load stepping does.
The states at requested load factors are those a slowly growing load reaches: each level is
recorded where the path first rises through it (on a snap-through that is the branch before the
limit point below it, and the branch after the snap above it), by a Newton solve at that fixed
load factor started from the path.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.sparse as sp

from ..errors import ConvergenceError, ModelError
from .linsolve import superlu
from .stability import Instability, _unit, _where
from .system import System

STABILISATION = (2 * np.pi * 1e-3) ** 2  # as fem.static: a mass term only if the bare tangent is singular
_PATH_TOLERANCE = 1e-6  # relative residual of the points on the way; the requested levels take settings.tolerance
_PATH_ENERGY = 1e-10  # or a correction's energy |du . r| this fraction of the step's first one


@dataclass
class ArcPath:
    """A traced path: converged points (load factor, positions (n, 3) [m], rotations (n, 3, 3)) in
    path order, the states at the requested levels, the final state (at load factor 1), the
    iteration record (step, load factor, iteration, relative residual) and the load factors of the
    limit points passed (local maxima of lambda along the path)."""

    points: list[tuple[float, np.ndarray, np.ndarray]] = field(default_factory=list)
    levels: list[tuple[float, np.ndarray, np.ndarray]] = field(default_factory=list)
    final: tuple[float, np.ndarray, np.ndarray] | None = None
    history: list[tuple[int, float, int, float]] = field(default_factory=list)
    arc: list[float] = field(default_factory=list)  # cumulative arc length [m] (translations) at each point
    limits: list[Instability] = field(default_factory=list)

    @property
    def limit_points(self) -> list[float]:
        """Load factors of the limit points passed."""
        return [event.load_factor for event in self.limits]


class _Solver:
    """The tangent at a state, factorised (SuperLU on the full, possibly indefinite tangent: past a
    limit point it has a negative eigenvalue and a Cholesky factorisation does not exist)."""

    def __init__(self, system: System, M: sp.csc_matrix):
        self.system, self.M = system, M

    def factor(self, x, R, lam: float):
        ev = self.system.evaluate(x, R, lam)
        K = self.system.tangent_of(ev)
        for alpha in (0.0, STABILISATION, 1e3 * STABILISATION):
            A = K if alpha == 0.0 else (K + alpha * self.M).tocsc()
            try:
                return ev, superlu(A.tocsc()).solve
            except RuntimeError:
                continue
        return ev, None


def _norm_mask(system: System) -> np.ndarray:
    """The DOFs the arc length is measured on: the translations (rotations are in other units and
    large rotations would dominate the step), all DOFs if there are none."""
    mask = ~system.rotation_mask
    return mask if mask.any() else np.ones_like(mask)


def trace(system: System, x: np.ndarray, R: np.ndarray, levels: list[float], settings,
          mass: sp.csc_matrix, progress: Callable[[float], None] | None = None) -> ArcPath:
    """Follow the equilibrium path from (x, R) at lambda = 0 to lambda = 1 by arc-length steps.

    settings: the StaticSettings (increments sets the first step: the tangent predictor for a
    load increment 1/increments; arc_length [m] overrides it; max_iterations, tolerance,
    desired_iterations, max_increment_growth, min_increment and max_arc_steps are used).
    levels: load factors (0 to 1) whose states are wanted. Raises ConvergenceError (with the last
    converged point in its message) when the path cannot be continued.
    """
    if system.has_prescribed or len(system.cord_nodes):
        raise ModelError(f"configuration '{system.config.name}': arc-length control needs dead loads only; "
                         "prescribed motions and suspension cords (whose pre-tension is ramped) are not supported. "
                         "Use StaticSettings(control='load')")
    solver = _Solver(system, mass)
    path = ArcPath()
    mask = _norm_mask(system)
    q = system.evaluate(x, R, 1.0, tangent=False).external - system.evaluate(x, R, 0.0, tangent=False).external
    q_norm = max(float(np.linalg.norm(q)), 1e-300)
    if not np.any(q):
        raise ModelError(f"configuration '{system.config.name}': arc-length control needs applied loads; "
                         "the configuration has none")
    pending = sorted(lv for lv in levels if lv > 1e-12) + [1.0]
    if any(lv <= 1e-12 for lv in levels):
        path.levels.append((0.0, x.copy(), R.copy()))
    lam, top = 0.0, 0.0
    path.points.append((lam, x, R))
    path.arc.append(0.0)
    ev, solve = solver.factor(x, R, lam)
    if solve is None:
        raise ConvergenceError(f"configuration '{system.config.name}': the unloaded tangent is singular; arc-length "
                               "control cannot start")
    du_t = solve(q)
    arc = settings.arc_length or float(np.linalg.norm(du_t[mask])) / settings.increments
    min_arc = settings.min_increment * arc * settings.increments
    previous = None  # the last converged increment (reduced displacement, lambda change)
    fine = None  # the step length that resolves a limit point found in the current step
    step = 0
    while pending and step < settings.max_arc_steps:
        step += 1
        got = _arc_step(system, solver, x, R, lam, q, q_norm, arc, previous, mask, settings, step, path.history)
        if got is None:
            arc *= 0.5
            if arc < min_arc:
                raise ConvergenceError(f"configuration '{system.config.name}': the arc-length path could not be "
                                       f"continued beyond load factor {lam:.4g} (the arc length was cut below "
                                       f"{min_arc:.3g}); a bifurcation on the path (a symmetric structure "
                                       "buckling asymmetrically) needs an imperfection", history=tuple(path.history))
            continue
        x_new, R_new, lam_new, du, iterations = got
        if previous is not None and previous[1] > 0 >= lam_new - lam:
            # A limit point within the step: taken again in shorter steps until the step is a
            # sixteenth of the one that found it, so the parabola through the last points is close.
            fine = fine or arc / 16
            if arc > fine:
                arc *= 0.25
                continue
            path.limits.append(_limit(system, path, lam_new, path.arc[-1] + arc, du))
            fine = None
        # Levels the load rises through for the first time: solved at their load factor.
        while pending and lam_new >= pending[0] - 1e-12 and pending[0] > top - 1e-12 and lam_new > lam:
            level = pending.pop(0)
            frac = (level - lam) / (lam_new - lam)
            xs, Rs = system.update(x, R, frac * du)
            at = _fixed_level(system, solver, xs, Rs, level, q_norm, settings, step, path.history)
            if at is None:
                raise ConvergenceError(f"configuration '{system.config.name}': Newton did not converge at load factor "
                                       f"{level:.4g} from the arc-length path", history=tuple(path.history))
            if level >= 1.0 - 1e-12:
                path.final = (1.0, *at)
            else:
                path.levels.append((level, *at))
        previous = (du, lam_new - lam)
        x, R, lam = x_new, R_new, lam_new
        top = max(top, lam)
        path.points.append((lam, x, R))
        path.arc.append(path.arc[-1] + arc)
        if progress is not None:
            progress(lam)
        scale = np.sqrt(settings.desired_iterations / max(iterations, 1))
        arc *= min(scale, settings.max_increment_growth)
    if path.final is None:
        raise ConvergenceError(f"configuration '{system.config.name}': the arc-length path reached load factor "
                               f"{lam:.4g} (highest {top:.4g}) in {settings.max_arc_steps} steps without reaching the "
                               "full load: raise StaticSettings.max_arc_steps or arc_length, or the structure cannot "
                               "carry the load", history=tuple(path.history))
    return path


def _limit(system: System, path: ArcPath, lam_next: float, s_next: float, du: np.ndarray) -> Instability:
    """The limit point between the last two converged points and the new one: the vertex of the
    parabola lambda(s) through the three (s the arc length), the path's direction there as the
    shape (the tangent's null vector at a limit point), eigenvalue 0 (the tangent is singular there
    by definition)."""
    s = np.array([path.arc[-2], path.arc[-1], s_next])
    lam = np.array([path.points[-2][0], path.points[-1][0], lam_next])
    c2, c1, c0 = np.polyfit(s - s[1], lam, 2)
    top = c0 - c1 * c1 / (4 * c2) if c2 < 0 else lam[1]
    shape = _unit(system.expand(du))
    return Instability(float(max(top, lam[1])), "limit point", 0.0, shape, _where(system, shape),
                       (float(lam[0]), float(lam[2])))


def _arc_step(system: System, solver: _Solver, x, R, lam: float, q: np.ndarray, q_norm: float, arc: float,
              previous, mask: np.ndarray, settings, step: int, history: list):
    """One arc-length increment from the converged (x, R, lam): the secant predictor (the last
    increment, displacements and load factor, scaled to the arc length; the tangent predictor for
    the first), then Newton corrections on the cylindrical constraint |du| = arc over the
    translations, the root closer in direction to the increment so far (Crisfield). The secant
    keeps going the way the path went: the tangent's own direction flips sign where an eigenvalue
    crosses zero, at a limit point but also at a bifurcation the path passes (a symmetric model),
    and Feng's sign rule, tried first, turned the path back there (the slit annular plate at 40 %
    of its load). Returns (x, R, lam, du, iterations) or None."""
    if previous is None:  # the tangent predictor, loading
        ev, solve = solver.factor(x, R, lam)
        if solve is None:
            return None
        du_t = solve(q)
        n_t = float(np.linalg.norm(du_t[mask]))
        if not np.isfinite(n_t) or n_t == 0.0:
            return None
        dlam = arc / n_t
        du = dlam * du_t
    else:  # the secant predictor: the last increment scaled to this arc length
        n_p = float(np.linalg.norm(previous[0][mask]))
        if n_p == 0.0:
            return None
        du, dlam = previous[0] * (arc / n_p), previous[1] * (arc / n_p)
    xk, Rk = system.update(x, R, du)
    lam_k = lam + dlam
    first = None
    for it in range(1, settings.max_iterations + 1):
        ev, solve = solver.factor(xk, Rk, lam_k)
        r = ev.internal - ev.external
        res = float(np.linalg.norm(r)) / max(q_norm * abs(lam_k), q_norm * 1e-3)
        history.append((step, lam_k, it, res))
        if not np.isfinite(res):
            return None
        if res < _PATH_TOLERANCE:
            return xk, Rk, lam_k, du, it
        if solve is None:
            return None
        du_r = -solve(r)
        energy = abs(float(du_r @ r))
        first = energy if first is None else first
        if it > 1 and energy <= _PATH_ENERGY * first:  # at the residual's round-off floor (thin shells)
            return xk, Rk, lam_k, du, it
        du_t = solve(q)
        a_vec, b_vec = du_t[mask], (du + du_r)[mask]
        a = a_vec @ a_vec
        b = 2.0 * (a_vec @ b_vec)
        c = b_vec @ b_vec - arc**2
        disc = b * b - 4 * a * c
        if disc < 0 or a == 0:
            return None
        roots = ((-b + np.sqrt(disc)) / (2 * a), (-b - np.sqrt(disc)) / (2 * a))
        # The root whose increment turns least from the increment so far.
        cosines = [(du + du_r + g * du_t)[mask] @ du[mask] for g in roots]
        g = roots[int(np.argmax(cosines))]
        delta = du_r + g * du_t
        xk, Rk = system.update(xk, Rk, delta)
        du = du + delta
        lam_k += g
    return None


def _fixed_level(system: System, solver: _Solver, x, R, lam: float, q_norm: float, settings, step: int,
                 history: list):
    """Newton at a fixed load factor from a state on the path next to it: (x, R) or None. Converged
    on the residual (settings.tolerance) or, as load stepping does for thin structures whose
    residual has a round-off floor above it, once a correction's energy |du . r| is below
    settings.relative_energy_tolerance of the first one or settings.energy_tolerance of load x
    length (that correction applied)."""
    length = float(np.abs(system.cm.xyz).max()) + 1.0
    first = None
    for it in range(settings.max_iterations):
        ev, solve = solver.factor(x, R, lam)
        r = ev.internal - ev.external
        ref = max(q_norm * lam, 1e-300)
        res = float(np.linalg.norm(r)) / ref
        history.append((step, lam, it, res))
        if res < settings.tolerance:
            return x, R
        if solve is None or not np.isfinite(res):
            return None
        delta = -solve(r)
        energy = abs(float(delta @ r))
        first = energy if first is None else first
        x, R = system.update(x, R, delta)
        if it > 0 and (energy <= settings.relative_energy_tolerance * first
                       or energy <= settings.energy_tolerance * ref * length):
            return x, R
    return None
