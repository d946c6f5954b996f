"""Static (Guyan) condensation: the omitted DOFs o follow the kept (analysis) DOFs a as the
stiffness alone says, u_o = G u_a with G = -K_oo^-1 K_oa, and the modes are those of

    K_r = K_aa + K_ao G,   M_r = T^T M T,   T = [I; G]   (rows in a, o order),

expanded back to every DOF by u_o = G u_a. Exact where the omitted DOFs carry no mass (the
eigenproblem's massless DOFs have infinite eigenvalues; condensing them out is how the finite ones
are found when K - sigma M is singular there); an approximation otherwise (the reduced model is
stiffer: each reduced frequency lies at or above the full model's of the same order).

``condense_dense`` serves the dense eigensolver (massless DOFs and mechanisms that carry neither
mass nor stiffness: a pseudo-inverse of K_oo); ``guyan`` the sparse models of a Nastran deck's
ASET/OMIT (a factorisation of K_oo, which must be non-singular as Nastran requires).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolverError

PINV_RTOL = 1e3 * np.finfo(float).eps  # eigenvalues of K_oo below this of its largest: a mechanism (dropped)


@dataclass(frozen=True)
class Reduced:
    """K_r, M_r (n_a, n_a) dense; kept (n_a,) and omitted (n_o,) DOF indices; G (n_o, n_a): u_o = G u_a."""

    K: np.ndarray
    M: np.ndarray
    kept: np.ndarray
    omitted: np.ndarray
    G: np.ndarray

    def expand(self, phi_a: np.ndarray) -> np.ndarray:
        """Vectors on every DOF (n, ...) from vectors on the kept ones (n_a, ...)."""
        n = len(self.kept) + len(self.omitted)
        out = np.zeros((n,) + phi_a.shape[1:])
        out[self.kept] = phi_a
        out[self.omitted] = self.G @ phi_a
        return out


def _split(n: int, omitted) -> tuple[np.ndarray, np.ndarray]:
    o = np.zeros(n, bool)
    o[np.asarray(omitted, dtype=int)] = True
    return np.flatnonzero(~o), np.flatnonzero(o)


def condense_dense(K: np.ndarray, M: np.ndarray, omitted) -> Reduced:
    """Guyan condensation of dense symmetric K, M onto the DOFs not in ``omitted`` (indices). K_oo may
    be singular where the omitted DOFs hold a mechanism with neither mass nor stiffness (a spin about
    a line of point masses on massless rotations): its pseudo-inverse drops those directions, which
    then carry no motion (their eigenvalue is undefined, not a mode)."""
    a, o = _split(K.shape[0], omitted)
    K = 0.5 * (K + K.T)
    Koo = K[np.ix_(o, o)]
    w, V = np.linalg.eigh(Koo)
    big = np.abs(w) > PINV_RTOL * max(np.abs(w).max(initial=0.0), 1e-300)
    Vb = V[:, big]
    G = -(Vb / w[big]) @ (Vb.T @ K[np.ix_(o, a)])
    Kr = K[np.ix_(a, a)] + K[np.ix_(a, o)] @ G
    Mr = _mass(M, a, o, G)
    return Reduced(0.5 * (Kr + Kr.T), Mr, a, o, G)


def _mass(M, a, o, G) -> np.ndarray:
    """T^T M T for T = [I; G] (dense or sparse M)."""
    Maa = M[np.ix_(a, a)] if isinstance(M, np.ndarray) else M[a][:, a].toarray()
    if isinstance(M, np.ndarray):
        Mao, Moo = M[np.ix_(a, o)], M[np.ix_(o, o)]
    else:
        Mao, Moo = M[a][:, o], M[o][:, o]
    cross = np.asarray(Mao @ G)
    Mr = Maa + cross + cross.T + G.T @ np.asarray(Moo @ G)
    return 0.5 * (Mr + Mr.T)


def guyan(K: sp.spmatrix, M: sp.spmatrix, omitted) -> Reduced:
    """Guyan reduction of sparse symmetric K, M (reduced DOFs) onto the DOFs not in ``omitted``:
    K_oo factorised once (SuperLU), G solved for every kept DOF at once. Raises SolverError if K_oo
    is singular (the omitted DOFs hold a mechanism or a rigid motion the kept set does not: Nastran
    stops there too)."""
    K = sp.csc_matrix(K)
    a, o = _split(K.shape[0], omitted)
    if len(a) == 0:
        raise SolverError("Guyan reduction: every DOF is omitted; keep at least the DOFs of the modes wanted "
                          "(ASET/ASET1) or omit fewer (OMIT/OMIT1)")
    if len(o) == 0:
        return Reduced(K.toarray(), sp.csc_matrix(M).toarray(), a, o, np.zeros((0, len(a))))
    Kc = K.tocsr()
    Koo = Kc[o][:, o].tocsc()
    Koa = Kc[o][:, a].toarray()
    try:
        lu = spla.splu(Koo, permc_spec="COLAMD", options={"SymmetricMode": True})
    except RuntimeError as exc:
        raise SolverError(f"Guyan reduction: the stiffness of the {len(o)} omitted DOFs (K_oo) is singular ({exc}): "
                          "they hold a mechanism or a rigid-body motion that the analysis set does not restrain; add "
                          "DOFs of that motion to ASET (or leave them out of OMIT)") from exc
    G = -lu.solve(Koa)
    if not np.all(np.isfinite(G)):
        raise SolverError(f"Guyan reduction: the stiffness of the {len(o)} omitted DOFs (K_oo) is singular (non-finite "
                          "solve); add the DOFs of the unrestrained motion to ASET (or leave them out of OMIT)")
    Kr = Kc[a][:, a].toarray() + np.asarray(Kc[a][:, o] @ G)
    return Reduced(0.5 * (Kr + Kr.T), _mass(sp.csr_matrix(M), a, o, G), a, o, G)
