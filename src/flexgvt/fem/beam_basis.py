"""The assembly's derivative with respect to beam values, as element blocks per unit value.

The beam kernel is linear in its 8 coefficients per element (EA, GJ, bending and shear terms, see
beam.element_coefficients), and the mass matrix and gravity load are linear in the element's 8
mass values (rho A at both nodes, then rho Ip, rho Iy, rho Iz at the first node and at the
second). The derivative of the residual, tangent and mass matrix with respect to any change of
those values is therefore the same change applied to 8 + 8 element blocks evaluated once at the
state with unit values. Any number of beam design variables then costs these 16 element passes
and products with the sparse (8 n_elements, n_variables) matrices of their value derivatives,
instead of one assembly per variable.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from .beam import BeamData, beam_forces, beam_mass_matrices, local_mass_matrices, nodal_weights

N_VALUES = 8  # kernel coefficients, and mass values, per element


def mass_values(mass_per_length: np.ndarray, inertia_per_length: np.ndarray) -> np.ndarray:
    """(k, 8) mass values of k elements: rho A at both nodes, then (rho Ip, rho Iy, rho Iz) at each."""
    return np.concatenate([np.reshape(mass_per_length, (-1, 2)), np.reshape(inertia_per_length, (-1, 6))], axis=1)


def local_unit_masses(beams: BeamData, rows: np.ndarray) -> np.ndarray:
    """(k, 8, 12, 12) element-axes mass matrices of elements ``rows`` per unit of each mass value
    (they do not depend on the state)."""
    sub = beams.take(rows)
    k = len(rows)
    out = np.empty((k, N_VALUES, 12, 12))
    for j in range(N_VALUES):
        unit = np.zeros((k, N_VALUES))
        unit[:, j] = 1.0
        data = replace(sub, mass_per_length=unit[:, :2], inertia_per_length=unit[:, 2:].reshape(k, 2, 3))
        out[:, j] = local_mass_matrices(data)
    return out


@dataclass(frozen=True)
class BeamBasis:
    """Element blocks per unit beam value at one state, for elements ``rows``.

    g (k, 8, 12): internal force per unit kernel coefficient; K (k, 8, 12, 12): the symmetric part
    of the consistent tangent per unit coefficient (all that quadratic forms and the modes' products
    need); f (k, 8, 12): applied gravity load per unit mass value; M (k, 8, 12, 12): mass matrix
    per unit mass value; dofs (k, 12): the element DOFs' full indices (6 node + component);
    reduced (k, 12): their reduced indices (-1 where fixed, or tied by a link); n_free, n_full: the
    numbers of reduced DOFs and of all DOFs."""

    rows: np.ndarray
    g: np.ndarray
    K: np.ndarray
    f: np.ndarray
    M: np.ndarray
    dofs: np.ndarray
    reduced: np.ndarray
    n_free: int
    n_full: int
    _layout: dict = field(default_factory=dict, repr=False, compare=False)

    def element_values(self, full: np.ndarray) -> np.ndarray:
        """(k, 12, ...) element values of full-DOF vectors (6 n_nodes, ...)."""
        return full[self.dofs]

    def scatter(self, values: np.ndarray, full: bool = False) -> sp.csc_matrix:
        """(n_free, c k) matrix whose column (e, j) is values[e, j] (12,) on element e's reduced DOFs,
        for values (k, c, 12); full: on all DOFs ((6 n_nodes, c k), systems with links)."""
        k, c = values.shape[:2]
        if (c, full) not in self._layout:
            target = self.dofs if full else self.reduced
            keep = target >= 0
            rows = np.broadcast_to(target[:, None, :], (k, c, 12))
            mask = np.broadcast_to(keep[:, None, :], rows.shape)
            counts = np.broadcast_to(keep.sum(axis=1)[:, None], (k, c)).ravel()
            self._layout[(c, full)] = (mask, rows[mask], np.r_[0, np.cumsum(counts)])
        mask, indices, indptr = self._layout[(c, full)]
        return sp.csc_matrix((values[mask], indices, indptr), shape=(self.n_full if full else self.n_free, k * c))

    def quadratic(self, ph: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(8 k, m) element quadratic forms ph_i^T K[e, j] ph_i and ph_i^T M[e, j] ph_i of element
        values ph (k, 12, m)."""
        k, _, m = ph.shape
        KP = (self.K.reshape(k, N_VALUES * 12, 12) @ ph).reshape(k, N_VALUES, 12, m)
        MP = (self.M.reshape(k, N_VALUES * 12, 12) @ ph).reshape(k, N_VALUES, 12, m)
        qK = np.sum(KP * ph[:, None], axis=2)
        qM = np.sum(MP * ph[:, None], axis=2)
        return qK.reshape(-1, m), qM.reshape(-1, m)

    def products(self, ph: np.ndarray, lam: float, full: bool = False) -> sp.csc_matrix:
        """(n_free, 16 k) matrix of K[e, j] ph (columns (e, j), j < 8) and -lam M[e, j] ph (j >= 8)
        on the reduced DOFs (full: on all DOFs), for element values ph (k, 12) of one mode with
        eigenvalue lam."""
        return self.scatter(self._element_products(ph, lam), full)

    def bilinear(self, ph: np.ndarray, w: np.ndarray, lam: float) -> np.ndarray:
        """(16 k, n_out) element bilinear forms w_o^T K[e, j] ph (j < 8) and -lam w_o^T M[e, j] ph
        (j >= 8), in the column order of ``products``, for element values ph (k, 12) of one mode and
        w (k, 12, n_out)."""
        return (self._element_products(ph, lam) @ w).reshape(len(ph) * 2 * N_VALUES, -1)

    def _element_products(self, ph: np.ndarray, lam: float) -> np.ndarray:
        """(k, 16, 12): K[e, j] ph then -lam M[e, j] ph per element."""
        k = len(ph)
        out = np.empty((k, 2 * N_VALUES, 12))
        out[:, :N_VALUES] = (self.K.reshape(k, N_VALUES * 12, 12) @ ph[:, :, None]).reshape(k, N_VALUES, 12)
        out[:, N_VALUES:] = (self.M.reshape(k, N_VALUES * 12, 12) @ ph[:, :, None]).reshape(k, N_VALUES, 12)
        out[:, N_VALUES:] *= -lam
        return out

    def bilinear_mass(self, ph: np.ndarray) -> np.ndarray:
        """(8 k, m, m) element mass bilinear forms ph^T M[e, j] ph of element values ph (k, 12, m)."""
        k, _, m = ph.shape
        MP = (self.M.reshape(k, N_VALUES * 12, 12) @ ph).reshape(k, N_VALUES, 12, m)
        return (np.swapaxes(ph, 1, 2)[:, None] @ MP).reshape(-1, m, m)


