"""Corotational 3D beam: internal forces, exact consistent tangent and mass about any state.

The element frame follows the chord and the mean of the nodal e2 directions (Crisfield); the
local element is a Timoshenko beam, uniform or tapered (element_coefficients), whose axial strain
carries the shallow-arch term, so the tangent contains both the chord-rotation (P-Delta) and the
in-element (P-delta) geometric stiffness. Nodal rotations are updated by spatial spins and local
rotations are measured with the SO(3) logarithm, so large rotations (a cantilever rolled into a full circle) are exact.

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
    stiffness: np.ndarray  # (n, 8) kernel coefficients EA, GJ, kd_y, ko_y, kd_z, ko_z, dd_y, dd_z
    #                        (element_coefficients)
    mass_per_length: np.ndarray  # (n, 2) rho*A at the first and second node [kg/m]
    inertia_per_length: np.ndarray  # (n, 2, 3) rho*Ip, rho*Iy, rho*Iz at each node [kg m]
    #                                 (bending zero without rotary inertia)
    lumped: np.ndarray  # (n,) bool
    arch: np.ndarray  # (n,) 1.0 for beams (shallow-arch axial strain), 0.0 for rods (chord strain only)
    lumped_axial: np.ndarray | None = None  # (n,) bool: axial and torsional mass lumped (None: as ``lumped``)

    def take(self, rows: np.ndarray) -> "BeamData":
        """The elements ``rows`` only."""
        return BeamData(self.nodes[rows], self.E0[rows], self.L0[rows], self.stiffness[rows],
                        self.mass_per_length[rows], self.inertia_per_length[rows], self.lumped[rows], self.arch[rows],
                        None if self.lumped_axial is None else self.lumped_axial[rows])


# 3-point Gauss rule on [0, 1]: Nastran's CBEAM integrates a tapered element's flexibility with it
# (the glider deck fmondsp.dat's modes to 3e-7, tests/io/test_nastran_f06_decks.py).
GAUSS3_POINTS = np.array([0.5 - np.sqrt(15.0) / 10.0, 0.5, 0.5 + np.sqrt(15.0) / 10.0])
GAUSS3_WEIGHTS = np.array([5.0, 8.0, 5.0]) / 18.0


def bending_coefficients(EI: np.ndarray, phi: np.ndarray, L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Timoshenko rotation-block coefficients kd = EI (4 + Phi) / (L (1 + Phi)), ko = EI (2 - Phi) / (L (1 + Phi))."""
    k = EI / (L * (1 + phi))
    return k * (4 + phi), k * (2 - phi)


def element_coefficients(E, G, pa: dict, pb: dict, L: np.ndarray) -> np.ndarray:
    """(n, 8) kernel coefficients of elements of lengths L [m] with section properties pa at the
    first node and pb at the second (dicts as GeneralSection.properties(); pb is pa: uniform).

    Per bending plane the coefficients give the 2 x 2 stiffness [[kd + dd, ko], [ko, kd - dd]] on
    the local end rotations (relative to the chord). Uniform: the exact Timoshenko element (dd = 0).
    Tapered (A, I, J, shear areas linear between the ends): the inverse of the element's
    flexibility, int (1 - s)^2 / EI, int s^2 / EI, -int s (1 - s) / EI [s = x / L] plus the shear
    term int 1 / (G As) / L^2 on all four, and EA, GJ as 1 / int (1 / EA) dx / L, integrated by
    3-point Gauss (Nastran CBEAM's rule; it equals the uniform element when the ends agree).
    Complex-safe (complex-step derivatives). Uniform elements (pb is pa) also take E, G and the
    properties as per-element arrays (n,)."""
    L = np.asarray(L)
    n = len(L)
    out = np.zeros((n, 8), dtype=np.result_type(E, G, *pa.values(), *pb.values(), L, float))
    if pb is pa:
        out[:, 0] = E * pa["A"]
        out[:, 1] = G * pa["J"]
        for col, (I, As) in ((2, ("Iy", "Az")), (4, ("Iz", "Ay"))):
            shear = np.asarray(pa[As]) != 0  # per element when the properties are per-element arrays
            phi = np.where(shear, 12 * E * pa[I] / (G * np.where(shear, pa[As], 1.0) * L**2), 0.0)
            out[:, col], out[:, col + 1] = bending_coefficients(E * pa[I], phi, L)
        return out
    s, w = GAUSS3_POINTS, GAUSS3_WEIGHTS

    def at_points(key):
        return pa[key] * (1 - s) + pb[key] * s

    out[:, 0] = 1.0 / np.sum(w / (E * at_points("A")))
    if pa["J"] != 0 or pb["J"] != 0:
        out[:, 1] = 1.0 / np.sum(w / (G * at_points("J")))
    for col, dd, I, As in ((2, 6, "Iy", "Az"), (4, 7, "Iz", "Ay")):
        if pa[I] == 0 and pb[I] == 0:
            continue  # no stiffness in this plane (held by constraints)
        inv = w / (E * at_points(I))
        c0, c1, c2 = np.sum(inv), np.sum(inv * s), np.sum(inv * s * s)
        shear = np.sum(w / (G * at_points(As))) / L if pa[As] != 0 else 0.0
        f11 = L * (c0 - 2 * c1 + c2) + shear
        f22 = L * c2 + shear
        f12 = -L * (c1 - c2) + shear
        det = f11 * f22 - f12 * f12
        k11, k22, k12 = f22 / det, f11 / det, -f12 / det
        out[:, col] = 0.5 * (k11 + k22)
        out[:, col + 1] = k12
        out[:, dd] = 0.5 * (k11 - k22)
    return out


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


