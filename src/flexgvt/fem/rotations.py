"""Vectorised finite-rotation helpers: skew matrices, exponential and logarithm maps, and the
inverse left Jacobian of SO(3) with its directional derivative (for exact corotational tangents).

Rotations are updated by spatial spins: R <- exp(skew(phi)) R.
"""

from __future__ import annotations

import numba
import numpy as np


def skew(v: np.ndarray) -> np.ndarray:
    """(..., 3) -> (..., 3, 3) with skew(a) @ b = a x b."""
    v = np.asarray(v)
    S = np.zeros(v.shape[:-1] + (3, 3), dtype=v.dtype)
    S[..., 0, 1], S[..., 0, 2] = -v[..., 2], v[..., 1]
    S[..., 1, 0], S[..., 1, 2] = v[..., 2], -v[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -v[..., 1], v[..., 0]
    return S


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product over the last axis with broadcasting (leaner than np.cross for small stacks)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


@numba.njit(cache=True, inline="always")
def _spin_node(p0, p1, p2, R, out, n):  # pragma: no cover - compiled
    """out[n] = exp(skew(p)) R[n] (Rodrigues)."""
    t2 = p0 * p0 + p1 * p1 + p2 * p2
    if t2 < 1e-4:  # series (next terms ~ t^10 / 11!, below 1e-27): no sin and cos
        a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)))
        b = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0 * (1.0 - t2 / 90.0)))
    else:
        t = np.sqrt(t2)
        a, b = np.sin(t) / t, (1.0 - np.cos(t)) / t2
    # Q = I + a S + b S^2 with S = skew(phi); S^2 = phi phi^T - t2 I
    q00 = 1.0 + b * (p0 * p0 - t2)
    q11 = 1.0 + b * (p1 * p1 - t2)
    q22 = 1.0 + b * (p2 * p2 - t2)
    q01, q10 = b * p0 * p1 - a * p2, b * p0 * p1 + a * p2
    q02, q20 = b * p0 * p2 + a * p1, b * p0 * p2 - a * p1
    q12, q21 = b * p1 * p2 - a * p0, b * p1 * p2 + a * p0
    for j in range(3):
        r0, r1, r2 = R[n, 0, j], R[n, 1, j], R[n, 2, j]
        out[n, 0, j] = q00 * r0 + q01 * r1 + q02 * r2
        out[n, 1, j] = q10 * r0 + q11 * r1 + q12 * r2
        out[n, 2, j] = q20 * r0 + q21 * r1 + q22 * r2


@numba.njit(cache=True)
def _spin_rotations(phi, R, out):  # pragma: no cover - compiled
    for n in range(phi.shape[0]):
        _spin_node(phi[n, 0], phi[n, 1], phi[n, 2], R, out, n)


@numba.njit(cache=True)
def _step_nodes(x, R, delta, dof_map, x_out, R_out):  # pragma: no cover - compiled
    """Nodal update from a reduced increment: x_out = x + dx, R_out = exp(skew(spin)) R, where
    dof_map[6 n + c] is the reduced index of each DOF (-1: held, no increment)."""
    d = np.empty(6)
    for n in range(x.shape[0]):
        for c in range(6):
            k = dof_map[6 * n + c]
            d[c] = delta[k] if k >= 0 else 0.0
        for c in range(3):
            x_out[n, c] = x[n, c] + d[c]
        _spin_node(d[3], d[4], d[5], R, R_out, n)


