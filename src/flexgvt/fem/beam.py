"""Corotational 3D beam: internal forces, exact consistent tangent and mass about any state.

The element frame follows the chord and the mean of the nodal e2 directions (Crisfield); the
local element is a Timoshenko beam whose axial strain carries the shallow-arch term, so the
tangent contains both the chord-rotation (P-Delta) and the in-element (P-delta) geometric
stiffness. Nodal rotations are updated by spatial spins and local rotations are measured with
the SO(3) logarithm, so large rotations (a cantilever rolled into a full circle) are exact.

The tangent is the derivative of the internal-force vector with respect to (dx, spin) and is
obtained by forward differentiation of every kinematic quantity by hand (all elements at once).
It is non-symmetric away from equilibrium; its symmetric part is the Hessian of the energy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from ._beam_kernel import _CHUNK, _beam_chunk, beam_kernel, element_frames_at
from .rotations import cross

@dataclass(frozen=True)
class BeamData:
    """Per-element arrays of all beams of a model (n elements)."""

    nodes: np.ndarray  # (n, 2) node storage indices
    E0: np.ndarray  # (n, 3, 3) undeformed frames, columns = local x, y, z
    L0: np.ndarray  # (n,) undeformed lengths [m]
    stiffness: np.ndarray  # (n, 6) kernel coefficients EA, GJ, kd_y, ko_y, kd_z, ko_z (see bending_coefficients)
    mass_per_length: np.ndarray  # (n,) rho*A [kg/m]
    inertia_per_length: np.ndarray  # (n, 3) rho*Ip, rho*Iy, rho*Iz (bending terms zero if no rotary inertia)
    lumped: np.ndarray  # (n,) bool
    section_stiffness: np.ndarray  # (n, 6) EA, GJ, EIy, EIz, Phi_y, Phi_z
    arch: np.ndarray  # (n,) 1.0 for beams (shallow-arch axial strain), 0.0 for rods (chord strain only)
    lumped_axial: np.ndarray | None = None  # (n,) bool: axial and torsional mass lumped (None: as ``lumped``)


def bending_coefficients(EI: np.ndarray, phi: np.ndarray, L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Timoshenko rotation-block coefficients kd = EI (4 + Phi) / (L (1 + Phi)), ko = EI (2 - Phi) / (L (1 + Phi))."""
    k = EI / (L * (1 + phi))
    return k * (4 + phi), k * (2 - phi)


def kernel_coefficients(section_stiffness: np.ndarray, L: np.ndarray) -> np.ndarray:
    """(n, 6) kernel coefficients from (EA, GJ, EIy, EIz, Phi_y, Phi_z)."""
    EA, GJ, EIy, EIz, phy, phz = section_stiffness.T
    kdy, koy = bending_coefficients(EIy, phy, L)
    kdz, koz = bending_coefficients(EIz, phz, L)
    return np.ascontiguousarray(np.column_stack([EA, GJ, kdy, koy, kdz, koz]))


def element_frames(xyz: np.ndarray, nodes: np.ndarray, orientation: np.ndarray) -> np.ndarray:
    """Undeformed frames (n, 3, 3): columns local x (along the beam), y, z (from orientation)."""
    ex = xyz[nodes[:, 1]] - xyz[nodes[:, 0]]
    ex /= np.linalg.norm(ex, axis=1, keepdims=True)
    ez = orientation - np.sum(orientation * ex, axis=1, keepdims=True) * ex
    ez /= np.linalg.norm(ez, axis=1, keepdims=True)
    ey = cross(ez, ex)
    return np.stack([ex, ey, ez], axis=2)


def beam_forces(x: np.ndarray, R: np.ndarray, data: BeamData, tangent: bool = True,
                reference_forces: np.ndarray | None = None):
    """Internal forces and consistent tangent of all beams at nodal positions x (n_nodes, 3), rotations R.

    Returns g (n, 12) conjugate to [dx1, spin1, dx2, spin2], K (n, 12, 12) with
    K[a, b] = d g_a / d p_b (exact, non-symmetric away from equilibrium; its symmetric part is
    the energy Hessian) or None, and the local forces (n, 7): [N, M1 (3), M2 (3)] [N, N m],
    conjugate to the elongation and the local rotations of the two nodes (column 0 is the axial
    force). reference_forces (n, 7): local forces to use in the stress-dependent (geometric) part
    of the tangent instead of the element's own (those of another state); g stays exact.
    """
    n = len(data.L0)
    g = np.empty((n, 12))
    K = np.empty((n, 12, 12)) if tangent else np.empty((0, 12, 12))
    local = np.empty((n, 7))
    ref = np.empty((0, 7)) if reference_forces is None or not tangent else \
        np.ascontiguousarray(reference_forces, dtype=float)
    if ref.shape[0] not in (0, n):
        raise ValueError(f"reference_forces has {ref.shape[0]} rows for {n} beam elements")
    args = (np.ascontiguousarray(x), np.ascontiguousarray(R), data.nodes, data.E0, data.L0, data.stiffness, data.arch,
            tangent, ref, g, K, local)
    if n < 2 * _CHUNK:
        # One chunk: no parallel region. Launching one costs ~0.5 ms on a 2-core VM, several times the
        # work of a few hundred elements (the updating's derivative passes make hundreds of such calls).
        _beam_chunk(*args, 0, n)
    else:
        beam_kernel(*args, numba.get_num_threads())
    return g, (K if tangent else None), local