_TRANS = np.array([[156, 22, 54, -13], [22, 4, 13, -3], [54, 13, 156, -22], [-13, -3, -22, 4]], float)  # x m L / 420
_TRANS_TAPER = np.array([[-84, -8, 0, 1], [-8, -1, 1, 0], [0, 1, 84, -8], [1, 0, -8, 1]], float)  # x D L / 840
_ROT = np.array([[36, 3, -36, 3], [3, 4, -3, -1], [-36, -3, 36, -3], [3, -1, -3, 4]], float)  # x rI / (30 L)
_ROT_TAPER = np.array([[0, 3, 0, -3], [3, -2, -3, 0], [0, -3, 0, 3], [-3, 0, 3, 2]], float)  # x D / (60 L)


def local_mass_matrices(data: BeamData) -> np.ndarray:
    """(n, 12, 12) element mass matrices in local axes [u v w rx ry rz] x 2.

    Per-length values vary linearly from the first node to the second, m(s) = M + D (s - 1/2)
    (M the mean, D the difference; D = 0 for a uniform element), and each matrix is their exact
    integral. Consistent: Hermitian cubic bending, linear axial and torsion, plus bending rotary
    inertia where ``inertia_per_length`` has it. Lumped: each node takes int m N_i dx (N_i linear):
    L (M/2 -+ D/12), half the element when uniform (translations, torsion and rotary inertia).
    ``lumped_axial`` lumps the axial and torsional terms of an element whose bending is consistent.
    Torsional inertia is rho*Ip (rotates with the section). Rods (arch == 0): linear shape
    functions in all three directions (consistent) or half at each node.
    """
    L = data.L0
    mA, mB = data.mass_per_length.T
    m, dm = 0.5 * (mA + mB) * L, (mB - mA) * L  # total mass and its difference term [kg]
    rI = 0.5 * (data.inertia_per_length[:, 0] + data.inertia_per_length[:, 1])  # (n, 3) mean rho Ip, rho Iy, rho Iz
    dI = data.inertia_per_length[:, 1] - data.inertia_per_length[:, 0]
    n = len(L)
    M = np.zeros((n, 12, 12))
    cons = ~data.lumped
    cons_axial = cons if data.lumped_axial is None else cons & ~data.lumped_axial
    # axial and torsion (linear shape functions)
    for dof, total, diff in ((0, m, dm), (3, rI[:, 0] * L, dI[:, 0] * L)):
        M[:, dof, dof] = np.where(cons_axial, total / 3 - diff / 12, total / 2 - diff / 12)
        M[:, dof + 6, dof + 6] = np.where(cons_axial, total / 3 + diff / 12, total / 2 + diff / 12)
        M[:, dof, dof + 6] = M[:, dof + 6, dof] = np.where(cons_axial, total / 6, 0.0)
    # bending: (v, rz) in x-y plane with sign +1, (w, ry) in x-z plane with sign -1
    for (t, r, s, k) in ((1, 5, 1.0, 2), (2, 4, -1.0, 1)):
        idx = [t, r, t + 6, r + 6]
        scale = np.ones((n, 4, 4))
        for a, pa in enumerate((0, 1, 0, 1)):
            for b, pb in enumerate((0, 1, 0, 1)):
                scale[:, a, b] = (s * L) ** (pa + pb)
        block = ((m / 420)[:, None, None] * _TRANS + (dm / 840)[:, None, None] * _TRANS_TAPER
                 + (rI[:, k] / (30 * L))[:, None, None] * _ROT + (dI[:, k] / (60 * L))[:, None, None] * _ROT_TAPER)
        block = block * scale
        lumped = np.zeros((n, 4, 4))
        lumped[:, 0, 0], lumped[:, 2, 2] = m / 2 - dm / 12, m / 2 + dm / 12
        lumped[:, 1, 1] = (rI[:, k] / 2 - dI[:, k] / 12) * L
        lumped[:, 3, 3] = (rI[:, k] / 2 + dI[:, k] / 12) * L
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


