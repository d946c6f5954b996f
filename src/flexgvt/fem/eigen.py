"""The eigen kernel under solve_modes, the static solver's stability check and the updating
layer's design-point solves: real and complex eigenpairs of reduced K, M (C) and the one rule
that turns eigenvalues into frequencies [Hz] with rigid-body modes at exactly 0 Hz
(modal_frequencies_hz). It imports no solver module, so static and modes both build on it."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ModelError, SolverError
from .labels import mac_matrix
from .linsolve import HAVE_FAST, CholmodCache

DENSE_LIMIT = 200  # reduced DOFs below which dense eigensolvers are used


def _frequency_hz(lam: np.ndarray, round_off: float = 0.0, n_rigid: int | None = None) -> np.ndarray:
    """Frequencies [Hz] of eigenvalues [rad^2/s^2]; round-off-sized ones (rigid-body modes) become 0:
    below 1e-9 of the largest or ``round_off`` [rad^2/s^2], at most the ``n_rigid`` smallest."""
    scale = max(np.abs(lam).max(initial=0.0), 1.0)
    zero = np.abs(lam) < max(1e-9 * scale, round_off)
    if n_rigid is not None and zero.sum() > n_rigid:
        keep = np.argsort(np.abs(lam))[:n_rigid]
        zero = np.zeros_like(zero)
        zero[keep] = True
    lam = np.where(zero, 0.0, lam)
    return np.sign(lam) * np.sqrt(np.abs(lam)) / (2 * np.pi)


# Default shift [rad^2/s^2]: just below zero, (2 pi 0.01 Hz)^2, so rigid-body modes (0) and the
# lowest elastic modes of very flexible structures are nearest to it whatever the model's scale.
DEFAULT_SHIFT = -(2 * np.pi * 0.01) ** 2


_MASS_ROUND_OFF = 1e-14  # diagonal masses below this fraction of the largest are round-off (see below)


def _lambda_max_bound(K: sp.spmatrix, m_diag: np.ndarray) -> float:
    """A lower bound of the largest eigenvalue of K phi = lam M phi: the largest K_ii / M_ii [rad^2/s^2]
    over the DOFs that carry mass. A diagonal mass below _MASS_ROUND_OFF of the largest is round-off,
    not mass: a massless drilling rotation (shells) or bending rotation (beams without rotary inertia)
    turned into global axes by a rotation with 6e-17 for a zero (a vertical plate) gets 1e-40 of its
    node's rotary inertia, and K_ii over it (1e45) made every mode "rigid" (free-free) or "zero"
    (damped). Legitimate rotary inertias are t^2/12 of the translational masses (1e-14: t = 0.35 um)."""
    has_mass = m_diag > _MASS_ROUND_OFF * m_diag.max(initial=0.0)
    if not np.any(has_mass):
        return 0.0
    return float(np.max(np.abs(K.diagonal())[has_mass] / m_diag[has_mass]))


def _rigid_safe_shift(K: sp.spmatrix, m_diag: np.ndarray, sigma: float) -> float:
    """A shift at least _RIGID_MARGIN times the round-off of the rigid-body eigenvalues below zero.

    Those are zero only to about eps * lambda_max; closer to them K - sigma M is numerically
    singular and the elastic eigenvalues lose accuracy, whatever the eigensolver tolerance.
    Measured on a 60-element free-free strip (lambda_max ~ 6e12 rad^2/s^2), largest relative
    error of the first ten elastic eigenvalues against the dense solution: default shift 3e-4
    (CHOLMOD) / 8e-5 (SuperLU); 100 eps lambda_max 3e-8 / 2e-6; 1,000 eps lambda_max 3e-8 / 3e-8.
    Any negative shift keeps the lowest modes nearest to it; a large one slows the eigensolver
    only where the lowest elastic eigenvalues are below it.
    """
    return min(sigma, -_RIGID_MARGIN * np.finfo(float).eps * _lambda_max_bound(K, m_diag))


_RIGID_MARGIN = 1e3


def _cholesky_inverse(K: sp.spmatrix, M: sp.spmatrix, sigma: float,
                      cache: CholmodCache | None = None) -> spla.LinearOperator | None:
    """(K - sigma M)^-1 through the symmetric LDL^T (PARDISO or CHOLMOD, fem.linsolve) when one is
    installed and no pivot is tiny (sigma not at an eigenvalue); None lets eigsh factorise with
    SuperLU. cache: a symbolic analysis of the pattern to reuse (the system's, from its static solve)."""
    if not HAVE_FAST:
        return None
    # Both triangles: CHOLMOD's simplicial refactorisation reads them faster than the lower one.
    if (sp.isspmatrix_csc(K) and sp.isspmatrix_csc(M) and K.has_sorted_indices and K.nnz == M.nnz
            and np.array_equal(K.indptr, M.indptr) and np.array_equal(K.indices, M.indices)):
        A = sp.csc_matrix((K.data - sigma * M.data, K.indices, K.indptr), shape=K.shape)  # one pattern
    else:
        A = (K - sigma * M).tocsc()
    A.sort_indices()
    factor = (cache or CholmodCache()).factor(A)
    if factor is None:
        return None
    return spla.LinearOperator(K.shape, matvec=factor.solve_A, dtype=float)


PINV_RTOL = 1e3 * np.finfo(float).eps  # eigenvalues of K_oo below this of its largest: a mechanism (dropped)


def condense_dense(K: np.ndarray, M: np.ndarray, omitted: np.ndarray):
    """Static (Guyan) condensation of dense symmetric K, M onto the DOFs not in ``omitted`` (indices):
    (kept, K_r, M_r, G) with u_o = G u_a, G = -K_oo^+ K_oa, K_r = K_aa + K_ao G, M_r = T^T M T for
    T = [I; G] (fem.reduction). K_oo may be singular where the omitted DOFs hold a mechanism with
    neither mass nor stiffness (a spin about a line of point masses on massless rotations): its
    pseudo-inverse drops those directions (below PINV_RTOL of its largest eigenvalue), which carry
    no motion (their eigenvalue is undefined, not a mode)."""
    o = np.zeros(K.shape[0], bool)
    o[omitted] = True
    a, o = np.flatnonzero(~o), np.flatnonzero(o)
    K = 0.5 * (K + K.T)
    w, V = np.linalg.eigh(K[np.ix_(o, o)])
    big = np.abs(w) > PINV_RTOL * max(np.abs(w).max(initial=0.0), 1e-300)
    G = -(V[:, big] / w[big]) @ (V[:, big].T @ K[np.ix_(o, a)])
    Kr = K[np.ix_(a, a)] + K[np.ix_(a, o)] @ G
    cross = M[np.ix_(a, o)] @ G
    Mr = M[np.ix_(a, a)] + cross + cross.T + G.T @ M[np.ix_(o, o)] @ G
    return a, 0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T), G


