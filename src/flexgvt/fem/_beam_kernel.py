"""Compiled per-element kernel of the corotational beam (see beam.py for the formulation).

Forward differentiation by hand of every kinematic quantity along 9 independent element DOFs
[x2 - x1, spin1, spin2] (the forces and tangent on the 12 [dx1, spin1, dx2, spin2] follow from
translation invariance and balance); checked against finite differences in tests/fem/test_tangent.py.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from .rotations import logm3 as logm

# error_model="numpy": a division by zero gives inf/NaN (caught by the Newton loop's finiteness
# checks) instead of an exception test on every division.
_FAST = dict(cache=True, fastmath={"contract", "reassoc", "arcp", "nsz"}, nogil=True, error_model="numpy")


@njit(**_FAST, inline="always")
def _cross(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(**_FAST, inline="always")
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**_FAST, inline="always")
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


@njit(**_FAST, inline="always")
def jl_inv_apply(theta, c, v, out, sign):
    """out = Jinv(theta) @ v (sign=-1) or Jinv(theta)^T @ v (sign=+1)."""
    t0, t1, t2 = theta[0], theta[1], theta[2]
    u0, u1, u2 = _cx(t0, t1, t2, v[0], v[1], v[2])
    w0, w1, w2 = _cx(t0, t1, t2, u0, u1, u2)
    out[0] = v[0] + sign * 0.5 * u0 + c * w0
    out[1] = v[1] + sign * 0.5 * u1 + c * w1
    out[2] = v[2] + sign * 0.5 * u2 + c * w2


@njit(**_FAST, inline="always")
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


@njit(**_FAST, inline="always")
def local_energy(u, t1, t2, L0, st, arch_on, f, ge, hc):
    """Gradient f (7) of the local strain energy in [u, theta1, theta2] and its Hessian as six
    rank-one terms, H = sum_t hc[t] h_t h_t^T with h_0 = ge (the axial strain gradient, written
    here), h_1 = e1 - e4 (torsion), h_2,3 = e2 +- e5 and h_4,5 = e3 +- e6 (bending per plane),
    plus, for a tapered element, hc[6 + p] (h_+ h_-^T + h_- h_+^T) per plane p; returns N.

    st = (EA, GJ, kd_y, ko_y, kd_z, ko_z, dd_y, dd_z): the energy is linear in these coefficients
    (bending energy 1/2 ((kd + dd) a^2 + 2 ko a b + (kd - dd) b^2) per plane, dd = 0 for a uniform
    element), so derivatives with respect to any material or section parameter are this same
    kernel evaluated with d st / d p.
    arch_on: 1 for beams (shallow-arch term in the axial strain), 0 for rods (chord strain only).
    """
    EA, GJ = st[0], st[1]
    a1, a2, b1, b2 = t1[1], t2[1], t1[2], t2[2]
    arch = arch_on * (2 * a1 * a1 - a1 * a2 + 2 * a2 * a2 + 2 * b1 * b1 - b1 * b2 + 2 * b2 * b2) / 30.0
    eps = u / L0 + arch
    ge[0] = 1.0 / L0
    ge[1] = 0.0
    ge[4] = 0.0
    ge[2] = arch_on * (4 * a1 - a2) / 30.0
    ge[5] = arch_on * (4 * a2 - a1) / 30.0
    ge[3] = arch_on * (4 * b1 - b2) / 30.0
    ge[6] = arch_on * (4 * b2 - b1) / 30.0
    N = EA * eps
    for i in range(7):
        f[i] = N * L0 * ge[i]
    kt = GJ / L0
    tw = t2[0] - t1[0]
    f[1] -= kt * tw
    f[4] += kt * tw
    hc[0] = EA * L0
    hc[1] = kt
    # Per bending plane the 2x2 block [[p, o], [o, p]] (bending plus the arch term's stress part)
    # is (p + o)/2 (e_i + e_j)(e_i + e_j)^T + (p - o)/2 (e_i - e_j)(e_i - e_j)^T.
    stress = arch_on * N * L0 / 30.0
    # A tapered element's block [[p + dd, o], [o, p - dd]] adds dd/2 (h_+ h_-^T + h_- h_+^T).
    for axis in range(2):
        if axis == 0:
            i, j, kd, ko, dd, ti, tj = 2, 5, st[2], st[3], st[6], t1[1], t2[1]
        else:
            i, j, kd, ko, dd, ti, tj = 3, 6, st[4], st[5], st[7], t1[2], t2[2]
        f[i] += (kd + dd) * ti + ko * tj
        f[j] += ko * ti + (kd - dd) * tj
        p = kd + 4.0 * stress
        o = ko - stress
        hc[2 + 2 * axis] = 0.5 * (p + o)
        hc[3 + 2 * axis] = 0.5 * (p - o)
        hc[6 + axis] = 0.5 * dd
    return N


@njit(**_FAST, inline="always")
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


@njit(**_FAST, inline="always")
def local_rotation(Rr, Rn, E0, qn, out, A, q4):
    """out = log(R_r^T R_n E0), the node's rotation relative to the element frame; qn = R_n E0[:, 1]
    (already at hand). Near the identity (the usual case) in scalars by the atan series (as logm's)."""
    t00 = Rn[0, 0] * E0[0, 0] + Rn[0, 1] * E0[1, 0] + Rn[0, 2] * E0[2, 0]
    t10 = Rn[1, 0] * E0[0, 0] + Rn[1, 1] * E0[1, 0] + Rn[1, 2] * E0[2, 0]
    t20 = Rn[2, 0] * E0[0, 0] + Rn[2, 1] * E0[1, 0] + Rn[2, 2] * E0[2, 0]
    t02 = Rn[0, 0] * E0[0, 2] + Rn[0, 1] * E0[1, 2] + Rn[0, 2] * E0[2, 2]
    t12 = Rn[1, 0] * E0[0, 2] + Rn[1, 1] * E0[1, 2] + Rn[1, 2] * E0[2, 2]
    t22 = Rn[2, 0] * E0[0, 2] + Rn[2, 1] * E0[1, 2] + Rn[2, 2] * E0[2, 2]
    a00 = Rr[0, 0] * t00 + Rr[1, 0] * t10 + Rr[2, 0] * t20
    a10 = Rr[0, 1] * t00 + Rr[1, 1] * t10 + Rr[2, 1] * t20
    a20 = Rr[0, 2] * t00 + Rr[1, 2] * t10 + Rr[2, 2] * t20
    a01 = Rr[0, 0] * qn[0] + Rr[1, 0] * qn[1] + Rr[2, 0] * qn[2]
    a11 = Rr[0, 1] * qn[0] + Rr[1, 1] * qn[1] + Rr[2, 1] * qn[2]
    a21 = Rr[0, 2] * qn[0] + Rr[1, 2] * qn[1] + Rr[2, 2] * qn[2]
    a02 = Rr[0, 0] * t02 + Rr[1, 0] * t12 + Rr[2, 0] * t22
    a12 = Rr[0, 1] * t02 + Rr[1, 1] * t12 + Rr[2, 1] * t22
    a22 = Rr[0, 2] * t02 + Rr[1, 2] * t12 + Rr[2, 2] * t22
    tr = a00 + a11 + a22
    if tr > 2.9:  # angle below 18 deg: the trace branch of Shepperd's quaternion (w > 0.98)
        w = 0.5 * np.sqrt(1.0 + tr)
        v0 = (a21 - a12) * 0.25 / w
        v1 = (a02 - a20) * 0.25 / w
        v2 = (a10 - a01) * 0.25 / w
        z2 = (v0 * v0 + v1 * v1 + v2 * v2) / (w * w)  # tan^2 of half the angle, below 0.025
        if z2 < 0.01:
            f = 2.0 / w * (1.0 - z2 * (1.0 / 3 - z2 * (1.0 / 5 - z2 * (1.0 / 7 - z2 * (
                1.0 / 9 - z2 * (1.0 / 11 - z2 * (1.0 / 13 - z2 * (1.0 / 15 - z2 / 17))))))))
            out[0] = f * v0
            out[1] = f * v1
            out[2] = f * v2
            return
    A[0, 0], A[0, 1], A[0, 2] = a00, a01, a02
    A[1, 0], A[1, 1], A[1, 2] = a10, a11, a12
    A[2, 0], A[2, 1], A[2, 2] = a20, a21, a22
    logm(A, out, q4)


@njit(**_FAST)
def element_frames_at(x, R, nodes, E0s, out):
    """out (n, 3, 3): the corotated frame of every element at nodal positions x, rotations R."""
    q1 = np.empty(3)
    q2 = np.empty(3)
    q = np.empty(3)
    for el in range(nodes.shape[0]):
        i1, i2 = nodes[el, 0], nodes[el, 1]
        corotated(x[i1], x[i2], R[i1], R[i2], E0s[el], out[el], q1, q2, q)


_CHUNK = 256  # elements per thread below which splitting the work costs more than it saves


@njit(cache=True, nogil=True, parallel=True)
def beam_kernel(x, R, nodes, E0s, L0s, stiff, arch, want_tangent, f_ref, g_out, K_out, f_out, threads):
    """All elements, in chunks over ``threads`` threads (elements are independent)."""
    n = nodes.shape[0]
    chunks = min(max(n // _CHUNK, 1), threads)
    for c in prange(chunks):
        _beam_chunk(x, R, nodes, E0s, L0s, stiff, arch, want_tangent, f_ref, g_out, K_out, f_out,
                    c * n // chunks, (c + 1) * n // chunks)


# The internal forces depend on the nodal translations only through x2 - x1, and they balance
# (g_x1 = -g_x2): the kernel works on 9 DOFs [dx (node 2 relative to node 1), spin1, spin2] and
# expands to the element's 12 at the end, K12[a, b] = s_a s_b K9[m_a, m_b].
_FULL_TO_9 = np.array([0, 1, 2, 3, 4, 5, 0, 1, 2, 6, 7, 8])
_FULL_SIGN = np.array([-1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0])


@njit(**_FAST)
def _beam_chunk(x, R, nodes, E0s, L0s, stiff, arch, want_tangent, f_ref, g_out, K_out, f_out, start, stop):
    """Internal forces g_out (n, 12), tangent K_out (n, 12, 12) with K[a, b] = d g_a / d p_b and local
    forces f_out (n, 7) = [N, M1, M2] conjugate to [elongation, local rotations of node 1, node 2].

    f_ref (n, 7) or (0, 7): local forces that replace the element's own in the stress-dependent
    (geometric) part of the tangent; the material part and the forces g_out stay exact.
    """
    m9 = _FULL_TO_9
    sg = _FULL_SIGN
    Rr = np.empty((3, 3))
    q1 = np.empty(3)
    q2 = np.empty(3)
    q = np.empty(3)
    t1 = np.empty(3)
    t2 = np.empty(3)
    f = np.empty(7)
    ge = np.empty(7)
    hc = np.empty(8)
    w = np.empty((6, 9))
    hw = np.empty((6, 9))
    om = np.zeros((9, 3))
    dth = np.zeros((2, 9, 3))
    a1 = np.empty(3)
    a2 = np.empty(3)
    tmp = np.empty(3)
    tmp2 = np.empty(3)
    mu = np.empty((2, 3))
    dln = np.zeros(9)
    A33 = np.empty((3, 3))
    q4 = np.empty(4)
    r1 = np.empty(3)
    r2 = np.empty(3)
    r3 = np.empty(3)
    G = np.empty((2, 3, 3))
    K9 = np.empty((9, 9))
    for el in range(start, stop):
        i1, i2 = nodes[el, 0], nodes[el, 1]
        x1, x2 = x[i1], x[i2]
        R1, R2 = R[i1], R[i2]
        E0 = E0s[el]
        L0 = L0s[el]
        ln = corotated(x1, x2, R1, R2, E0, Rr, q1, q2, q)
        for i in range(3):
            r1[i], r2[i], r3[i] = Rr[i, 0], Rr[i, 1], Rr[i, 2]
        local_rotation(Rr, R1, E0, q1, t1, A33, q4)
        local_rotation(Rr, R2, E0, q2, t2, A33, q4)
        c1, e1 = jl_inv_coeffs(t1)
        c2, e2 = jl_inv_coeffs(t2)
        N = local_energy(ln - L0, t1, t2, L0, stiff[el], arch[el], f, ge, hc)
        for i in range(7):
            f_out[el, i] = f[i]
        # mu_s = Jinv_s^T m_s (the nodal moments): the rotation parts of g = B f are wb . mu.
        jl_inv_apply(t1, c1, f[1:4], mu[0], 1.0)
        jl_inv_apply(t2, c2, f[4:7], mu[1], 1.0)
        qb1 = _dot(r1, q)
        qb2 = _dot(r2, q)
        _cross(q1, r3, a1)
        _cross(q2, r3, a2)
        # g = B f = dln f0 + wb . mu over the 9 DOFs, wb[s, k] = W_s[k] - om[k] (W_s[k]: row of R_r
        # for the node's own spins), written out: om[k] = (qb1 om_1 / qb2, -r3[k] / ln, r2[k] / ln) for
        # the relative translations and (a_s[i] / (2 qb2), 0, 0) for the spins of node s.
        f0 = f[0]
        ms0, ms1, ms2 = mu[0, 0] + mu[1, 0], mu[0, 1] + mu[1, 1], mu[0, 2] + mu[1, 2]
        for k in range(3):
            o1 = -r3[k] / ln
            o2 = r2[k] / ln
            gk = r1[k] * f0 - (qb1 * o1 / qb2 * ms0 + o1 * ms1 + o2 * ms2)
            g_out[el, k] = -gk
            g_out[el, 6 + k] = gk
            g_out[el, 3 + k] = Rr[k, 0] * mu[0, 0] + Rr[k, 1] * mu[0, 1] + Rr[k, 2] * mu[0, 2] - 0.5 * a1[k] / qb2 * ms0
            g_out[el, 9 + k] = Rr[k, 0] * mu[1, 0] + Rr[k, 1] * mu[1, 1] + Rr[k, 2] * mu[1, 2] - 0.5 * a2[k] / qb2 * ms0
        if not want_tangent:
            continue
        if f_ref.shape[0] > 0 and stiff[el, 0] != 0.0:
            # H's stress terms (shallow-arch strain) with the reference axial force: the energy is
            # evaluated at the elongation that gives that force, then the reference forces replace f.
            EA = stiff[el, 0]
            arch_strain = N / EA - (ln - L0) / L0
            local_energy((f_ref[el, 0] / EA - arch_strain) * L0, t1, t2, L0, stiff[el], arch[el], f, ge, hc)
            for i in range(7):
                f[i] = f_ref[el, i]
            jl_inv_apply(t1, c1, f[1:4], mu[0], 1.0)
            jl_inv_apply(t2, c2, f[4:7], mu[1], 1.0)
        for k in range(9):
            # Spin of the frame for a unit DOF k: about r2, r3 from the chord (translations), about
            # r1 from the twist of the mean e2 vector (q through qb1 and the spins of q1, q2).
            if k < 3:
                dln[k] = r1[k]
                o1 = -r3[k] / ln
                o2 = r2[k] / ln
                o0 = qb1 * o1 / qb2
            else:
                o0 = 0.5 * (a1[k - 3] if k < 6 else a2[k - 6]) / qb2
                o1 = o2 = 0.0
            om[k, 0], om[k, 1], om[k, 2] = o0, o1, o2
            # dth_s = Jinv_s wb_s with wb_s = R_r^T W_s[k] - om (W_s[k]: the node's own spins)
            for s_ in range(2):
                own = 3 + 3 * s_ <= k < 6 + 3 * s_
                row = k - 3 - 3 * s_
                v0 = (Rr[row, 0] if own else 0.0) - o0
                v1 = (Rr[row, 1] if own else 0.0) - o1
                v2 = (Rr[row, 2] if own else 0.0) - o2
                th = t1 if s_ == 0 else t2
                cs = c1 if s_ == 0 else c2
                u0, u1, u2 = _cx(th[0], th[1], th[2], v0, v1, v2)
                y0, y1, y2 = _cx(th[0], th[1], th[2], u0, u1, u2)
                dth[s_, k, 0] = v0 - 0.5 * u0 + cs * y0
                dth[s_, k, 1] = v1 - 0.5 * u1 + cs * y1
                dth[s_, k, 2] = v2 - 0.5 * u2 + cs * y2
            # Material part B H B^T = sum_t hc[t] w_t w_t^T, w_t = B h_t (B[k] = [dln, dth_1, dth_2]).
            a0, a1_, a2_ = dth[0, k, 0], dth[0, k, 1], dth[0, k, 2]
            b0, b1, b2 = dth[1, k, 0], dth[1, k, 1], dth[1, k, 2]
            w[0, k] = dln[k] * ge[0] + a1_ * ge[2] + a2_ * ge[3] + b1 * ge[5] + b2 * ge[6]  # ge[1] = ge[4] = 0
            w[1, k] = a0 - b0
            w[2, k] = a1_ + b1
            w[3, k] = a1_ - b1
            w[4, k] = a2_ + b2
            w[5, k] = a2_ - b2
            for t in range(6):
                hw[t, k] = hc[t] * w[t, k]
        for a in range(9):  # one triangle, mirrored
            for b in range(a, 9):
                acc = (hw[0, a] * w[0, b] + hw[1, a] * w[1, b] + hw[2, a] * w[2, b] + hw[3, a] * w[3, b]
                       + hw[4, a] * w[4, b] + hw[5, a] * w[5, b])
                K9[a, b] = acc
                K9[b, a] = acc
        if hc[6] != 0.0 or hc[7] != 0.0:  # tapered: the cross terms of the two bending blocks
            cy, cz = hc[6], hc[7]
            for a in range(9):
                for b in range(a, 9):
                    acc = (cy * (w[2, a] * w[3, b] + w[3, a] * w[2, b])
                           + cz * (w[4, a] * w[5, b] + w[5, a] * w[4, b]))
                    K9[a, b] += acc
                    if b != a:
                        K9[b, a] += acc
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
        f0 = f[0]
        ms0, ms1, ms2 = mu[0, 0] + mu[1, 0], mu[0, 1] + mu[1, 1], mu[0, 2] + mu[1, 2]
        # Geometric part, column j: d g_k / d p_j of the terms wb . mu and dln f0. Each is om[k] . u_j
        # (dense, rank 3: wb[s, k] = W_s[k] - om[k] and the frame-twist om[k, 0] depends on the
        # frame through qb1, qb2) plus terms on the rows where D[k] or W_s[k] is non-zero. One pass
        # per column j with scalar temporaries: the frame's derivative (dr1, dr2, dr3 = omg x r),
        # the twist ingredients (dqb1, dqb2, da1, da2) and the Jacobian derivative (nu_s).
        c0s = ms0 / qb2
        beta = ms1 + c0s * qb1
        for j in range(9):
            o0, o1, o2 = om[j, 0], om[j, 1], om[j, 2]
            g0 = Rr[0, 0] * o0 + Rr[0, 1] * o1 + Rr[0, 2] * o2  # frame spin in global axes
            g1 = Rr[1, 0] * o0 + Rr[1, 1] * o1 + Rr[1, 2] * o2
            g2 = Rr[2, 0] * o0 + Rr[2, 1] * o1 + Rr[2, 2] * o2
            d20, d21, d22 = _cx(g0, g1, g2, r2[0], r2[1], r2[2])
            d30, d31, d32 = _cx(g0, g1, g2, r3[0], r3[1], r3[2])
            if j < 3:  # the chord direction moves with the relative translation only
                d10 = ((1.0 if j == 0 else 0.0) - r1[0] * r1[j]) / ln
                d11 = ((1.0 if j == 1 else 0.0) - r1[1] * r1[j]) / ln
                d12 = ((1.0 if j == 2 else 0.0) - r1[2] * r1[j]) / ln
            else:
                d10 = d11 = d12 = 0.0
            # z = e_i x q_s: the spin of q1 (j = 3..5) or q2 (j = 6..8) about axis e_i
            z0 = z1 = z2 = 0.0
            if j >= 3:
                qs = q1 if j < 6 else q2
                i = (j - 3) % 3
                z0, z1, z2 = _cx(1.0 if i == 0 else 0.0, 1.0 if i == 1 else 0.0, 1.0 if i == 2 else 0.0,
                                   qs[0], qs[1], qs[2])
            dqb1 = d10 * q[0] + d11 * q[1] + d12 * q[2] + 0.5 * (z0 * r1[0] + z1 * r1[1] + z2 * r1[2])
            dqb2 = d20 * q[0] + d21 * q[1] + d22 * q[2] + 0.5 * (z0 * r2[0] + z1 * r2[1] + z2 * r2[2])
            a10, a11, a12 = _cx(q1[0], q1[1], q1[2], d30, d31, d32)
            a20, a21, a22 = _cx(q2[0], q2[1], q2[2], d30, d31, d32)
            if j >= 3:
                b0, b1, b2 = _cx(z0, z1, z2, r3[0], r3[1], r3[2])
                if j < 6:
                    a10, a11, a12 = a10 + b0, a11 + b1, a12 + b2
                else:
                    a20, a21, a22 = a20 + b0, a21 + b1, a22 + b2
            # nu_s = (d Jinv_s[dth_s])^T m_s
            n00 = G[0, 0, 0] * dth[0, j, 0] + G[0, 0, 1] * dth[0, j, 1] + G[0, 0, 2] * dth[0, j, 2]
            n01 = G[0, 1, 0] * dth[0, j, 0] + G[0, 1, 1] * dth[0, j, 1] + G[0, 1, 2] * dth[0, j, 2]
            n02 = G[0, 2, 0] * dth[0, j, 0] + G[0, 2, 1] * dth[0, j, 1] + G[0, 2, 2] * dth[0, j, 2]
            n10 = G[1, 0, 0] * dth[1, j, 0] + G[1, 0, 1] * dth[1, j, 1] + G[1, 0, 2] * dth[1, j, 2]
            n11 = G[1, 1, 0] * dth[1, j, 0] + G[1, 1, 1] * dth[1, j, 1] + G[1, 1, 2] * dth[1, j, 2]
            n12 = G[1, 2, 0] * dth[1, j, 0] + G[1, 2, 1] * dth[1, j, 1] + G[1, 2, 2] * dth[1, j, 2]
            dl = dln[j] / ln
            U0 = c0s * dqb2 - (n00 + n10)
            U1 = beta * dl - c0s * dqb1 - (n01 + n11)
            U2 = ms2 * dl - (n02 + n12)
            for a in range(9):  # the rank-3 part om[a] . U (the spins' om has its first component only)
                K9[a, j] += om[a, 0] * U0
            for a in range(3):
                K9[a, j] += om[a, 1] * U1 + om[a, 2] * U2
            y0, y1, y2 = _cx(mu[0, 0], mu[0, 1], mu[0, 2], o0, o1, o2)
            p0, p1, p2 = n00 - y0, n01 - y1, n02 - y2  # node 1: nu_1 - mu_1 x om
            y0, y1, y2 = _cx(mu[1, 0], mu[1, 1], mu[1, 2], o0, o1, o2)
            u0, u1, u2 = n10 - y0, n11 - y1, n12 - y2  # node 2
            # spin rows of node 1 and node 2 (W_s[k] is row (k - base) of Rr), then the relative
            # translation rows (D[k] = e_i)
            K9[3, j] += Rr[0, 0] * p0 + Rr[0, 1] * p1 + Rr[0, 2] * p2 - 0.5 * c0s * a10
            K9[4, j] += Rr[1, 0] * p0 + Rr[1, 1] * p1 + Rr[1, 2] * p2 - 0.5 * c0s * a11
            K9[5, j] += Rr[2, 0] * p0 + Rr[2, 1] * p1 + Rr[2, 2] * p2 - 0.5 * c0s * a12
            K9[6, j] += Rr[0, 0] * u0 + Rr[0, 1] * u1 + Rr[0, 2] * u2 - 0.5 * c0s * a20
            K9[7, j] += Rr[1, 0] * u0 + Rr[1, 1] * u1 + Rr[1, 2] * u2 - 0.5 * c0s * a21
            K9[8, j] += Rr[2, 0] * u0 + Rr[2, 1] * u1 + Rr[2, 2] * u2 - 0.5 * c0s * a22
            K9[0, j] += f0 * d10 + (beta * d30 - ms2 * d20) / ln
            K9[1, j] += f0 * d11 + (beta * d31 - ms2 * d21) / ln
            K9[2, j] += f0 * d12 + (beta * d32 - ms2 * d22) / ln
        K = K_out[el]
        for a in range(12):  # K[a, b] = d g_a / d p_b, expanded from the 9 DOFs
            ra, sa = m9[a], sg[a]
            for b in range(12):
                K[a, b] = sa * sg[b] * K9[ra, m9[b]]