def nodal_weights(data: BeamData) -> tuple[np.ndarray, np.ndarray]:
    """Each element's mass at its first and second node, int rho A N_i dx [kg]: half each when uniform."""
    mA, mB = data.mass_per_length.T
    m, dm = 0.5 * (mA + mB) * data.L0, (mB - mA) * data.L0
    return m / 2 - dm / 12, m / 2 + dm / 12


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
                            out[e, r0 + i, c0 + j] = (d0 * Q[i, 0] * Q[j, 0] + d1 * Q[i, 1] * Q[j, 1]
                                                      + d2 * Q[i, 2] * Q[j, 2])
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


@numba.njit(cache=True, inline="always")
def _bending_energy(kd, ko, dd, L, d1, r1, d2, r2, sign):  # pragma: no cover - compiled
    """Energy of a bending block 1/2 ((kd + dd) a^2 + 2 ko a b + (kd - dd) b^2), a and b the end
    rotations relative to the chord; sign=+1 for (v, rz), -1 for (w, ry)."""
    chord = sign * (d2 - d1) / L
    a, b = r1 - chord, r2 - chord
    return 0.5 * ((kd + dd) * a * a + 2 * ko * a * b + (kd - dd) * b * b)


@numba.njit(cache=True)
def _beam_energies(shapes, nodes, Rr, stiffness, L, vertical, out):  # pragma: no cover - compiled
    """out[m] += (OOP, IP, torsion, extension) strain energies of mode m summed over the beams
    (stiffness: the kernel coefficients, beam.element_coefficients)."""
    loc = np.empty((4, 3))  # local u1, t1, u2, t2
    for m in range(shapes.shape[0]):
        for e in range(nodes.shape[0]):
            for blk in range(4):
                node = nodes[e, blk // 2]
                off = 3 * (blk % 2)
                for j in range(3):
                    loc[blk, j] = (shapes[m, node, off] * Rr[e, 0, j] + shapes[m, node, off + 1] * Rr[e, 1, j]
                                   + shapes[m, node, off + 2] * Rr[e, 2, j])
            EA, GJ, kdy, koy, kdz, koz, ddy, ddz = stiffness[e]
            Le = L[e]
            ext = 0.5 * EA / Le * (loc[2, 0] - loc[0, 0]) ** 2
            tor = 0.5 * GJ / Le * (loc[3, 0] - loc[1, 0]) ** 2
            by = _bending_energy(kdy, koy, ddy, Le, loc[0, 2], loc[1, 1], loc[2, 2], loc[3, 1], -1.0)
            bz = _bending_energy(kdz, koz, ddz, Le, loc[0, 1], loc[1, 2], loc[2, 1], loc[3, 2], 1.0)
            out[m, 0] += by if vertical[e] else bz
            out[m, 1] += bz if vertical[e] else by
            out[m, 2] += tor
            out[m, 3] += ext


def strain_energies(shapes: np.ndarray, x: np.ndarray, R: np.ndarray, data: BeamData) -> np.ndarray:
    """(n_modes, 4) strain energies (OOP bending, IP bending, torsion, extension) of mode shapes
    (n_modes, n_nodes, 6) summed over the beams, each element in its deformed local axes at
    (x, R): bending about the local axis closer to the global vertical plane is out-of-plane."""
    out = np.zeros((len(shapes), 5))
    if len(data.L0):
        Rr = current_frames(x, R, data)
        vertical = np.abs(Rr[:, 2, 2]) >= np.abs(Rr[:, 2, 1])  # local z closer to global z: bending about y is OOP
        _beam_energies(np.ascontiguousarray(shapes, dtype=float), data.nodes, np.ascontiguousarray(Rr),
                       np.ascontiguousarray(data.stiffness, dtype=float), data.L0, vertical, out)
    return out[:, :4]
