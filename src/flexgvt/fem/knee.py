"""The knee of a load path that stays stable: buckling passed with no unstable equilibrium on the way.

fem.stability finds a loss of stability from the tangent's eigenvalues. Along some paths none is
ever negative: an imperfect bifurcation (the wingbox's skins wrinkle progressively, their own
weight across them the imperfection), or a load increment that went from the pre-buckled path
straight onto a stable post-buckled branch. What marks the buckling there is the path itself: the
work of the loads per unit load factor (its compliance) is constant or drifts slowly along the
pre-buckled path and jumps where the skin gives way (the 0.1 m wingbox at -1 g: within 1e-4 up to
0.5 g, then 1.34 times that from 0.6 g on).

``knee`` finds the first such jump among the converged increments, brackets where the path leaves
its pre-buckled line by solving equilibria inside the increment (bisection), and puts the onset
where the pre- and post-buckled lines of the load-work curve meet (the two-tangent construction
of experimental buckling loads). The shape is the departure from the pre-buckled path at the
end of the bracket: what the structure did that its pre-buckled path would not have.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from ..errors import SolverError
from .stability import Instability, _unit, locate, negative_eigenvalues, where_local

KNEE = 0.05  # an increment's compliance above the trend of the ones before by this fraction: a knee candidate
DEPARTED = 0.02  # a state whose load work exceeds the pre-buckled line by this fraction of the line's increment
WIDTH = 0.005  # the bracket is narrowed to this fraction of the load factor (at most BISECTIONS solves)
BISECTIONS = 8


@dataclass(frozen=True)
class _Point:
    lam: float
    x: np.ndarray
    R: np.ndarray
    work: float  # the loads' work at full load factor over the displacement from the start [J]


def knee(system, trail: list, resolve: Callable[[float, np.ndarray, np.ndarray], tuple]) -> Instability | None:
    """The first knee of a stable load path (see the module's docstring), or None. trail: the
    converged equilibria (load factor, x, R) in load order, all stable; resolve(lam, x, R): the
    equilibrium at load factor lam by Newton from the state (x, R) (raises SolverError when it
    does not converge). Where a state solved from below is unstable and not departed (the solve
    followed the pre-buckled path past a bifurcation that the increments jumped), the bifurcation
    is located from the tangent instead (fem.stability.locate), with recovered=True."""
    loads = system.applied.reshape(-1, 6)[:, :3]
    if len(trail) < 3 or not np.any(loads):
        return None
    x0 = trail[0][1]

    def point(lam, x, R) -> _Point:
        return _Point(float(lam), x, R, float(np.sum(loads * (x - x0))))

    path = [point(*t) for t in trail]
    j = _candidate(path)
    if j is None:
        return None
    before, a, b = path[j - 1], path[j], path[j + 1]
    if len(system.cord_nodes):
        taut = [system.evaluate(p.x, p.R, p.lam, tangent=False).cord_tension > 0.0 for p in (a, b)]
        if np.any(taut[0] != taut[1]):
            return None  # a cord turned slack (or taut) in the increment: a change of supports, not a buckle
    if negative_eigenvalues(system, a.x, a.R, a.lam) > 0:
        # The knee's start is itself unstable (an increment landed on the pre-buckled path past its
        # bifurcation, between the increments the stability check sampled): the tangent says where.
        event = locate(system, list(trail[:j + 1]), resolve)
        return None if event is None else replace(event, recovered=True)
    slope = (a.work - before.work) / (a.lam - before.lam)  # the pre-buckled path's compliance [J]

    def departed(p: _Point) -> bool:
        line = slope * (p.lam - a.lam)
        return p.work - a.work - line > DEPARTED * abs(line)

    if not departed(b):
        return None
    lo, hi = a, b
    for _ in range(BISECTIONS):
        if hi.lam - lo.lam <= WIDTH * hi.lam:
            break
        lam = 0.5 * (lo.lam + hi.lam)
        try:
            mid = point(lam, *resolve(lam, lo.x, lo.R))
        except SolverError:
            break
        if departed(mid):
            hi = mid
        elif negative_eigenvalues(system, mid.x, mid.R, mid.lam) > 0:
            # The solve from below stayed on the pre-buckled path past its bifurcation: the tangent says where.
            event = locate(system, [(p.lam, p.x, p.R) for p in (before, lo, mid)], resolve)
            return None if event is None else replace(event, recovered=True)
        else:
            lo = mid
    # The post-buckled line: the compliance just past the bracket.
    lam = hi.lam + max(hi.lam - lo.lam, WIDTH * hi.lam)
    if b.lam > hi.lam:
        lam = min(lam, b.lam)
    try:
        after = b if lam == b.lam else point(lam, *resolve(lam, hi.x, hi.R))
    except SolverError:
        return None
    post = (after.work - hi.work) / (after.lam - hi.lam)
    if post < (1.0 + KNEE) * slope:
        return None  # no jump of the compliance: the path softens smoothly (an approach to buckling, not a knee)
    # Two tangents: lo + slope (lam - lo) = hi + post (lam - hi).
    lam_star = (hi.work - lo.work - post * hi.lam + slope * lo.lam) / (slope - post)
    lam_star = float(np.clip(lam_star, lo.lam, hi.lam))
    ahead = (a.x - before.x) / (a.lam - before.lam)
    shape = np.zeros((len(x0), 6))
    shape[:, :3] = b.x - a.x - (b.lam - a.lam) * ahead  # the departure from the pre-buckled path at b
    if not np.any(shape):
        return None
    return Instability(lam_star, "bifurcation", 0.0, _unit(shape), where_local(system, shape), (lo.lam, hi.lam),
                       recovered=True, found_by="path", softening=float(post / slope))


def _candidate(path: list[_Point]) -> int | None:
    """Index j of the first point after which the compliance of the increment (j, j+1) exceeds the
    trend of the two increments before it by KNEE. Two, not one: the first increment's own
    compliance can differ from the next one's without any buckling (an asymmetric aircraft on two
    cords: 6 % lower, the cords' pendulum stiffness growing from nothing with their tension)."""
    lam = np.array([p.lam for p in path])
    work = np.array([p.work for p in path])
    c = np.diff(work) / np.diff(lam)
    mid = 0.5 * (lam[1:] + lam[:-1])
    for k in range(2, len(c)):
        if not (c[k - 1] > 0.0 and c[k - 2] > 0.0):
            continue
        trend = c[k - 1] + max(0.0, (c[k - 1] - c[k - 2]) / (mid[k - 1] - mid[k - 2])) * (mid[k] - mid[k - 1])
        if c[k] > trend + KNEE * c[k - 1]:
            return k
    return None