def beam_basis(system, x: np.ndarray, R: np.ndarray, lam: float, rows: np.ndarray, local_units: np.ndarray,
               stiffness: bool = True) -> BeamBasis:
    """BeamBasis of ``system``'s beam elements ``rows`` at positions x, rotations R and load factor lam;
    local_units: local_unit_masses of those rows; stiffness=False leaves g and K empty (mass only)."""
    rows = np.asarray(rows, int)
    sub = system.cm.beams.take(rows)
    k = len(rows)
    g = np.zeros((k, N_VALUES, 12))
    K = np.zeros((k, N_VALUES, 12, 12))
    if stiffness:
        for j in range(N_VALUES):
            unit = np.zeros((k, N_VALUES))
            unit[:, j] = 1.0
            g[:, j], K[:, j], _ = beam_forces(x, R, replace(sub, stiffness=unit), True)
        K = 0.5 * (K + np.swapaxes(K, 2, 3))
    M = np.empty((k, N_VALUES, 12, 12))
    for j in range(N_VALUES):
        M[:, j] = beam_mass_matrices(x, R, sub, local_units[:, j])
    f = np.zeros((k, N_VALUES, 12))
    gvec = system.config.gravity_vector
    for j in range(2):
        unit = np.zeros((k, 2))
        unit[:, j] = 1.0
        w1, w2 = nodal_weights(replace(sub, mass_per_length=unit))
        f[:, j, 0:3] = lam * w1[:, None] * gvec[None, :]
        f[:, j, 6:9] = lam * w2[:, None] * gvec[None, :]
    dofs = (6 * sub.nodes[:, :, None] + np.arange(6)[None, None, :]).reshape(k, 12)
    return BeamBasis(rows, g, K, f, M, dofs, system.dof_map[dofs], system.n_free, 6 * system.n_nodes)


__all__ = ["BeamBasis", "N_VALUES", "beam_basis", "local_unit_masses", "mass_values"]
