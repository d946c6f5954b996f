"""Stability of static equilibria: the lowest eigenvalue of the tangent (symmetric part, with the
mass matrix as metric) at a state, and where along a load path it went negative (a bifurcation, as
a compressed skin buckling, or a limit point), with the buckling shape and the elements it moves.

solve_static (fem.static) calls ``locate`` on its converged increments when the final state is
unstable; this module knows nothing of the load stepping: the caller hands it a ``resolve(lam)``
that returns the equilibrium at a load factor between two converged increments.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolverError
from .eigen import _RIGID_MARGIN, DEFAULT_SHIFT, _rigid_safe_shift, modal_frequencies_hz, real_modes, rigid_count
from .linsolve import inertia

BUCKLING_MODES = ("ignore", "warn", "stop", "continue")
_SAMPLES = 6  # increments checked along a path that ends stable (a bifurcation passed on the way)
_ROUND_OFF = 1e-9  # a relative eigenvalue this close to zero counts as zero (rigid body, neutral)


@dataclass(frozen=True)
class Instability:
    """Where a load path lost stability. load_factor: the critical fraction of the configuration's
    loads (a tangent eigenvalue crosses zero there, found by a linear buckling analysis between the
    equilibria of ``bracket``); kind: 'bifurcation' (the loads went on growing along an unstable
    path: a skin wrinkling under compression);
    eigenvalue: the lowest at the state that was found unstable [rad^2/s^2]; shape (n_nodes, 6):
    the buckling shape at the stable side of the bracket (largest translation 1); where: the
    elements it moves most; recovered: the path went on to a stable equilibrium (the solver left
    the unstable fundamental path for a stable, post-buckled one by itself). found_by: 'tangent' (a
    negative tangent eigenvalue along the path) or 'path' (a knee of a path that stays stable,
    fem.knee: load_factor is where its pre- and post-buckled load-work lines meet, shape the departure
    from the pre-buckled path, eigenvalue 0); softening: there, the post-buckled compliance over the
    pre-buckled one (the work of the loads per load factor; 1 for 'tangent')."""

    load_factor: float
    kind: str
    eigenvalue: float
    shape: np.ndarray
    where: str
    bracket: tuple[float, float]
    recovered: bool = False
    found_by: str = "tangent"
    softening: float = 1.0

    def describe(self) -> str:
        seen = (f"; seen as a knee of the load path: no equilibrium along it is unstable, and its compliance "
                f"grows {self.softening:.3g} times there" if self.found_by == "path" else "")
        return (f"{self.kind} at load factor {self.load_factor:.4g} (between {self.bracket[0]:.4g} and "
                f"{self.bracket[1]:.4g}), moving most {self.where}{seen}")


def _matrices(system, x, R, lam):
    """The tangent's symmetric part and the metric: the mass matrix, or the identity for a massless
    model (the signs of the eigenvalues are what stability asks)."""
    ev = system.evaluate(x, R, lam, assemble=False)
    M = system.mass_matrix(x, R)
    K = system.newton_matrix(ev, M, 0.0)
    if not np.any(M.data):
        M = sp.identity(K.shape[0], format="csc")
    return K, M


def _shift(system, K, M) -> float:
    """Below zero by the rigid-body eigenvalues' round-off (none needed when clamped)."""
    return 0.0 if system.clamped else _rigid_safe_shift(K, np.abs(M.diagonal()), DEFAULT_SHIFT)


def shifted(system, K: sp.spmatrix, M: sp.spmatrix) -> sp.csc_matrix:
    """K - s M with the stability check's shift s, plus _RIGID_MARGIN eps |K_ii| on the diagonal of
    massless DOFs: the shift's margin for them (a mechanism with neither mass nor stiffness, as a spin
    about a line of point masses, is neutral: its pivot is round-off of either sign without it)."""
    A = (K - _shift(system, K, M) * M).tocsc()
    massless = M.diagonal() == 0
    if np.any(massless):
        A = (A + sp.diags(np.where(massless, _RIGID_MARGIN * np.finfo(float).eps * np.abs(K.diagonal()), 0.0))).tocsc()
    return A


def negative_eigenvalues(system, x: np.ndarray, R: np.ndarray, lam: float) -> int:
    """How many eigenvalues of the tangent's symmetric part lie below zero at a state (rigid-body
    modes of a free structure excepted), by Sylvester's law of inertia: the negative pivots of
    K - s M factorised with symmetric pivoting, s just below the rigid-body round-off: PARDISO's
    Bunch-Kaufman LDL^T where installed (fem.linsolve.inertia), else SuperLU with diagonal pivots.
    -1 when neither gives the count (a pivot perturbed, or SuperLU had to leave the diagonal)."""
    K, M = _matrices(system, x, R, lam)
    A = shifted(system, K, M)
    counts = inertia(A, system.inertia_cache)
    if counts is not None:
        return counts[1]
    return superlu_negative_pivots(A)