def step_nodes(x: np.ndarray, R: np.ndarray, delta: np.ndarray, dof_map: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(x + dx, exp(skew(spin)) R) for a reduced increment ``delta`` numbered by ``dof_map``."""
    x_out, R_out = np.empty_like(x, dtype=float), np.empty_like(R, dtype=float)
    _step_nodes(np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(R, dtype=float),
                np.ascontiguousarray(delta, dtype=float), dof_map, x_out, R_out)
    return x_out, R_out


def spin(R: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """exp(skew(phi)) @ R for stacks (n, 3, 3) and spatial spins (n, 3) [rad]."""
    out = np.empty_like(R, dtype=float)
    _spin_rotations(np.ascontiguousarray(phi, dtype=float), np.ascontiguousarray(R, dtype=float), out)
    return out


def expm_so3(phi: np.ndarray) -> np.ndarray:
    """Rotation matrices exp(skew(phi)) for (..., 3) rotation vectors (Rodrigues, exact)."""
    phi = np.asarray(phi, dtype=float)
    t2 = np.sum(phi * phi, axis=-1)
    t = np.sqrt(t2)
    small = t2 < 1e-12
    ts = np.where(small, 1.0, t)
    a = np.where(small, 1.0 - t2 / 6.0, np.sin(ts) / ts)
    b = np.where(small, 0.5 - t2 / 24.0, (1.0 - np.cos(ts)) / np.where(small, 1.0, t2))
    S = skew(phi)
    return np.eye(3) + a[..., None, None] * S + b[..., None, None] * (S @ S)


@numba.njit(cache=True, inline="always")
def logm3(R, out, q):  # pragma: no cover - compiled
    """Rotation vector of R (Shepperd quaternion, q: scratch (4,)), angle in [0, pi]."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    if tr >= R[0, 0] and tr >= R[1, 1] and tr >= R[2, 2]:
        s = 2.0 * np.sqrt(1.0 + tr)
        q[0] = 0.25 * s
        q[1] = (R[2, 1] - R[1, 2]) / s
        q[2] = (R[0, 2] - R[2, 0]) / s
        q[3] = (R[1, 0] - R[0, 1]) / s
    elif R[0, 0] >= R[1, 1] and R[0, 0] >= R[2, 2]:
        s = 2.0 * np.sqrt(max(1.0 + 2 * R[0, 0] - tr, 1e-300))
        q[0] = (R[2, 1] - R[1, 2]) / s
        q[1] = 0.25 * s
        q[2] = (R[0, 1] + R[1, 0]) / s
        q[3] = (R[0, 2] + R[2, 0]) / s
    elif R[1, 1] >= R[2, 2]:
        s = 2.0 * np.sqrt(max(1.0 + 2 * R[1, 1] - tr, 1e-300))
        q[0] = (R[0, 2] - R[2, 0]) / s
        q[1] = (R[0, 1] + R[1, 0]) / s
        q[2] = 0.25 * s
        q[3] = (R[1, 2] + R[2, 1]) / s
    else:
        s = 2.0 * np.sqrt(max(1.0 + 2 * R[2, 2] - tr, 1e-300))
        q[0] = (R[1, 0] - R[0, 1]) / s
        q[1] = (R[0, 2] + R[2, 0]) / s
        q[2] = (R[1, 2] + R[2, 1]) / s
        q[3] = 0.25 * s
    if q[0] < 0:
        for i in range(4):
            q[i] = -q[i]
    s2 = q[1] ** 2 + q[2] ** 2 + q[3] ** 2
    if s2 < 0.01 * q[0] * q[0]:  # angle below 11 deg: 2 atan(z) / (z q0) with z = tan(angle / 2) by its
        z2 = s2 / (q[0] * q[0])  # series (next term z^18 / 19 < 6e-20), no atan2
        f = 2.0 / q[0] * (1.0 - z2 * (1.0 / 3 - z2 * (1.0 / 5 - z2 * (1.0 / 7 - z2 * (
            1.0 / 9 - z2 * (1.0 / 11 - z2 * (1.0 / 13 - z2 * (1.0 / 15 - z2 / 17))))))))
    else:
        sn = np.sqrt(s2)
        f = 2.0 * np.arctan2(sn, q[0]) / sn
    out[0] = f * q[1]
    out[1] = f * q[2]
    out[2] = f * q[3]


@numba.njit(cache=True)
def _scaled_increment(x, R, xp, Rp, dof_map, scale, out):  # pragma: no cover - compiled
    A = np.empty((3, 3))
    q = np.empty(4)
    spin = np.empty(3)
    for n in range(x.shape[0]):
        for i in range(3):
            for j in range(3):
                A[i, j] = R[n, i, 0] * Rp[n, j, 0] + R[n, i, 1] * Rp[n, j, 1] + R[n, i, 2] * Rp[n, j, 2]
        logm3(A, spin, q)
        for c in range(6):
            k = dof_map[6 * n + c]
            if k >= 0:
                out[k] = scale * (x[n, c] - xp[n, c] if c < 3 else spin[c - 3])


def scaled_increment(x, R, xp, Rp, dof_map: np.ndarray, scale: float) -> np.ndarray:
    """scale times the reduced increment (translations, spatial spins) from state (xp, Rp) to (x, R)."""
    out = np.zeros(int(dof_map.max(initial=-1)) + 1)
    _scaled_increment(*(np.ascontiguousarray(a, dtype=float) for a in (x, R, xp, Rp)), dof_map, float(scale), out)
    return out


def logm_so3(R: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3) of rotation matrices (..., 3, 3), angle in [0, pi]."""
    R = np.asarray(R, dtype=float)
    tr = np.trace(R, axis1=-2, axis2=-1)
    # Quaternion (Shepperd): pick the largest of w, x, y, z for accuracy everywhere.
    diag = np.stack([tr, R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]], axis=-1)
    k = np.argmax(diag, axis=-1)
    q = np.empty(R.shape[:-2] + (4,))
    r21, r12 = R[..., 2, 1], R[..., 1, 2]
    r02, r20 = R[..., 0, 2], R[..., 2, 0]
    r10, r01 = R[..., 1, 0], R[..., 0, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        s0 = 2.0 * np.sqrt(np.maximum(1.0 + tr, 1e-300))
        s1 = 2.0 * np.sqrt(np.maximum(1.0 + 2 * R[..., 0, 0] - tr, 1e-300))
        s2 = 2.0 * np.sqrt(np.maximum(1.0 + 2 * R[..., 1, 1] - tr, 1e-300))
        s3 = 2.0 * np.sqrt(np.maximum(1.0 + 2 * R[..., 2, 2] - tr, 1e-300))
        cand = np.stack([
            np.stack([0.25 * s0, (r21 - r12) / s0, (r02 - r20) / s0, (r10 - r01) / s0], -1),
            np.stack([(r21 - r12) / s1, 0.25 * s1, (r01 + r10) / s1, (r02 + r20) / s1], -1),
            np.stack([(r02 - r20) / s2, (r01 + r10) / s2, 0.25 * s2, (r12 + r21) / s2], -1),
            np.stack([(r10 - r01) / s3, (r02 + r20) / s3, (r12 + r21) / s3, 0.25 * s3], -1),
        ], axis=-2)
    q = np.take_along_axis(cand, k[..., None, None], axis=-2)[..., 0, :]
    q = np.where(q[..., :1] < 0, -q, q)
    w, v = q[..., 0], q[..., 1:]
    s = np.linalg.norm(v, axis=-1)
    small = s < 1e-8
    factor = np.where(small, 2.0 / np.maximum(w, 1e-300) * (1.0 - s * s / (3.0 * w * w)),
                      2.0 * np.arctan2(s, w) / np.where(small, 1.0, s))
    return factor[..., None] * v


def _c_and_e(t2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """c(t) = 1/t^2 - cot(t/2)/(2t) and e(t) = c'(t)/t, with series near t = 0."""
    t = np.sqrt(t2)
    small = t < 1e-2
    ts = np.where(small, 1.0, t)
    half = 0.5 * ts
    cot = np.cos(half) / np.sin(half)
    c = np.where(small, 1 / 12 + t2 / 720 + t2 * t2 / 30240, 1 / ts**2 - cot / (2 * ts))
    dc = -2 / ts**3 + 1 / (4 * ts * np.sin(half) ** 2) + cot / (2 * ts**2)
    e = np.where(small, 1 / 360 + t2 / 7560 + t2 * t2 / 201600, dc / ts)
    return c, e


def jl_inv(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Inverse left Jacobian Jinv(theta) = I - S/2 + c S^2, (..., 3, 3); also c and e = c'/t."""
    t2 = np.sum(theta * theta, axis=-1)
    c, e = _c_and_e(t2)
    S = skew(theta)
    return np.eye(3) - 0.5 * S + c[..., None, None] * (S @ S), c, e


def jl_inv_derivative_T(theta: np.ndarray, c: np.ndarray, e: np.ndarray, dtheta: np.ndarray,
                        m: np.ndarray) -> np.ndarray:
    """(d Jinv[dtheta])^T m for directions dtheta (..., k, 3) and vectors m (..., 3) -> (..., k, 3)."""
    th = theta[..., None, :]
    mm = m[..., None, :]
    tdot = np.sum(th * dtheta, axis=-1, keepdims=True)
    txm = cross(th, mm)
    term1 = 0.5 * cross(dtheta, mm)
    term2 = e[..., None, None] * tdot * cross(th, txm)
    term3 = c[..., None, None] * (cross(dtheta, txm) + cross(th, cross(dtheta, mm)))
    return term1 + term2 + term3
