"""The mode-shape derivatives' linear systems (K - lambda_i M) v = r of every mode with one
factorisation per configuration and design point.

Nelson's method factorises K - lambda_i M (one DOF pinned) once per mode: eight paired modes of
three configurations were 24 sparse LU factorisations per Jacobian of the wingbox. Here the
computed modes Phi (mass-normalised, the lowest m) split the solution: on them it is spectral,
v_s = sum_{j != i} phi_j phi_j^T r / (lambda_j - lambda_i); on their M-orthogonal complement Q,
where K - lambda_i M is positive definite (every eigenvalue there exceeds lambda_i), conjugate
gradients preconditioned by (K - sigma M)^-1 (sigma below every eigenvalue, one factorisation)
converge in a few steps, as that preconditioned operator's spectrum lies in
[(lambda_{m+1} - lambda_i) / (lambda_{m+1} - sigma), 1]. All right-hand sides of all modes go through
one block iteration. The result is the solution M-orthogonal to phi_i, which Nelson's normalisation
turns into the same derivative; the operator is symmetric, so the adjoint (projected) form holds.
The state's derivative du = -K^-1 dR goes through the same factor (lambda = 0) where the tangent
is symmetric (at equilibrium its skew part is proportional to the residual and to applied nodal
moments; checked, else its own LU).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from ..fem.linsolve import BACKENDS, CholmodCache, superlu

_TOLERANCE = 1e-12  # relative preconditioned residual of the conjugate gradients
_FLOOR = 1e-8  # a residual that stops falling (round-off of the stiff entries, ~1e-11) is accepted below this
_MAX_ITERATIONS = 200


class ModeSolver:
    """G_i r for the modes of one configuration at one design point: K (symmetric tangent), M, and
    the computed eigenpairs lam (m,), phi (n_free, m) (mass-normalised); K - sigma M is factorised
    once (the installed symmetric factorisation, fem.linsolve.BACKENDS[0], else SuperLU).
    ``iterations`` counts the block iterations (each one solve with the factor)."""

    def __init__(self, K: sp.csc_matrix, M: sp.csc_matrix, lam: np.ndarray, phi: np.ndarray):
        self.K, self.M = K, M
        self.lam = np.asarray(lam, float)
        self.phi = np.asarray(phi, float)
        self.Mphi = np.asarray(M @ self.phi)
        gram = self.phi.T @ self.Mphi
        if np.abs(gram - np.eye(len(self.lam))).max() > 1e-8:
            raise SolverError("ModeSolver: the modes are not mass-normalised (phi^T M phi != I)")
        low = min(float(self.lam.min()), 0.0)
        self.sigma = low - 0.1 * max(float(self.lam.max()) - low, 1e-12)
        A = (K - self.sigma * M).tocsc()
        # K - sigma M is symmetric positive definite (sigma below every eigenvalue): the installed
        # symmetric factorisation (PARDISO, CHOLMOD) where there is one, else SuperLU.
        self._cache = CholmodCache() if BACKENDS else None
        factor = self._cache.factor(0.5 * (A + A.T)) if self._cache is not None else None
        if factor is not None:
            self._solve = factor.solve_A
        else:
            try:
                self._solve = superlu(A).solve
            except RuntimeError as exc:
                raise SolverError(f"ModeSolver: K - sigma M is singular ({exc}); a mode below sigma was "
                                  "missed") from None
        self.iterations = 0

    def _project(self, X: np.ndarray) -> np.ndarray:
        """X with its components along the computed modes removed (M-orthogonal projection onto Q)."""
        return X - self.phi @ (self.Mphi.T @ X)

    def solve(self, R: np.ndarray, modes: np.ndarray) -> np.ndarray:
        """(n_free, c) G_i r of each column r of R (n_free, c), i = modes[column] (an index into the
        computed modes): the solution of (K - lambda_i M) v = r M-orthogonal to phi_i (r's own phi_i
        component is left out)."""
        R = np.asarray(R, float).reshape(len(R), -1)
        modes = np.asarray(modes, int)
        lam_c = self.lam[modes]
        gaps = self.lam[:, None] - lam_c[None, :]  # (m, c)
        own = np.arange(len(self.lam))[:, None] == modes[None, :]
        scale = np.maximum(np.abs(lam_c), 1e-300)
        if np.any((np.abs(gaps) <= 1e-10 * scale[None, :]) & ~own):
            raise SolverError("mode shape derivative: the eigenvalue is repeated, so its shape derivative is not "
                              "unique")
        a = self.phi.T @ R  # (m, c)
        coef = np.where(own, 0.0, a / np.where(own, 1.0, gaps))
        v = self.phi @ coef
        b = R - self.Mphi @ a  # the remainder, orthogonal to every computed mode
        return v + self._conjugate_gradients(b, lam_c)

    def solve_stiffness(self, R: np.ndarray) -> np.ndarray:
        """(n_free, c) K^-1 R: the same split with lambda = 0 (modal part Phi Lambda^-1 Phi^T R), for a
        positive definite K (SolverError otherwise: a mechanism or an unstable state)."""
        if self.lam.min() <= 0:
            raise SolverError("ModeSolver: K is not positive definite (a computed eigenvalue <= 0)")
        R = np.asarray(R, float).reshape(len(R), -1)
        a = self.phi.T @ R
        return self.phi @ (a / self.lam[:, None]) + self._conjugate_gradients(R - self.Mphi @ a, np.zeros(R.shape[1]))

    def _conjugate_gradients(self, b: np.ndarray, lam_c: np.ndarray) -> np.ndarray:
        """x in Q with (K - lam_c M) x = b column by column (b orthogonal to the computed modes).
        Stops on the preconditioned residual sqrt(r^T z) (about the error's energy norm: the
        preconditioned operator's condition number is below 1 / (1 - lambda_i / lambda_m+1)), not on
        |r|, which the stiff entries of K dominate."""
        x = np.zeros_like(b)
        if not np.any(b):
            return x
        r = b.copy()
        z = self._project(self._solve(r))
        p = z.copy()
        rz = np.sum(r * z, axis=0)
        rz0 = np.where(rz > 0, rz, 1.0)
        active = rz > 0
        best = np.ones(len(rz))  # smallest relative residual so far, and the steps since it halved
        stall = np.zeros(len(rz), int)
        for _ in range(_MAX_ITERATIONS):
            q = np.asarray(self.K @ p) - np.asarray(self.M @ p) * lam_c[None, :]
            pq = np.sum(p * q, axis=0)
            if np.any(pq[active] <= 0):
                raise SolverError("mode shape derivative: K - lambda M is not positive on the complement of the "
                                  "computed modes (a mode below the highest computed one was missed)")
            alpha = np.where(active, rz / np.where(active, pq, 1.0), 0.0)
            x += alpha * p
            r -= alpha * q
            self.iterations += 1
            z = self._project(self._solve(r))
            rz_new = np.sum(r * z, axis=0)
            res = np.sqrt(np.abs(rz_new) / rz0)
            better = res < 0.5 * best
            best = np.where(better, res, best)
            stall = np.where(better, 0, stall + 1)
            if np.any(active & (stall >= 4) & (best >= _FLOOR)):
                raise SolverError("mode shape derivative: the conjugate gradients stalled above their floor")
            active &= (res > _TOLERANCE) & (stall < 4)
            if not np.any(active):
                return x
            beta = np.where(active, rz_new / np.where(rz != 0, rz, 1.0), 0.0)
            rz = rz_new
            p = z + beta * p
        raise SolverError(f"mode shape derivative: the conjugate gradients did not converge in {_MAX_ITERATIONS} "
                          "steps")


__all__ = ["ModeSolver"]