def local_mass_matrices(data: BeamData) -> np.ndarray:
    """(n, 12, 12) element mass matrices in local axes [u v w rx ry rz] x 2.

    Consistent: Hermitian cubic bending, linear axial and torsion, plus bending rotary inertia
    where ``inertia_per_length`` has it. Lumped: half the element at each node (translations,
    torsion and rotary inertia). ``lumped_axial`` lumps the axial and torsional terms of an element
    whose bending is consistent. Torsional inertia is rho*Ip (rotates with the section). Rods
    (arch == 0): linear shape functions in all three directions (consistent) or half at each node.
    """
    L = data.L0
    m = data.mass_per_length * L
    rIp, rIy, rIz = data.inertia_per_length.T
    n = len(L)
    M = np.zeros((n, 12, 12))
    cons = ~data.lumped
    cons_axial = cons if data.lumped_axial is None else cons & ~data.lumped_axial
    # axial and torsion
    for dof, total in ((0, m), (3, rIp * L)):
        M[:, dof, dof] = M[:, dof + 6, dof + 6] = np.where(cons_axial, total / 3, total / 2)
        M[:, dof, dof + 6] = M[:, dof + 6, dof] = np.where(cons_axial, total / 6, 0.0)
    # bending: (v, rz) in x-y plane with sign +1, (w, ry) in x-z plane with sign -1
    for (t, r, s, rI) in ((1, 5, 1.0, rIz), (2, 4, -1.0, rIy)):
        idx = [t, r, t + 6, r + 6]
        Lc = L[:, None, None]
        trans = (m / 420)[:, None, None] * np.array([[156, 22, 54, -13], [22, 4, 13, -3],
                                                     [54, 13, 156, -22], [-13, -3, -22, 4]])[None]
        rot = (rI / (30 * L))[:, None, None] * np.array([[36, 3, -36, 3], [3, 4, -3, -1],
                                                         [-36, -3, 36, -3], [3, -1, -3, 4]])[None]
        scale = np.ones((n, 4, 4))
        for a, pa in enumerate((0, 1, 0, 1)):
            for b, pb in enumerate((0, 1, 0, 1)):
                scale[:, a, b] = (s * Lc[:, 0, 0]) ** (pa + pb)
        block = (trans + rot) * scale
        lumped = np.zeros((n, 4, 4))
        lumped[:, 0, 0] = lumped[:, 2, 2] = m / 2
        lumped[:, 1, 1] = lumped[:, 3, 3] = rI * L / 2
        block = np.where(cons[:, None, None], block, lumped)
        M[:, np.array(idx)[:, None], np.array(idx)[None, :]] = block
    rods = data.arch == 0
    if rods.any():  # translations only, linear (or lumped) in every direction
        r = np.zeros((int(rods.sum()), 12, 12))
        m_r, c_r = m[rods], cons[rods]
        for dof in range(3):
            r[:, dof, dof] = r[:, dof + 6, dof + 6] = np.where(c_r, m_r / 3, m_r / 2)
            r[:, dof, dof + 6] = r[:, dof + 6, dof] = np.where(c_r, m_r / 6, 0.0)
        M[rods] = r
    return M


def beam_mass_matrices(x: np.ndarray, R: np.ndarray, data: BeamData, local: np.ndarray) -> np.ndarray:
    """(n, 12, 12) global mass matrices about the current state: local matrices in the corotated frame."""
    out = np.empty((len(data.L0), 12, 12))
    _rotate_blocks(current_frames(x, R, data), np.ascontiguousarray(local, dtype=float), out)
    return out


def current_frames(x: np.ndarray, R: np.ndarray, data: BeamData) -> np.ndarray:
    """(n, 3, 3) corotated element frames (columns r1, r2, r3) at positions x, rotations R."""
    out = np.empty((len(data.L0), 3, 3))
    element_frames_at(np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(R, dtype=float), data.nodes,
                      data.E0, out)
    return out


@numba.njit(cache=True)
def _rotate_blocks(Rr, local, out):  # pragma: no cover - compiled
    """out[e] = E local[e] E^T with E = diag(Rr[e], Rr[e], Rr[e], Rr[e]), block by 3x3 block. A
    diagonal local block (all but the translation-rotation couplings of beam mass) is
    sum_k d_k Q e_k (Q e_k)^T, the rest the full product."""
    tmp = np.empty((3, 3))
    for e in range(Rr.shape[0]):
        Q = Rr[e]
        for bi in range(4):
            for bj in range(4):
                r0, c0 = 3 * bi, 3 * bj
                L = local[e]
                if (L[r0, c0 + 1] == 0.0 and L[r0, c0 + 2] == 0.0 and L[r0 + 1, c0] == 0.0
                        and L[r0 + 1, c0 + 2] == 0.0 and L[r0 + 2, c0] == 0.0 and L[r0 + 2, c0 + 1] == 0.0):
                    d0, d1, d2 = L[r0, c0], L[r0 + 1, c0 + 1], L[r0 + 2, c0 + 2]
                    for i in range(3):
                        for j in range(3):
                            out[e, r0 + i, c0 + j] = d0 * Q[i, 0] * Q[j, 0] + d1 * Q[i, 1] * Q[j, 1] + d2 * Q[i, 2] * Q[j, 2]
                    continue
                for i in range(3):
                    for j in range(3):
                        acc = 0.0
                        for k in range(3):
                            acc += L[r0 + i, c0 + k] * Q[j, k]
                        tmp[i, j] = acc  # local block times Q^T
                for i in range(3):
                    for j in range(3):
                        acc = 0.0
                        for k in range(3):
                            acc += Q[i, k] * tmp[k, j]
                        out[e, r0 + i, c0 + j] = acc