def superlu_negative_pivots(A: sp.csc_matrix) -> int:
    """Negative pivots of SuperLU's LU of symmetric A with diagonal pivoting (its inertia when the
    row and column orders agree), -1 when singular or the pivoting left the diagonal."""
    try:
        lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular: a zero eigenvalue at the shift
        return -1
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return -1
    return int(np.sum(lu.U.diagonal() < 0))


def lowest_eigenvalue(system, x: np.ndarray, R: np.ndarray, lam: float, k: int = 4) -> tuple[float, np.ndarray]:
    """The lowest of the k eigenvalues [rad^2/s^2] of the tangent's symmetric part nearest zero at a
    state (rigid-body modes of a free structure left out) and its shape (6 n_nodes,): near a loss of
    stability, the one crossing zero."""
    K, M = _matrices(system, x, R, lam)
    T = system.transformation(x, R) if system.has_links else None
    n_rigid = 0 if system.clamped else rigid_count(system, x, T, K, M)
    vals, vecs = real_modes(K, M, n_rigid + k, None, system.clamped, system.cholmod_cache)
    f = modal_frequencies_hz(vals, K, M, system, x, T, n_rigid=n_rigid)
    elastic = np.flatnonzero(f != 0.0)
    j = int(elastic[np.argmin(vals[elastic])]) if len(elastic) else len(vals) - 1
    return float(vals[j]), system.expand(vecs[:, j], T)


def _where(system, shape: np.ndarray) -> str:
    """The family and elements the shape's translations move most (for the message)."""
    u = np.linalg.norm(shape.reshape(-1, 6)[:, :3], axis=1)
    top = np.flatnonzero(u >= 0.5 * u.max())
    parts = [text for text in (family.describe(top) for family in system.families if family.structural) if text]
    return parts[0] if parts else f"nodes {', '.join(str(int(i)) for i in system.cm.node_ids[top[:5]])}"


