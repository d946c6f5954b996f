"""Point components: concentrated masses (gravity potential, inertia), suspension cords and 6-component
springs, with internal forces and exact consistent tangents conjugate to (dx, spin) per node.

Tangents follow the beam convention K[a, b] = d g_a / d p_b; arrays are vectorised over items.
"""

from __future__ import annotations

import numpy as np

from .rotations import cross, jl_inv, jl_inv_derivative_T, logm_so3, skew


def mass_gravity(R: np.ndarray, offset0: np.ndarray, weight: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Potential -W.(x + R o0) of masses with fixed force W = m a [N] at rotating offsets.

    Returns g (n, 6) and K (n, 6, 6).
    """
    r = (R @ offset0[:, :, None])[:, :, 0]
    g = np.concatenate([-weight, -cross(r, weight)], axis=1)
    K = np.zeros((len(r), 6, 6))
    K[:, 3:, 3:] = -skew(weight) @ skew(r)
    return g, K


def mass_matrix(R: np.ndarray, offset0: np.ndarray, mass: np.ndarray, inertia0: np.ndarray) -> np.ndarray:
    """(n, 6, 6) mass matrices of offset point masses about the current rotation, at their node."""
    r = (R @ offset0[:, :, None])[:, :, 0]
    S = skew(r)
    M = np.zeros((len(r), 6, 6))
    M[:, :3, :3] = mass[:, None, None] * np.eye(3)
    M[:, :3, 3:] = -mass[:, None, None] * S
    M[:, 3:, :3] = mass[:, None, None] * S
    M[:, 3:, 3:] = -mass[:, None, None] * (S @ S) + R @ inertia0 @ np.swapaxes(R, 1, 2)
    return M


def _cord_arms(xa, Ra, xb, Rb, offset0, w):
    """Rotated arms r_a, r_b and the attachment point P = (1 - w)(x_a + r_a) + w (x_b + r_b)."""
    ra = (Ra @ offset0[:, :, None])[:, :, 0]
    rb = (Rb @ offset0[:, :, None])[:, :, 0]
    P = (1.0 - w)[:, None] * (xa + ra) + w[:, None] * (xb + rb)
    return ra, rb, P


def _cord_map(ra, rb, w):
    """(n, 3, 12) dP = TP [dx_a, w_a, dx_b, w_b]."""
    n = len(w)
    eye = np.broadcast_to(np.eye(3), (n, 3, 3))
    return np.concatenate([(1.0 - w)[:, None, None] * np.concatenate([eye, -skew(ra)], axis=2),
                           w[:, None, None] * np.concatenate([eye, -skew(rb)], axis=2)], axis=2)


def cord_forces(xa: np.ndarray, Ra: np.ndarray, xb: np.ndarray, Rb: np.ndarray, offset0: np.ndarray,
                anchor: np.ndarray, k: np.ndarray, l0: np.ndarray,
                w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Cords from fixed anchors to an attachment point between two nodes, P = (1 - w)(x_a + R_a o) +
    w (x_b + R_b o) (w = 0: at node a with the rigid arm o; 0 < w < 1: along the element a-b, the
    translations interpolated linearly). Returns g (n, 12), K (n, 12, 12) over [dx_a, w_a, dx_b,
    w_b], tension (n,) and length (n,)."""
    ra, rb, P = _cord_arms(xa, Ra, xb, Rb, offset0, w)
    d = P - anchor
    length = np.linalg.norm(d, axis=1)
    nvec = d / length[:, None]
    T = k * np.maximum(length - l0, 0.0)
    taut = (length >= l0).astype(float)  # a cord at its natural length already resists stretching
    gP = T[:, None] * nvec
    wa, wb = (1.0 - w)[:, None], w[:, None]
    g = np.concatenate([wa * gP, wa * cross(ra, gP), wb * gP, wb * cross(rb, gP)], axis=1)
    nn = nvec[:, :, None] * nvec[:, None, :]
    KPP = (k * taut)[:, None, None] * nn + (T / length)[:, None, None] * (np.eye(3) - nn)
    TP = _cord_map(ra, rb, w)
    K = np.swapaxes(TP, 1, 2) @ KPP @ TP
    SgP = skew(gP)
    K[:, 3:6, 3:6] += wa[:, :, None] * (SgP @ skew(ra))
    K[:, 9:12, 9:12] += wb[:, :, None] * (SgP @ skew(rb))
    return g, K, T, length


def member_forces(xa: np.ndarray, Ra: np.ndarray, xb: np.ndarray, Rb: np.ndarray, xc: np.ndarray,
                  offset0: np.ndarray, anchor: np.ndarray, s: np.ndarray, k: np.ndarray, l0: np.ndarray,
                  w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Tension members (a distributed cord's segments) from an end Q = (1 - s) anchor + s x_c (s = 0: a
    fixed point, s = 1: node c's translation) to an attachment P between nodes a and b as in
    cord_forces. Tension T = k (length - l0), none when slack; sideways the geometric stiffness T /
    length. Returns g (n, 18), K (n, 18, 18) over [dx_a, w_a, dx_b, w_b, dx_c, w_c], tension (n,) and
    length (n,)."""
    ra, rb, P = _cord_arms(xa, Ra, xb, Rb, offset0, w)
    sv = s[:, None]
    d = P - ((1.0 - sv) * anchor + sv * xc)
    length = np.linalg.norm(d, axis=1)
    nvec = d / length[:, None]
    T = k * np.maximum(length - l0, 0.0)
    taut = (length >= l0).astype(float)
    gP = T[:, None] * nvec
    wa, wb = (1.0 - w)[:, None], w[:, None]
    zero = np.zeros_like(gP)
    g = np.concatenate([wa * gP, wa * cross(ra, gP), wb * gP, wb * cross(rb, gP), -sv * gP, zero], axis=1)
    nn = nvec[:, :, None] * nvec[:, None, :]
    KPP = (k * taut)[:, None, None] * nn + (T / length)[:, None, None] * (np.eye(3) - nn)
    n = len(w)
    TD = np.concatenate([_cord_map(ra, rb, w), -s[:, None, None] * np.broadcast_to(np.eye(3), (n, 3, 3)),
                         np.zeros((n, 3, 3))], axis=2)  # d(P - Q) = TD [dx_a, w_a, dx_b, w_b, dx_c, w_c]
    K = np.swapaxes(TD, 1, 2) @ KPP @ TD
    SgP = skew(gP)
    K[:, 3:6, 3:6] += wa[:, :, None] * (SgP @ skew(ra))
    K[:, 9:12, 9:12] += wb[:, :, None] * (SgP @ skew(rb))
    return g, K, T, length


def cord_damping(xa, Ra, xb, Rb, offset0, anchor, c, w) -> np.ndarray:
    """(n, 12, 12) viscous damping of cords along their current line of action (see cord_forces)."""
    ra, rb, P = _cord_arms(xa, Ra, xb, Rb, offset0, w)
    d = P - anchor
    nvec = d / np.linalg.norm(d, axis=1, keepdims=True)
    TP = _cord_map(ra, rb, w)
    CPP = c[:, None, None] * nvec[:, :, None] * nvec[:, None, :]
    return np.swapaxes(TP, 1, 2) @ CPP @ TP


def spring_forces(xa: np.ndarray, Xa: np.ndarray, Ra: np.ndarray, xb: np.ndarray, Xb: np.ndarray, Rb: np.ndarray,
                  frame: np.ndarray, k: np.ndarray, law=None) -> tuple[np.ndarray, np.ndarray]:
    """6-component springs on relative translation and rotation vector of b w.r.t. a (fixed frame axes).

    law: None (linear, rates k (n, 6)) or a function of the deflections in the spring axes (n, 6)
    returning (forces (n, 6), slopes (n, 6)) there: a nonlinear spring whose tangent is diagonal in
    its axes. Returns g (n, 12) and K (n, 12, 12) over [dx_a, w_a, dx_b, w_b].
    """
    n = len(k)
    Rab = Rb @ np.swapaxes(Ra, 1, 2)
    theta = logm_so3(Rab)
    Ji, c, e = jl_inv(theta)
    FT = np.swapaxes(frame, 1, 2)
    dt = (xb - Xb) - (xa - Xa)
    if law is None:
        Kt = frame @ (k[:, :3, None] * FT)
        Kr = frame @ (k[:, 3:, None] * FT)
        ft = (Kt @ dt[:, :, None])[:, :, 0]
        m = (Kr @ theta[:, :, None])[:, :, 0]
    else:
        local = np.concatenate([(FT @ dt[:, :, None])[:, :, 0], (FT @ theta[:, :, None])[:, :, 0]], axis=1)
        f_loc, slope = law(local)
        Kt = frame @ (slope[:, :3, None] * FT)
        Kr = frame @ (slope[:, 3:, None] * FT)
        ft = (frame @ f_loc[:, :3, None])[:, :, 0]
        m = (frame @ f_loc[:, 3:, None])[:, :, 0]
    mu = (np.swapaxes(Ji, 1, 2) @ m[:, :, None])[:, :, 0]
    Omega = np.concatenate([-Rab, np.broadcast_to(np.eye(3), (n, 3, 3))], axis=2)  # omega = Omega [w_a, w_b]
    g = np.concatenate([-ft, -(np.swapaxes(Rab, 1, 2) @ mu[:, :, None])[:, :, 0], ft, mu], axis=1)
    K = np.zeros((n, 12, 12))
    for (i, si), (j, sj) in (((0, -1), (0, -1)), ((0, -1), (6, 1)), ((6, 1), (0, -1)), ((6, 1), (6, 1))):
        K[:, i:i + 3, j:j + 3] = si * sj * Kt
    JO = Ji @ Omega  # d theta / d [w_a, w_b]   (n, 3, 6)
    dth = np.swapaxes(JO, 1, 2)  # (n, 6, 3) directions
    nu = np.swapaxes(jl_inv_derivative_T(theta, c, e, dth, m), 1, 2)  # (n, 3, 6)
    Kww = np.swapaxes(JO, 1, 2) @ Kr @ JO + np.swapaxes(Omega, 1, 2) @ nu
    Kww[:, :3, :] += -np.swapaxes(Rab, 1, 2) @ skew(mu) @ Omega
    rot = np.r_[3:6, 9:12]
    K[:, rot[:, None], rot[None, :]] = Kww
    return g, K


def spring_damping(Ra, Rb, frame, c) -> np.ndarray:
    """(n, 12, 12) linearised viscous damping of springs over [dx_a, w_a, dx_b, w_b]."""
    n = len(c)
    Rab = Rb @ np.swapaxes(Ra, 1, 2)
    FT = np.swapaxes(frame, 1, 2)
    Ct = frame @ (c[:, :3, None] * FT)
    Cr = frame @ (c[:, 3:, None] * FT)
    Omega = np.concatenate([-Rab, np.broadcast_to(np.eye(3), (n, 3, 3))], axis=2)
    C = np.zeros((n, 12, 12))
    for (i, si), (j, sj) in (((0, -1), (0, -1)), ((0, -1), (6, 1)), ((6, 1), (0, -1)), ((6, 1), (6, 1))):
        C[:, i:i + 3, j:j + 3] = si * sj * Ct
    rot = np.r_[3:6, 9:12]
    C[:, rot[:, None], rot[None, :]] = np.swapaxes(Omega, 1, 2) @ Cr @ Omega
    return C
