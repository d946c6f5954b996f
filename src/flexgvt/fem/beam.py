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

import numpy as np

from ._beam_kernel import beam_kernel
from .rotations import cross, logm_so3

@dataclass(frozen=True)
class BeamData:
    """Per-element arrays of all beams of a model (n elements)."""

    nodes: np.ndarray  # (n, 2) node storage indices
    E0: np.ndarray  # (n, 3, 3) undeformed frames, columns = local x, y, z
    L0: np.ndarray  # (n,) undeformed lengths [m]
    stiffness: np.ndarray  # (n, 6) EA, GJ, EIy, EIz, Phi_y, Phi_z
    mass_per_length: np.ndarray  # (n,) rho*A [kg/m]
    inertia_per_length: np.ndarray  # (n, 3) rho*Ip, rho*Iy, rho*Iz (bending terms zero if no rotary inertia)
    lumped: np.ndarray  # (n,) bool


def element_frames(xyz: np.ndarray, nodes: np.ndarray, orientation: np.ndarray) -> np.ndarray:
    """Undeformed frames (n, 3, 3): columns local x (along the beam), y, z (from orientation)."""
    ex = xyz[nodes[:, 1]] - xyz[nodes[:, 0]]
    ex /= np.linalg.norm(ex, axis=1, keepdims=True)
    ez = orientation - np.sum(orientation * ex, axis=1, keepdims=True) * ex
    ez /= np.linalg.norm(ez, axis=1, keepdims=True)
    ey = cross(ez, ex)
    return np.stack([ex, ey, ez], axis=2)


def corotated_frames(x1, x2, R1, R2, E0):
    """Current element frames (n, 3, 3), the chord length and the mean e2 vector."""
    d = x2 - x1
    ln = np.linalg.norm(d, axis=1)
    r1 = d / ln[:, None]
    q1 = (R1 @ E0[:, :, 1:2])[:, :, 0]
    q2 = (R2 @ E0[:, :, 1:2])[:, :, 0]
    q = 0.5 * (q1 + q2)
    r3 = cross(r1, q)
    r3 /= np.linalg.norm(r3, axis=1, keepdims=True)
    r2 = cross(r3, r1)
    return np.stack([r1, r2, r3], axis=2), ln, q1, q2, q


def local_rotations(Rr, R1, R2, E0):
    """Local rotation vectors of both element ends relative to the corotated frame, (n, 3) each."""
    RrT = np.swapaxes(Rr, 1, 2)
    return logm_so3(RrT @ R1 @ E0), logm_so3(RrT @ R2 @ E0)


def beam_forces(x: np.ndarray, R: np.ndarray, data: BeamData, tangent: bool = True):
    """Internal forces and consistent tangent of all beams at nodal positions x (n_nodes, 3), rotations R.

    Returns g (n, 12) conjugate to [dx1, spin1, dx2, spin2], K (n, 12, 12) with
    K[a, b] = d g_a / d p_b (exact, non-symmetric away from equilibrium; its symmetric part is
    the energy Hessian) or None, and the axial forces N (n,) [N].
    """
    n = len(data.L0)
    g = np.empty((n, 12))
    K = np.empty((n, 12, 12)) if tangent else np.empty((0, 12, 12))
    N = np.empty(n)
    beam_kernel(np.ascontiguousarray(x), np.ascontiguousarray(R), data.nodes, data.E0, data.L0, data.stiffness,
                tangent, g, K, N)
    return g, (K if tangent else None), N