def corner_spread(u: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """(n,) how much a shape deforms each element of nodes (n, p) (row indices of u): the rms spread of
    its corners' translations u (n_nodes, 3) about their mean, rigid translations of the element left
    out (a wrinkle shows, the global motion a buckling shape carries with it does not)."""
    corners = u[nodes]
    return np.sqrt(((corners - corners.mean(axis=1, keepdims=True)) ** 2).sum(axis=2).mean(axis=1))


def where_local(system, shape: np.ndarray) -> str:
    """The family and elements the shape deforms most (corner_spread at least half the largest): a
    wrinkle, not the global motion the shape carries with it, as a departure from a pre-buckled path
    does."""
    u = shape.reshape(-1, 6)[:, :3]
    spreads = [(family, corner_spread(u, family.nodes))
               for family in system.families if family.structural and np.asarray(family.nodes).shape[1] >= 2
               and len(family.nodes)]
    largest = max((float(s.max()) for _, s in spreads), default=0.0)
    if largest <= 0.0:
        return _where(system, shape)
    parts = [family.describe(np.unique(family.nodes[s >= 0.5 * largest])) for family, s in spreads
             if np.any(s >= 0.5 * largest)]
    parts = [p for p in parts if p]
    return "; ".join(parts) if parts else _where(system, shape)


def locate(system, trail: list, resolve: Callable[[float, np.ndarray, np.ndarray], tuple],
           refinements: int = 12) -> Instability | None:
    """The first loss of stability along a load path. trail: the converged equilibria (load factor,
    x, R) in load order; resolve(lam, x, R): the equilibrium (x, R) at load factor lam by Newton
    from the state (x, R) (here trail's stable one below lam). Bisects the trail for the first unstable
    equilibrium, then refines the crossing by a linear buckling analysis between the bracketing
    equilibria, solving the equilibrium at each estimate to narrow the bracket; where the estimates
    keep landing on one side (the tangent is not linear in the load across a wide bracket: lateral
    buckling's is quadratic), the next one is the bracket's middle, so the bracket always shrinks.
    When the last equilibrium is stable, _SAMPLES increments evenly along the path are
    checked (a path that passed a bifurcation and went on along a stable branch). None when no
    checked equilibrium is unstable."""
    values: dict[int, tuple[float, np.ndarray]] = {}
    counts: dict[int, int] = {}

    def lowest(k):
        if k not in values:
            values[k] = lowest_eigenvalue(system, trail[k][1], trail[k][2], trail[k][0])
        return values[k]

    def unstable(k):
        if k not in counts:
            counts[k] = negative_eigenvalues(system, trail[k][1], trail[k][2], trail[k][0])
            if counts[k] < 0:  # the inertia is unknown: the eigenvalues nearest zero decide
                counts[k] = int(lowest(k)[0] < 0)
        return counts[k] > 0

    hi = len(trail) - 1
    recovered = False
    if not unstable(hi):  # stable at the end: a path through a bifurcation onto a stable branch?
        samples = np.unique(np.linspace(0, hi, min(hi + 1, _SAMPLES + 2)).round().astype(int))[1:-1]
        found = [int(k) for k in samples if unstable(int(k))]
        if not found:
            return None
        hi, recovered = found[0], True
    if unstable(0):  # unstable from the start (unloaded): nothing to locate
        val, shape = lowest(0)
        return Instability(trail[0][0], "bifurcation", val, _unit(shape), _where(system, shape),
                           (trail[0][0], trail[0][0]))
    lo = 0
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if unstable(mid):
            hi = mid
        else:
            lo = mid
    a, b = trail[lo], trail[hi]
    critical, shape = _linearised(system, a, b)
    if critical is None:  # the tangent does not change linearly across the bracket: its middle
        critical, shape = 0.5 * (a[0] + b[0]), lowest(lo)[1]
    side, streak = None, 0
    for _ in range(refinements):
        if (b[0] - a[0]) < 1e-3 * max(b[0], 1e-12):
            break
        try:
            x, R = resolve(critical, trail[lo][1], trail[lo][2])
        except SolverError:  # no equilibrium found there: keep the estimate of the bracket
            break
        c = (critical, x, R)
        neg = negative_eigenvalues(system, x, R, critical)
        now = "b" if neg > 0 or (neg < 0 and lowest_eigenvalue(system, x, R, critical)[0] < 0) else "a"
        streak = streak + 1 if now == side else 1
        side = now
        if now == "b":
            b = c
        else:
            a = c
        # The same end moved twice: the linear estimate is biased to that side (regula falsi's
        # stagnation: from a 0.91-1.12 bracket it stayed at 1.116 of the strip's critical load).
        again, again_shape = (None, None) if streak >= 2 else _linearised(system, a, b)
        if again is None:
            critical = 0.5 * (a[0] + b[0])
            continue
        moved = abs(again - critical)
        critical, shape = again, again_shape
        if moved <= 1e-6 * max(critical, 1e-12):  # exact for a tangent linear in the load (a flat plate)
            break
    value = lowest_eigenvalue(system, trail[hi][1], trail[hi][2], trail[hi][0])[0]
    # Load control went on past it to unstable equilibria: a bifurcation (at a limit point the
    # load cannot grow, and the ramp stops with a ConvergenceError instead).
    return Instability(float(critical), "bifurcation", float(value), _unit(shape), where_local(system, shape),
                       (float(a[0]), float(b[0])), recovered)


def _linearised(system, a: tuple, b: tuple) -> tuple[float | None, np.ndarray | None]:
    """The critical load factor and buckling shape from the tangents at a stable equilibrium a and an
    unstable one b (load factor, x, R): K_a phi = nu (K_a - K_b) phi, lam = lam_a + (lam_b - lam_a) / nu
    with nu the largest (the tangent changing linearly between them, as a linear buckling
    analysis about a); (None, None) when that puts no crossing between them."""
    Ka, _ = _matrices(system, a[1], a[2], a[0])
    Kb, _ = _matrices(system, b[1], b[2], b[0])
    D = (Ka - Kb).tocsr()
    factor = system.inertia_cache.factor(Ka.tocsc())  # PARDISO or CHOLMOD on the stability checks' pattern
    if factor is not None:
        solve = factor.solve_A
    else:
        try:
            solve = spla.splu(Ka.tocsc()).solve
        except RuntimeError:  # exactly singular at a: no linear estimate from there
            return None, None
    n = Ka.shape[0]
    op = spla.LinearOperator((n, n), matvec=lambda v: solve(D @ v), dtype=float)
    k = min(3, n - 2)
    nu, vecs = spla.eigs(op, k=k, which="LR", v0=np.random.default_rng(0).standard_normal(n), tol=1e-10)
    j = int(np.argmax(nu.real))
    ratio = float(nu[j].real)
    if not ratio >= 1.0:  # no crossing inside the bracket by the linear estimate
        return None, None
    T = system.transformation(a[1], a[2]) if system.has_links else None
    return a[0] + (b[0] - a[0]) / ratio, system.expand(np.real(vecs[:, j]), T)


def _unit(shape: np.ndarray) -> np.ndarray:
    s = shape.reshape(-1, 6)
    return s / max(np.linalg.norm(s[:, :3], axis=1).max(), 1e-300)
