"""Compiled per-element kernel of the corotational beam (see beam.py for the formulation).

Forward differentiation by hand of every kinematic quantity along the 12 element DOFs
[dx1, spin1, dx2, spin2]; checked against finite differences in tests/fem/test_tangent.py.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from .rotations import logm3 as logm

_FAST = dict(cache=True, fastmath={"contract", "reassoc", "arcp", "nsz"}, nogil=True)


@njit(**_FAST, inline="always")
def _cross(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(**_FAST, inline="always")
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**_FAST)
def jl_inv_coeffs(theta):
    """c(t) and e(t) = c'(t)/t of Jinv = I - S/2 + c S^2."""
    t2 = _dot(theta, theta)
    if t2 < 1e-4:
        return 1 / 12 + t2 / 720 + t2 * t2 / 30240, 1 / 360 + t2 / 7560 + t2 * t2 / 201600
    t = np.sqrt(t2)
    half = 0.5 * t
    cot = np.cos(half) / np.sin(half)
    c = 1 / t2 - cot / (2 * t)
    dc = -2 / t**3 + 1 / (4 * t * np.sin(half) ** 2) + cot / (2 * t2)
    return c, dc / t


@njit(**_FAST, inline="always")
def _cx(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(**_FAST)
def jl_inv_apply(theta, c, v, out, sign):
    """out = Jinv(theta) @ v (sign=-1) or Jinv(theta)^T @ v (sign=+1)."""
    t0, t1, t2 = theta[0], theta[1], theta[2]
    u0, u1, u2 = _cx(t0, t1, t2, v[0], v[1], v[2])
    w0, w1, w2 = _cx(t0, t1, t2, u0, u1, u2)
    out[0] = v[0] + sign * 0.5 * u0 + c * w0
    out[1] = v[1] + sign * 0.5 * u1 + c * w1
    out[2] = v[2] + sign * 0.5 * u2 + c * w2


@njit(**_FAST)
def jl_inv_dT_apply(theta, c, e, dth, m, out):
    """out = (d Jinv[dth])^T m."""
    t0, t1, t2 = theta[0], theta[1], theta[2]
    d0, d1, d2 = dth[0], dth[1], dth[2]
    m0, m1, m2 = m[0], m[1], m[2]
    x0, x1, x2 = _cx(t0, t1, t2, m0, m1, m2)
    a0, a1, a2 = _cx(t0, t1, t2, x0, x1, x2)
    b0, b1, b2 = _cx(d0, d1, d2, x0, x1, x2)
    y0, y1, y2 = _cx(d0, d1, d2, m0, m1, m2)
    z0, z1, z2 = _cx(t0, t1, t2, y0, y1, y2)
    td = t0 * d0 + t1 * d1 + t2 * d2
    out[0] = 0.5 * y0 + e * td * a0 + c * (b0 + z0)
    out[1] = 0.5 * y1 + e * td * a1 + c * (b1 + z1)
    out[2] = 0.5 * y2 + e * td * a2 + c * (b2 + z2)


@njit(**_FAST)
def local_energy(u, t1, t2, L0, st, arch_on, f, H):
    """Gradient f (7) and Hessian H (7, 7) of the local strain energy in [u, theta1, theta2]; returns N.

    st = (EA, GJ, kd_y, ko_y, kd_z, ko_z): the energy is linear in these coefficients (bending
    energy 1/2 (kd (a^2 + b^2) + 2 ko a b) per plane), so derivatives with respect to any
    material or section parameter are this same kernel evaluated with d st / d p.
    arch_on: 1 for beams (shallow-arch term in the axial strain), 0 for rods (chord strain only).
    """
    EA, GJ = st[0], st[1]
    a1, a2, b1, b2 = t1[1], t2[1], t1[2], t2[2]
    arch = arch_on * (2 * a1 * a1 - a1 * a2 + 2 * a2 * a2 + 2 * b1 * b1 - b1 * b2 + 2 * b2 * b2) / 30.0
    eps = u / L0 + arch
    ge = f  # reuse f as scratch for the strain gradient, overwritten below
    for i in range(7):
        ge[i] = 0.0
    ge[0] = 1.0 / L0
    ge[2] = arch_on * (4 * a1 - a2) / 30.0
    ge[5] = arch_on * (4 * a2 - a1) / 30.0
    ge[3] = arch_on * (4 * b1 - b2) / 30.0
    ge[6] = arch_on * (4 * b2 - b1) / 30.0
    N = EA * eps
    for i in range(7):
        for j in range(7):
            H[i, j] = EA * L0 * ge[i] * ge[j]
    for i in range(7):
        f[i] = N * L0 * ge[i]
    for i, j in ((2, 5), (3, 6)):
        H[i, i] += arch_on * N * L0 * 4.0 / 30.0
        H[j, j] += arch_on * N * L0 * 4.0 / 30.0
        H[i, j] -= arch_on * N * L0 / 30.0
        H[j, i] -= arch_on * N * L0 / 30.0
    kt = GJ / L0
    tw = t2[0] - t1[0]
    f[1] -= kt * tw
    f[4] += kt * tw
    H[1, 1] += kt
    H[4, 4] += kt
    H[1, 4] -= kt
    H[4, 1] -= kt
    for axis in range(2):
        if axis == 0:
            i, j, kd, ko, ti, tj = 2, 5, st[2], st[3], t1[1], t2[1]
        else:
            i, j, kd, ko, ti, tj = 3, 6, st[4], st[5], t1[2], t2[2]
        f[i] += kd * ti + ko * tj
        f[j] += ko * ti + kd * tj
        H[i, i] += kd
        H[j, j] += kd
        H[i, j] += ko
        H[j, i] += ko
    return N


@njit(**_FAST)
def corotated(x1, x2, R1, R2, E0, Rr, q1, q2, q):
    """Element frame Rr (columns r1, r2, r3) and nodal e2 vectors; returns the chord length."""
    d0, d1, d2 = x2[0] - x1[0], x2[1] - x1[1], x2[2] - x1[2]
    ln = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    Rr[0, 0], Rr[1, 0], Rr[2, 0] = d0 / ln, d1 / ln, d2 / ln
    for i in range(3):
        q1[i] = R1[i, 0] * E0[0, 1] + R1[i, 1] * E0[1, 1] + R1[i, 2] * E0[2, 1]
        q2[i] = R2[i, 0] * E0[0, 1] + R2[i, 1] * E0[1, 1] + R2[i, 2] * E0[2, 1]
        q[i] = 0.5 * (q1[i] + q2[i])
    s0, s1, s2 = _cx(Rr[0, 0], Rr[1, 0], Rr[2, 0], q[0], q[1], q[2])
    nr3 = np.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
    Rr[0, 2], Rr[1, 2], Rr[2, 2] = s0 / nr3, s1 / nr3, s2 / nr3
    Rr[0, 1], Rr[1, 1], Rr[2, 1] = _cx(Rr[0, 2], Rr[1, 2], Rr[2, 2], Rr[0, 0], Rr[1, 0], Rr[2, 0])
    return ln


@njit(**_FAST)
def _rel(Rr, Rn, E0, A, tmp):
    """A = Rr^T Rn E0 without temporaries."""
    for i in range(3):
        for j in range(3):
            tmp[i, j] = Rn[i, 0] * E0[0, j] + Rn[i, 1] * E0[1, j] + Rn[i, 2] * E0[2, j]
    for i in range(3):
        for j in range(3):
            A[i, j] = Rr[0, i] * tmp[0, j] + Rr[1, i] * tmp[1, j] + Rr[2, i] * tmp[2, j]


@njit(**_FAST)
def local_rotations(Rr, R1, R2, E0, t1, t2, A, tmp, q4):
    _rel(Rr, R1, E0, A, tmp)
    logm(A, t1, q4)
    _rel(Rr, R2, E0, A, tmp)
    logm(A, t2, q4)


@njit(cache=True, nogil=True, parallel=True)
def beam_kernel(x, R, nodes, E0s, L0s, stiff, arch, want_tangent, f_ref, g_out, K_out, f_out, threads):
    """All elements, in chunks over ``threads`` threads (elements are independent)."""
    n = nodes.shape[0]
    chunks = min(max(n // 256, 1), threads)
    for c in prange(chunks):
        _beam_chunk(x, R, nodes, E0s, L0s, stiff, arch, want_tangent, f_ref, g_out, K_out, f_out,
                    c * n // chunks, (c + 1) * n // chunks)


@njit(**_FAST)
def _beam_chunk(x, R, nodes, E0s, L0s, stiff, arch, want_tangent, f_ref, g_out, K_out, f_out, start, stop):
    """Internal forces g_out (n, 12), tangent K_out (n, 12, 12) with K[a, b] = d g_a / d p_b and local
    forces f_out (n, 7) = [N, M1, M2] conjugate to [elongation, local rotations of node 1, node 2].

    f_ref (n, 7) or (0, 7): local forces that replace the element's own in the stress-dependent
    (geometric) part of the tangent; the material part and the forces g_out stay exact.
    """
    Rr = np.empty((3, 3))
    q1 = np.empty(3)
    q2 = np.empty(3)
    q = np.empty(3)
    t1 = np.empty(3)
    t2 = np.empty(3)
    f = np.empty(7)
    H = np.empty((7, 7))
    B = np.zeros((12, 7))
    om = np.zeros((12, 3))
    wb = np.zeros((2, 12, 3))
    dth = np.zeros((2, 12, 3))
    D = np.zeros((12, 3))
    for i in range(3):
        D[i, i] = -1.0
        D[6 + i, i] = 1.0
    a1 = np.empty(3)
    a2 = np.empty(3)
    tmp = np.empty(3)
    tmp2 = np.empty(3)
    mu = np.empty((2, 3))
    nu = np.empty((2, 12, 3))
    dr1 = np.empty((12, 3))
    dr2 = np.empty((12, 3))
    dr3 = np.empty((12, 3))
    omg = np.empty((12, 3))
    dq1 = np.zeros((12, 3))
    dq2 = np.zeros((12, 3))
    dqb1 = np.empty(12)
    dqb2 = np.empty(12)
    da1 = np.empty((12, 3))
    da2 = np.empty((12, 3))
    dln = np.empty(12)
    A33 = np.empty((3, 3))
    T33 = np.empty((3, 3))
    q4 = np.empty(4)
    r1 = np.empty(3)
    r2 = np.empty(3)
    r3 = np.empty(3)
    BH = np.empty((12, 7))
    musum = np.empty(3)
    U = np.empty((3, 12))
    G = np.empty((2, 3, 3))
    for el in range(start, stop):
        i1, i2 = nodes[el, 0], nodes[el, 1]
        x1, x2 = x[i1], x[i2]
        R1, R2 = R[i1], R[i2]
        E0 = E0s[el]
        L0 = L0s[el]
        ln = corotated(x1, x2, R1, R2, E0, Rr, q1, q2, q)
        for i in range(3):
            r1[i], r2[i], r3[i] = Rr[i, 0], Rr[i, 1], Rr[i, 2]
        local_rotations(Rr, R1, R2, E0, t1, t2, A33, T33, q4)
        c1, e1 = jl_inv_coeffs(t1)
        c2, e2 = jl_inv_coeffs(t2)
        N = local_energy(ln - L0, t1, t2, L0, stiff[el], arch[el], f, H)
        for i in range(7):
            f_out[el, i] = f[i]
        # g = B f with B[k] = (dln, Jinv1 wb1, Jinv2 wb2): the rotation parts are wb . (Jinv^T f) = wb . mu.
        jl_inv_apply(t1, c1, f[1:4], mu[0], 1.0)
        jl_inv_apply(t2, c2, f[4:7], mu[1], 1.0)
        qb1 = _dot(r1, q)
        qb2 = _dot(r2, q)
        _cross(q1, r3, a1)
        _cross(q2, r3, a2)
        for k in range(12):
            dln[k] = _dot(r1, D[k])
            om[k, 2] = _dot(r2, D[k]) / ln
            om[k, 1] = -_dot(r3, D[k]) / ln
            w1 = a1[k - 3] if 3 <= k < 6 else 0.0
            w2 = a2[k - 9] if k >= 9 else 0.0
            om[k, 0] = (qb1 * om[k, 1] + 0.5 * (w1 + w2)) / qb2
            for s in range(2):
                base = 3 if s == 0 else 9
                for i in range(3):
                    # R_r^T W_s[k]: row (k - base) of R_r^T for the node's own spin DOFs.
                    wl = Rr[k - base, i] if base <= k < base + 3 else 0.0
                    wb[s, k, i] = wl - om[k, i]
            g_out[el, k] = dln[k] * f[0] + _dot(wb[0, k], mu[0]) + _dot(wb[1, k], mu[1])
            if want_tangent:
                jl_inv_apply(t1, c1, wb[0, k], dth[0, k], -1.0)
                jl_inv_apply(t2, c2, wb[1, k], dth[1, k], -1.0)
                B[k, 0] = dln[k]
                for i in range(3):
                    B[k, 1 + i] = dth[0, k, i]
                    B[k, 4 + i] = dth[1, k, i]
        if not want_tangent:
            continue
        if f_ref.shape[0] > 0 and stiff[el, 0] != 0.0:
            # H's stress terms (shallow-arch strain) with the reference axial force: the energy is
            # evaluated at the elongation that gives that force, then the reference forces replace f.
            EA = stiff[el, 0]
            arch_strain = N / EA - (ln - L0) / L0
            local_energy((f_ref[el, 0] / EA - arch_strain) * L0, t1, t2, L0, stiff[el], arch[el], f, H)
            for i in range(7):
                f[i] = f_ref[el, i]
            jl_inv_apply(t1, c1, f[1:4], mu[0], 1.0)
            jl_inv_apply(t2, c2, f[4:7], mu[1], 1.0)
        K = K_out[el]
        for a in range(12):
            for l in range(7):
                acc = 0.0
                for m in range(7):
                    acc += B[a, m] * H[m, l]
                BH[a, l] = acc
        for a in range(12):  # B H B^T is symmetric (H is): one triangle, mirrored
            for b in range(a, 12):
                acc = 0.0
                for l in range(7):
                    acc += BH[a, l] * B[b, l]
                K[a, b] = acc
                K[b, a] = acc
        # (d Jinv[dth])^T m is linear in dth: its 3x3 matrix G (columns from unit vectors), per node.
        for i in range(3):
            for m in range(3):
                tmp[m] = 1.0 if m == i else 0.0
            jl_inv_dT_apply(t1, c1, e1, tmp, f[1:4], tmp2)
            for m in range(3):
                G[0, m, i] = tmp2[m]
            jl_inv_dT_apply(t2, c2, e2, tmp, f[4:7], tmp2)
            for m in range(3):
                G[1, m, i] = tmp2[m]
        for k in range(12):
            for i in range(3):
                omg[k, i] = Rr[i, 0] * om[k, 0] + Rr[i, 1] * om[k, 1] + Rr[i, 2] * om[k, 2]
                dr1[k, i] = (D[k, i] - r1[i] * dln[k]) / ln
                for s in range(2):
                    nu[s, k, i] = G[s, i, 0] * dth[s, k, 0] + G[s, i, 1] * dth[s, k, 1] + G[s, i, 2] * dth[s, k, 2]
            _cross(omg[k], r2, dr2[k])
            _cross(omg[k], r3, dr3[k])
        # Spin directions of the nodal e2 vectors and the frame-twist ingredients.
        for k in range(12):
            for i in range(3):
                dq1[k, i] = 0.0
                dq2[k, i] = 0.0
        # e_i x q:  e0 x q = (0, -q2, q1), e1 x q = (q2, 0, -q0), e2 x q = (-q1, q0, 0)
        dq1[3, 1], dq1[3, 2], dq1[4, 0], dq1[4, 2], dq1[5, 0], dq1[5, 1] = -q1[2], q1[1], q1[2], -q1[0], -q1[1], q1[0]
        dq2[9, 1], dq2[9, 2], dq2[10, 0], dq2[10, 2], dq2[11, 0], dq2[11, 1] = -q2[2], q2[1], q2[2], -q2[0], -q2[1], q2[0]
        for j in range(12):
            dqb1[j] = _dot(dr1[j], q)
            dqb2[j] = _dot(dr2[j], q)
            for i in range(3):
                dqa = 0.5 * (dq1[j, i] + dq2[j, i])
                dqb1[j] += dqa * r1[i]
                dqb2[j] += dqa * r2[i]
            _cross(dq1[j], r3, tmp)
            _cross(q1, dr3[j], tmp2)
            for i in range(3):
                da1[j, i] = tmp[i] + tmp2[i]
            _cross(dq2[j], r3, tmp)
            _cross(q2, dr3[j], tmp2)
            for i in range(3):
                da2[j, i] = tmp[i] + tmp2[i]
        f0 = f[0]
        for i in range(3):
            musum[i] = mu[0, i] + mu[1, i]
        # Geometric part, column j: d g_k / d p_j of the terms wb . mu and dln f0. Each is om[k] . u_j
        # (dense, rank 3: wb[s, k] = W_s[k] - om[k] and the frame-twist om[k, 0] depends on the
        # frame through qb1, qb2) plus terms on the rows where D[k] or W_s[k] is non-zero.
        c0s = musum[0] / qb2
        beta = musum[1] + c0s * qb1
        for j in range(12):
            dl = dln[j] / ln
            U[0, j] = c0s * dqb2[j] - (nu[0, j, 0] + nu[1, j, 0])
            U[1, j] = beta * dl - c0s * dqb1[j] - (nu[0, j, 1] + nu[1, j, 1])
            U[2, j] = musum[2] * dl - (nu[0, j, 2] + nu[1, j, 2])
            _cross(mu[0], om[j], tmp)
            _cross(mu[1], om[j], tmp2)
            for i in range(3):
                tmp[i] = nu[0, j, i] - tmp[i]
                tmp2[i] = nu[1, j, i] - tmp2[i]
            for i in range(3):
                # spin rows of node 1 and node 2: W_s[k] is row (k - base) of Rr
                K[3 + i, j] += _dot(Rr[i], tmp) - 0.5 * c0s * da1[j, i]
                K[9 + i, j] += _dot(Rr[i], tmp2) - 0.5 * c0s * da2[j, i]
                # translation rows: D[k] = -e_i (k < 3), +e_i (6 <= k < 9)
                t = f0 * dr1[j, i] + (beta * dr3[j, i] - musum[2] * dr2[j, i]) / ln
                K[i, j] -= t
                K[6 + i, j] += t
        for k in range(12):  # K[a, b] = d g_a / d p_b
            for j in range(12):
                K[k, j] += om[k, 0] * U[0, j] + om[k, 1] * U[1, j] + om[k, 2] * U[2, j]