def _massless_mechanism(A: np.ndarray, B: np.ndarray) -> bool:
    """DOFs with no mass (zero rows of B) holding a motion with no stiffness either (a spin about a line
    of point masses on massless rotations): the pencil A - lam B is singular for every lam, and a
    solver's result for it hangs on the sign of round-off."""
    zero = ~np.any(B != 0, axis=0)
    if not zero.any():
        return False
    w = np.abs(np.linalg.eigvalsh(0.5 * (A + A.T)[np.ix_(zero, zero)]))
    return bool(w.min() <= PINV_RTOL * max(w.max(), 1e-300))


def _condensed_modes(A: np.ndarray, B: np.ndarray, dm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every finite eigenpair of A phi = lam B phi with B semi-definite and singular: the massless DOFs
    condensed out (fem.reduction, exact for them), the modes expanded back. The massless DOFs are B's
    zero rows where the rest of B is definite, else B's null eigenvectors."""
    zero = ~np.any(B != 0, axis=0)
    tol = 1e-14 * max(dm.max(), 1e-300)
    basis = None
    if not (zero.any() and np.all(np.linalg.eigvalsh(B[np.ix_(~zero, ~zero)]) > tol)):
        w, basis = np.linalg.eigh(B)
        zero = w <= tol
        A, B = basis.T @ A @ basis, np.diag(np.where(zero, 0.0, w))
    kept, Kr, Mr, G = condense_dense(A, B, np.flatnonzero(zero))
    lam, phi_a = sla.eigh(Kr, Mr)
    phi = np.empty((A.shape[0], len(lam)))
    phi[kept] = phi_a
    phi[zero] = G @ phi_a
    return lam, (phi if basis is None else basis @ phi)


def _residuals(K: sp.spmatrix, M: sp.spmatrix, lam: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """|K phi - lam M phi| / (|K phi| + |lam| |M phi|) of each eigenpair."""
    Kp, Mp = K @ phi, M @ phi
    scale = np.linalg.norm(Kp, axis=0) + np.abs(lam) * np.linalg.norm(Mp, axis=0)
    return np.linalg.norm(Kp - Mp * lam, axis=0) / np.where(scale > 0, scale, 1.0)


_NO_MASS = ("no mode: the free DOFs carry no mass (every element's density is zero and there is no "
            "concentrated mass on them, or all the mass sits on fixed DOFs); give the materials a density rho "
            "[kg/m^3] or add concentrated masses (model.add_mass) on the free part")


def real_modes(K: sp.spmatrix, M: sp.spmatrix, n_modes: int, shift: float | None = None, clamped: bool = False,
               cholmod: CholmodCache | None = None, use_cholmod: bool = True):
    """Lowest n_modes of K phi = lam M phi (K symmetric, possibly singular or indefinite).

    clamped: the constraints restrain every rigid-body motion (no cluster of near-zero modes), so
    the sparse eigensolver runs without a margin of extra pairs. cholmod: a symbolic analysis of
    K's pattern to reuse; use_cholmod=False: SuperLU's shift-invert even where CHOLMOD is installed.
    """
    n = K.shape[0]
    k = min(n_modes, n)
    dm = np.abs(M.diagonal())
    if not (np.all(np.isfinite(K.data)) and np.all(np.isfinite(M.data))):
        raise SolverError("real_modes: the stiffness or mass matrix holds NaN or infinite entries (an overflowing "
                          "input value or a diverged state); check the model's values (see fem.checks.check_matrix)")
    if not np.any(M.data):
        raise ModelError(_NO_MASS)
    sigma = DEFAULT_SHIFT if shift is None else shift
    if n <= DENSE_LIMIT or k >= n - 1:
        A = K.toarray()
        B = M.toarray()
        # Shift-invert first, B phi = mu (A - s B) phi with mu = 1 / (lam - s): its round-off is relative
        # to the lowest eigenvalue, where the direct A phi = lam B phi's is relative to the largest. On a
        # 20-element cantilever strip held by a grounded spring 7e7 times stiffer than the strip (axially)
        # the direct form put the first frequency 59 % off; the shift-invert one agrees with the clamped
        # strip to 1e-9. It needs A - s B definite (s below every eigenvalue, clear of the rigid-body
        # round-off: see _rigid_safe_shift); mu = 0 for massless DOFs.
        s_inv = sigma if shift is not None or clamped else _rigid_safe_shift(K, dm, sigma)
        b_definite = bool(np.all(np.linalg.eigvalsh(B) > 1e-14 * max(dm.max(), 1e-300)))
        lam = None
        if not b_definite and _massless_mechanism(A, B):  # a singular pencil: condense the massless DOFs
            lam, phi = _condensed_modes(A, B, dm)
        else:
            try:
                mu, phi = sla.eigh(B, A - s_inv * B)
                # Massless DOFs give mu at round-off; with a definite B every mu is a mode's.
                keep = mu > (100 * np.finfo(float).eps if b_definite else 1e-12) * max(mu.max(initial=0.0), 1e-300)
                lam, phi = s_inv + 1.0 / mu[keep], phi[:, keep]
                if len(lam) < k and b_definite:  # every mode asked for, the highest lost below round-off
                    lam = None
            except np.linalg.LinAlgError:  # indefinite (buckled, unstable) or singular
                lam = None
        if lam is None and not b_definite and np.all(np.linalg.eigvalsh(B) > -1e-14 * max(dm.max(), 1e-300)):
            # Massless DOFs with A - s B not definite: their static condensation is exact, where the
            # general solver below returns spurious finite eigenvalues for them (QZ on a singular B).
            lam, phi = _condensed_modes(A, B, dm)
        if lam is None and b_definite:
            try:
                lam, phi = sla.eigh(A - sigma * B, B)
                lam = lam + sigma
            except np.linalg.LinAlgError:
                lam = None
        if lam is None:  # the general solver
            try:
                w, v = sla.eig(A, B)
            except np.linalg.LinAlgError as exc:
                raise SolverError(f"the dense eigensolver failed ({exc}): the stiffness and mass matrices are too "
                                  "badly scaled; check the model for absurd values (stiffness, mass, coordinates)"
                                  ) from exc
            ok = np.isfinite(w)
            lam, phi = w[ok].real, v[:, ok].real
        if len(lam) == 0:
            raise ModelError(_NO_MASS)
        order = np.argsort(lam)[:k]
        lam, phi = lam[order], phi[:, order]
    else:
        try:
            # A margin of extra pairs where rigid-body modes cluster at zero (ARPACK can miss members
            # of such clusters); none when the constraints restrain them: repeated elastic pairs
            # (square sections) were all found without it, and the margin costs a Lanczos restart.
            k_run = min(n - 2, k if clamped else k + max(6, k // 4))
            if shift is None and not clamped:
                sigma = _rigid_safe_shift(K, dm, sigma)
            Mop = M.tocsr()  # ARPACK multiplies by M a few times per pair: leave exact zeros out
            Mop.eliminate_zeros()
            # A fixed start vector: ARPACK's own is random, so results (and an optimiser's path through
            # nearly repeated modes) would change from one run to the next in the last digits.
            v0 = np.random.default_rng(0).standard_normal(n)

            def run(s):
                return spla.eigsh(K.tocsc(), k=k_run, M=Mop, sigma=s, which="LM", mode="normal",
                                  OPinv=_cholesky_inverse(K, M, s, cholmod) if use_cholmod else None, tol=1e-12,
                                  v0=v0)

            lam, phi = run(sigma)
            if shift is None and not clamped:
                # A shift thousands of times closer to the rigid-body cluster than to the lowest
                # elastic eigenvalue can leave ARPACK's elastic pairs unconverged without a word (the
                # free-free glider deck fmondsp.dat: residuals 1e-5 to 1e-3 and frequencies off by up
                # to 1e-3 at -0.004 rad^2/s^2 with lambda_1 = 1147; converged pairs have residuals
                # near 1e-8). Then the shift moves to 1e-3 of the lowest elastic eigenvalue found.
                elastic = lam > 100 * np.finfo(float).eps * _lambda_max_bound(K, dm)
                worst = _residuals(K, M, lam[elastic], phi[:, elastic]).max(initial=0.0)
                if worst > 1e-6:
                    lam2, phi2 = run(min(sigma, -1e-3 * lam[elastic].min()))
                    elastic2 = lam2 > 100 * np.finfo(float).eps * _lambda_max_bound(K, dm)
                    if _residuals(K, M, lam2[elastic2], phi2[:, elastic2]).max(initial=0.0) < worst:
                        lam, phi = lam2, phi2
        except RuntimeError as exc:
            raise SolverError(f"eigensolver failed ({exc}); the model may have a mechanism with no mass") from exc
        order = np.argsort(lam)[:k]
        # ARPACK's generalised mode returns M-orthonormal Ritz vectors (to ~1e-14, tested).
        return lam[order], phi[:, order]
    mm = np.einsum("ij,ij->j", phi, M @ phi)
    bad = mm <= 0
    if np.any(bad):
        raise SolverError("a mode has zero or negative modal mass: some DOFs carry stiffness but no mass and no "
                          "stiffness-free mass; check rotary inertia, lumped masses and constraints")
    phi = phi / np.sqrt(mm)
    return lam, phi


def complex_modes(K: sp.spmatrix, C: sp.spmatrix, M: sp.spmatrix, n_modes: int, clamped: bool = False,
                  n_rigid: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Lowest n_modes complex eigenpairs of (s^2 M + s C + K) phi = 0 (state-space, dense or sparse).

    One root per mode: one of each conjugate pair, and one of the double zero root of each
    undamped rigid-body motion (both have its shape). clamped: no rigid-body motion is free;
    n_rigid: at most this many rigid motions (the rest of the near-zero roots are physical).
    """
    n = K.shape[0]
    lam_max = _lambda_max_bound(K, np.abs(M.diagonal()))
    if n <= DENSE_LIMIT // 2:
        Kd, Cd, Md = K.toarray(), C.toarray(), M.toarray()
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Kd, -Cd]])
        B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), Md]])
        try:
            s, v = sla.eig(A, B)
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise SolverError(f"the dense complex eigensolver failed ({exc}): check the stiffness, damping and mass "
                              "values of the model for absurd entries") from exc
        ok = np.isfinite(s)
        s, v = s[ok], v[:n, ok]
    else:
        # Shift-invert on the linearised pencil with sigma near zero through a complex LU of K + sigma C + sigma^2 M.
        sigma = 1e-3
        if not clamped:  # rigid motions: K + sigma^2 M must stay clear of round-off (see _rigid_safe_shift)
            sigma = max(sigma, np.sqrt(_RIGID_MARGIN * np.finfo(float).eps * lam_max))
        Q = (K + sigma * C + sigma**2 * M).tocsc().astype(complex)
        try:
            lu = spla.splu(Q)
        except RuntimeError as exc:  # exactly singular: a mechanism without mass or damping
            raise SolverError(f"complex modes: K + s C + s^2 M is singular at s = {sigma:g} rad/s ({exc}): the model "
                              "has a mechanism that nothing (stiffness, damping or mass) restrains; fix or connect it"
                              ) from exc

        def op(z):
            x1, x2 = z[:n], z[n:]
            # (A - sigma B)^{-1} B z for A = [[0, I], [-K, -C]], B = diag(I, M)
            rhs = -(M @ x2) - (C + sigma * M) @ x1
            y1 = lu.solve(rhs.astype(complex))
            y2 = sigma * y1 + x1
            return np.concatenate([y1, y2])

        L = spla.LinearOperator((2 * n, 2 * n), matvec=op, dtype=complex)
        # A fixed start vector, as in real_modes: ARPACK's own is random, and the highest roots asked
        # for moved by ~3e-9 from one call to the next on the same matrices (strip, cords damped).
        v0 = np.random.default_rng(0).standard_normal(2 * n).astype(complex)
        try:
            nu, v = spla.eigs(L, k=min(2 * n_modes + 4, 2 * n - 2), which="LM", v0=v0)
        except RuntimeError as exc:  # ARPACK's errors (no convergence) are RuntimeErrors
            raise SolverError(f"complex eigensolver failed ({exc}); the model may have a mechanism with no mass"
                              ) from exc
        s = sigma + 1.0 / nu
        v = v[:n]
    keep = s.imag >= -1e-9 * np.maximum(np.abs(s), 1.0)  # one of each conjugate pair (and overdamped roots)
    s, v = s[keep], v[:, keep]
    order = np.argsort(np.abs(s))
    s, v = s[order], v[:, order]
    # Roots at the round-off level of zero are rigid motions; each undamped one is a double root
    # (two copies of its shape): keep the first copy of each shape.
    zero = np.abs(s) < 10 * np.sqrt(np.finfo(float).eps * max(lam_max, 1.0))
    if n_rigid is not None and zero.sum() > 2 * n_rigid:  # each rigid motion: a double root
        zero[np.argsort(np.abs(s))[2 * n_rigid:]] = False
    zero_idx = np.flatnonzero(zero)
    mac = mac_matrix(v[:, zero_idx], v[:, zero_idx])
    taken = []
    for j in range(len(zero_idx)):
        if all(mac[i, j] < 0.9 for i in taken):
            taken.append(j)
    taken = zero_idx[taken]
    s = np.where(zero, 0.0, s)
    chosen = np.r_[taken, np.flatnonzero(~zero)].astype(int)[:n_modes]
    s, v = s[chosen], v[:, chosen]
    # Normalise each mode so that its largest component is real and phi^H M phi = 1.
    big = v[np.argmax(np.abs(v), axis=0), np.arange(v.shape[1])]
    v = v * (np.abs(big) / np.where(big == 0, 1, big))
    mm = np.real(np.einsum("ij,ij->j", v.conj(), M @ v))
    v = v / np.sqrt(np.where(mm > 0, mm, 1.0))
    return s, v


def rigid_count(system, x: np.ndarray, T, K, M) -> int:
    """How many rigid-body modes the structure has at the state: the rigid motions the fixed DOFs
    leave free whose Rayleigh quotient (tangent over mass, cords, springs and gravity's load
    stiffness included) is zero to within its own round-off eps |U|^T |K| |U|. That bound is set
    by the mass the stiff members move, not by the stiffest element's K/M, so a suspended
    structure's pendulum and plunge modes are never taken for rigid ones."""
    motions, basis = system.unrestrained_rigid_motions(x)
    if basis.shape[1] == 0:
        return 0
    U = system.reduce_displacement(motions @ basis)
    Kr = U.T @ (K @ U)
    Mr = U.T @ (M @ U)
    Ua = np.abs(U)
    err = np.finfo(float).eps * (Ua.T @ (abs(K) @ Ua))
    try:
        # Rigid motions that carry no mass (a spin about a line of point masses) have no mode: leave them out.
        w, V = np.linalg.eigh(0.5 * (Mr + Mr.T))
        V = V[:, w > 1e-12 * max(w.max(), 1e-300)] / np.sqrt(w[w > 1e-12 * max(w.max(), 1e-300)])
        if V.shape[1] == 0:
            return 0
        lam = np.linalg.eigvalsh(V.T @ (0.5 * (Kr + Kr.T)) @ V)  # M-orthonormal rigid subspace
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolverError(f"configuration '{system.config.name}': counting the rigid-body modes failed ({exc}): the "
                          "stiffness or mass of the rigid motions overflows; check the model for absurd values "
                          "(densities, masses, coordinates)") from exc
    bound = 100 * float(np.max(np.abs(V).T @ err @ np.abs(V)))
    return int(np.sum(np.abs(lam) <= bound))


def modal_frequencies_hz(lam: np.ndarray, K: sp.spmatrix, M: sp.spmatrix, system, x: np.ndarray, T=None,
                         n_rigid: int | None = None) -> np.ndarray:
    """Frequencies [Hz] of the eigenvalues lam [rad^2/s^2] of the reduced K, M of ``system`` at node
    positions x [m] (T: its link transformation or None), as solve_modes reports them: rigid-body
    eigenvalues, zero only to about eps * lambda_max (see _rigid_safe_shift), become exactly 0, at
    most as many as the structure has rigid-body modes (rigid_count, or ``n_rigid`` when the caller
    has counted them already); negative: unstable."""
    if system.clamped:
        return _frequency_hz(lam, 0.0, None)
    return _frequency_hz(lam, 100 * np.finfo(float).eps * _lambda_max_bound(K, np.abs(M.diagonal())),
                         rigid_count(system, x, T, K, M) if n_rigid is None else n_rigid)
