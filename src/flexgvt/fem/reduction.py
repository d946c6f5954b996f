"""Static (Guyan) reduction, as Nastran applies a deck's ASET/ASET1 and OMIT/OMIT1: the omitted DOFs
o follow the analysis DOFs a as the stiffness alone says, u_o = G u_a with G = -K_oo^-1 K_oa, and
the modes are those of

    K_r = K_aa + K_ao G,   M_r = T^T M T,   T = [I; G]   (rows in a, o order),

expanded back to every DOF by u_o = G u_a. Exact where the omitted DOFs carry no mass (their
eigenvalues are infinite); otherwise the reduced model is stiffer and each reduced frequency lies at
or above the full model's of the same order (Rayleigh-Ritz on the columns of T).

Sets (``sets``: a BdfDeck's ``options``, or any mapping with 'ASET' and/or 'OMIT' -> {grid id:
components '1'-'6' in basic axes}): with an 'ASET' every free DOF outside it is omitted (Nastran:
the a-set names what is kept, 'OMIT' is then implied); with only 'OMIT' those DOFs are omitted.
Fixed DOFs and DOFs tied by rigid links are in neither set (Nastran's s- and m-sets) and are skipped.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ModelError, SolverError
from .eigen import PINV_RTOL, real_modes

SET_KEYS = ("ASET", "OMIT")


@dataclass(frozen=True)
class Reduced:
    """K, M (n_a, n_a) dense reduced matrices; kept (n_a,) and omitted (n_o,) indices into the
    system's reduced DOFs; G (n_o, n_a): u_o = G u_a."""

    K: np.ndarray
    M: np.ndarray
    kept: np.ndarray
    omitted: np.ndarray
    G: np.ndarray

    def expand(self, phi_a: np.ndarray) -> np.ndarray:
        """Vectors on every DOF (n, ...) from vectors on the analysis set (n_a, ...)."""
        out = np.zeros((len(self.kept) + len(self.omitted),) + phi_a.shape[1:])
        out[self.kept] = phi_a
        out[self.omitted] = self.G @ phi_a
        return out


def guyan(K: sp.spmatrix, M: sp.spmatrix, omitted) -> Reduced:
    """Guyan reduction of sparse symmetric K, M onto the DOFs not in ``omitted`` (indices): K_oo
    factorised once (SuperLU), G solved for every kept DOF at once. SolverError if K_oo is singular
    (the omitted DOFs hold a mechanism or a rigid-body motion the analysis set does not restrain:
    Nastran stops there too)."""
    n = K.shape[0]
    mask = np.zeros(n, bool)
    mask[np.asarray(omitted, dtype=int)] = True
    a, o = np.flatnonzero(~mask), np.flatnonzero(mask)
    if len(a) == 0:
        raise SolverError("Guyan reduction: every free DOF is omitted; keep the DOFs that describe the modes wanted "
                          "(ASET/ASET1) or omit fewer (OMIT/OMIT1)")
    Kc, Mc = sp.csr_matrix(K), sp.csr_matrix(M)
    if len(o) == 0:
        return Reduced(Kc.toarray(), Mc.toarray(), a, o, np.zeros((0, n)))
    Ko = Kc[o]
    try:
        Koo = Ko[:, o].tocsc()
        lu = spla.splu(Koo, permc_spec="COLAMD", options={"SymmetricMode": True})
        G = -lu.solve(Ko[:, a].toarray())
    except RuntimeError as exc:
        G, why = None, str(exc)
    else:  # a pivot at round-off of the stiffest DOF's: a rigid motion or a mechanism, singular in exact arithmetic
        smallest = float(np.abs(lu.U.diagonal()).min())
        why = f"smallest pivot {smallest:.3g}, largest stiffness {float(np.abs(Koo.diagonal()).max()):.3g}"
        if smallest <= PINV_RTOL * np.abs(Koo.diagonal()).max():
            G = None
    if G is None or not np.all(np.isfinite(G)):
        raise SolverError(f"Guyan reduction: the stiffness of the {len(o)} omitted DOFs (K_oo) is singular ({why}): "
                          "they hold a mechanism or a rigid-body motion that the analysis set does not restrain; put "
                          "DOFs of that motion in ASET (or leave them out of OMIT)")
    Ka = Kc[a]
    Kr = Ka[:, a].toarray() + np.asarray(Ka[:, o] @ G)
    Ma = Mc[a]
    cross = np.asarray(Ma[:, o] @ G)
    Mr = Ma[:, a].toarray() + cross + cross.T + G.T @ np.asarray(Mc[o][:, o] @ G)
    return Reduced(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T), a, o, G)


def _dofs(system, grids: Mapping, key: str) -> np.ndarray:
    """Reduced DOF indices of {grid id: components} (fixed and link-dependent ones left out)."""
    out = []
    for nid, comps in grids.items():
        where = f"reduction set {key}: grid {nid}"
        hit = np.flatnonzero(system.cm.node_ids == int(nid))
        if len(hit) == 0:
            raise ModelError(f"{where} is not a node of the model; give node ids of the model (a deck's ASET/OMIT "
                             "grids are its node ids)")
        comps = str(comps)
        if not comps or any(c not in "123456" for c in comps):
            raise ModelError(f"{where}: components {comps!r} must be digits 1-6")
        dofs = system.dof_map[6 * int(hit[0]) + np.array(sorted({int(c) - 1 for c in comps}))]
        out.append(dofs[dofs >= 0])
    return np.unique(np.concatenate(out)) if out else np.zeros(0, int)


def omitted_dofs(system, sets: Mapping) -> np.ndarray:
    """The system's reduced DOF indices that ``sets`` omits (see the module's docstring)."""
    aset, omit = sets.get("ASET"), sets.get("OMIT")
    if aset:
        kept = _dofs(system, aset, "ASET")
        mask = np.ones(system.n_free, bool)
        mask[kept] = False
        return np.flatnonzero(mask)
    if omit:
        return _dofs(system, omit, "OMIT")
    return np.zeros(0, int)


def guyan_modes(K: sp.spmatrix, M: sp.spmatrix, omitted: np.ndarray, n_modes: int, shift: float | None = None,
                clamped: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The lowest n_modes eigenpairs (lam [rad^2/s^2], shapes on every reduced DOF, M_r-normalised,
    which is phi^T M phi = 1 for the expanded shapes) of K, M Guyan-reduced by omitting ``omitted``."""
    red = guyan(K, M, omitted)
    lam, phi_a = real_modes(sp.csc_matrix(red.K), sp.csc_matrix(red.M), n_modes, shift, clamped, use_cholmod=False)
    return lam, red.expand(phi_a)
