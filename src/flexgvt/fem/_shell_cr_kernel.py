"""Compiled corotational shell kernel: the forces and the exact tangent of fem._shell_corotational
(whose NumPy version is the readable reference and documents the formulation), per element in scalar
code on 3-tuples, forward-differentiated along the 6 p unit directions one at a time."""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from .rotations import logm3

_FAST = dict(cache=True, fastmath={"contract", "reassoc", "arcp", "nsz"}, nogil=True, error_model="numpy")
_CHUNK = 64


@njit(**_FAST, inline="always")
def _cr(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(**_FAST, inline="always")
def _dt(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**_FAST, inline="always")
def _ad(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(**_FAST, inline="always")
def _sb(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(**_FAST, inline="always")
def _sc(s, a):
    return (s * a[0], s * a[1], s * a[2])


@njit(**_FAST, inline="always")
def _get(A, i):
    return (A[i, 0], A[i, 1], A[i, 2])


@njit(**_FAST, inline="always")
def _put(A, i, v):
    A[i, 0], A[i, 1], A[i, 2] = v[0], v[1], v[2]


@njit(**_FAST, inline="always")
def _mv(e1, e2, e3, v):
    """[e1 e2 e3] v."""
    return (e1[0] * v[0] + e2[0] * v[1] + e3[0] * v[2], e1[1] * v[0] + e2[1] * v[1] + e3[1] * v[2],
            e1[2] * v[0] + e2[2] * v[1] + e3[2] * v[2])


@njit(**_FAST, inline="always")
def _jinv(th, c, v, sign):
    """Jinv(th) v (sign -1) or Jinv(th)^T v (sign +1); Jinv = I - S/2 + c S^2."""
    u = _cr(th, v)
    w = _cr(th, u)
    return (v[0] + sign * 0.5 * u[0] + c * w[0], v[1] + sign * 0.5 * u[1] + c * w[1],
            v[2] + sign * 0.5 * u[2] + c * w[2])


@njit(**_FAST, inline="always")
def _djinv_t(th, c, e, dth, m):
    """(d Jinv[dth])^T m."""
    x = _cr(th, m)
    a = _cr(th, x)
    b = _cr(dth, x)
    y = _cr(dth, m)
    z = _cr(th, y)
    td = _dt(th, dth)
    return (0.5 * y[0] + e * td * a[0] + c * (b[0] + z[0]), 0.5 * y[1] + e * td * a[1] + c * (b[1] + z[1]),
            0.5 * y[2] + e * td * a[2] + c * (b[2] + z[2]))


@njit(**_FAST, inline="always")
def _coeffs(t2):
    """c and e = c'/t of Jinv."""
    if t2 < 1e-4:
        return 1 / 12 + t2 / 720 + t2 * t2 / 30240, 1 / 360 + t2 / 7560 + t2 * t2 / 201600
    t = np.sqrt(t2)
    half = 0.5 * t
    cot = np.cos(half) / np.sin(half)
    dc = -2 / t**3 + 1 / (4 * t * np.sin(half) ** 2) + cot / (2 * t2)
    return 1 / t2 - cot / (2 * t), dc / t


@njit(**_FAST, inline="always")
def _incidence(p, a):
    """Signs of corner a in (d1, d2): quad d1 = x3 - x1, d2 = x4 - x2; triangle d1 = x2 - x1, d2 = x3 - x1."""
    if p == 4:
        return (-1.0 if a == 0 else (1.0 if a == 2 else 0.0)), (-1.0 if a == 1 else (1.0 if a == 3 else 0.0))
    return (-1.0 if a == 0 else (1.0 if a == 1 else 0.0)), (-1.0 if a == 0 else (1.0 if a == 2 else 0.0))


@njit(**_FAST)
def _local(el, Kl, GN, KS, d, fl, Kt, Nj, Kd, tangent):
    """fl = K d (+ the initial-stress force) and, if tangent, the local tangent Kt at deformations d."""
    k = d.shape[0]
    for i in range(k):
        acc = 0.0
        for j in range(k):
            acc += Kl[el, i, j] * d[j]
        fl[i] = acc
    if tangent:
        for i in range(k):
            for j in range(k):
                Kt[i, j] = Kl[el, i, j]
    if KS.shape[0] == 0:
        return
    for m in range(3):
        acc = 0.0
        for j in range(k):
            acc += GN[el, m, j] * d[j]
        Nj[m] = acc
        qq = 0.0
        for i in range(k):
            acc = 0.0
            for j in range(k):
                acc += KS[el, m, i, j] * d[j]
            Kd[m, i] = acc
            qq += d[i] * acc
        for i in range(k):
            fl[i] += Nj[m] * Kd[m, i] + 0.5 * qq * GN[el, m, i]
    if tangent:
        for i in range(k):
            for j in range(k):
                acc = 0.0
                for m in range(3):
                    acc += Nj[m] * KS[el, m, i, j] + Kd[m, i] * GN[el, m, j] + GN[el, m, i] * Kd[m, j]
                Kt[i, j] += acc


@njit(**_FAST)
def _stress(fl, th, cs, rs, e1, e2, e3, nms, Ns, Ms):
    """Global corner forces N, moments M (and H^T f_l,m) of local forces fl; V and mean(N)."""
    p = th.shape[0]
    V = (0.0, 0.0, 0.0)
    mN = (0.0, 0.0, 0.0)
    for a in range(p):
        flu = (fl[6 * a], fl[6 * a + 1], fl[6 * a + 2])
        nm = _jinv(_get(th, a), cs[a], (fl[6 * a + 3], fl[6 * a + 4], fl[6 * a + 5]), 1.0)
        _put(nms, a, nm)
        Na = _mv(e1, e2, e3, flu)
        Ma = _mv(e1, e2, e3, nm)
        _put(Ns, a, Na)
        _put(Ms, a, Ma)
        V = _ad(V, _ad(_cr(_get(rs, a), Na), Ma))
        mN = _ad(mN, _sc(1.0 / p, Na))
    return V, mN


@njit(**_FAST)
def _frame_grad(V, e1, e2, e3, ln, la, d1, d2, u1, u2, l1, l2, p):
    """G^T V on d1 and d2 (g1, g2) and the intermediate vectors of its derivative."""
    wn = _sc(1.0 / ln, _cr(V, e3))
    Ve3 = _dt(V, e3)
    wa = _sc(Ve3 / la, e2)
    g1 = _cr(d2, wn)
    g2 = _cr(wn, d1)
    q1 = q2 = wa
    if p == 4:
        q1 = _sc(1.0 / l1, _sb(wa, _sc(_dt(u1, wa), u1)))
        q2 = _sc(1.0 / l2, _sb(wa, _sc(_dt(u2, wa), u2)))
        g1, g2 = _ad(g1, q1), _sb(g2, q2)
    else:
        g1 = _ad(g1, wa)
    return wn, Ve3, wa, q1, q2, g1, g2


@njit(**_FAST)
def cr_chunk(Xl, E0, Kl, GN, KS, x, Rr, tangent, ref_fl, ref_d, forces, K_out, frames, d_out, fl_out, start,
             stop):
    p = x.shape[1]
    k = 6 * p
    has_ref = ref_fl.shape[0] > 0
    xs = np.empty((p, 3))
    rs = np.empty((p, 3))
    th = np.empty((p, 3))
    cs = np.empty(p)
    es = np.empty(p)
    Ns = np.empty((p, 3))
    Ms = np.empty((p, 3))
    nms = np.empty((p, 3))
    dNs = np.empty((p, 3))
    dMs = np.empty((p, 3))
    Rd = np.empty((3, 3))
    q = np.empty(4)
    tv = np.empty(3)
    d = np.empty(k)
    fl = np.empty(k)
    Kt = np.empty((k, k))
    ddv = np.empty(k)
    dfl = np.empty(k)
    Nj = np.empty(3)
    Kd = np.empty((3, k))
    for el in range(start, stop):
        for a in range(p):
            for i in range(3):
                xs[a, i] = x[el, a, i]
        if p == 4:
            d1 = _sb(_get(xs, 2), _get(xs, 0))
            d2 = _sb(_get(xs, 3), _get(xs, 1))
            l1, l2 = np.sqrt(_dt(d1, d1)), np.sqrt(_dt(d2, d2))
            u1, u2 = _sc(1.0 / l1, d1), _sc(1.0 / l2, d2)
            av = _sb(u1, u2)
        else:
            d1 = _sb(_get(xs, 1), _get(xs, 0))
            d2 = _sb(_get(xs, 2), _get(xs, 0))
            l1 = l2 = 1.0
            u1 = u2 = d1
            av = d1
        nv = _cr(d1, d2)
        ln = np.sqrt(_dt(nv, nv))
        la = np.sqrt(_dt(av, av))
        e3 = _sc(1.0 / ln, nv)
        e1 = _sc(1.0 / la, av)
        e2 = _cr(e3, e1)
        for i in range(3):
            frames[el, i, 0], frames[el, i, 1], frames[el, i, 2] = e1[i], e2[i], e3[i]
        xc = (0.0, 0.0, 0.0)
        for a in range(p):
            xc = _ad(xc, _get(xs, a))
        xc = _sc(1.0 / p, xc)
        for a in range(p):
            r = _sb(_get(xs, a), xc)
            _put(rs, a, r)
            d[6 * a] = _dt(e1, r) - Xl[el, a, 0]
            d[6 * a + 1] = _dt(e2, r) - Xl[el, a, 1]
            d[6 * a + 2] = _dt(e3, r) - Xl[el, a, 2]
            for j in range(3):  # Rd = E^T Rr E0
                c0 = Rr[el, a, 0, 0] * E0[el, 0, j] + Rr[el, a, 0, 1] * E0[el, 1, j] + Rr[el, a, 0, 2] * E0[el, 2, j]
                c1 = Rr[el, a, 1, 0] * E0[el, 0, j] + Rr[el, a, 1, 1] * E0[el, 1, j] + Rr[el, a, 1, 2] * E0[el, 2, j]
                c2 = Rr[el, a, 2, 0] * E0[el, 0, j] + Rr[el, a, 2, 1] * E0[el, 1, j] + Rr[el, a, 2, 2] * E0[el, 2, j]
                col = (c0, c1, c2)
                Rd[0, j], Rd[1, j], Rd[2, j] = _dt(e1, col), _dt(e2, col), _dt(e3, col)
            logm3(Rd, tv, q)
            for i in range(3):
                th[a, i] = tv[i]
                d[6 * a + 3 + i] = tv[i]
            cs[a], es[a] = _coeffs(_dt(_get(th, a), _get(th, a)))
        _local(el, Kl, GN, KS, d, fl, Kt, Nj, Kd, tangent and not has_ref)
        for i in range(k):
            d_out[el, i] = d[i]
            fl_out[el, i] = fl[i]
        V, mN = _stress(fl, th, cs, rs, e1, e2, e3, nms, Ns, Ms)
        wn, Ve3, wa, q1, q2, g1, g2 = _frame_grad(V, e1, e2, e3, ln, la, d1, d2, u1, u2, l1, l2, p)
        for a in range(p):
            s1, s2 = _incidence(p, a)
            ga = _ad(_sc(s1, g1), _sc(s2, g2))
            fa = _sb(_sb(_get(Ns, a), mN), ga)
            Ma = _get(Ms, a)
            for i in range(3):
                forces[el, 6 * a + i] = fa[i]
                forces[el, 6 * a + 3 + i] = Ma[i]
        if not tangent:
            continue
        if has_ref:  # the stress-dependent parts from another state's local forces and deformations
            for i in range(k):
                fl[i] = ref_fl[el, i]
                d[i] = ref_d[el, i]
            _local(el, Kl, GN, KS, d, dfl, Kt, Nj, Kd, True)
            V, mN = _stress(fl, th, cs, rs, e1, e2, e3, nms, Ns, Ms)
            wn, Ve3, wa, q1, q2, g1, g2 = _frame_grad(V, e1, e2, e3, ln, la, d1, d2, u1, u2, l1, l2, p)
        for col in range(k):
            na, cj = col // 6, col % 6
            ev = (1.0 if cj == 0 else 0.0, 1.0 if cj == 1 else 0.0, 1.0 if cj == 2 else 0.0)
            ov = (1.0 if cj == 3 else 0.0, 1.0 if cj == 4 else 0.0, 1.0 if cj == 5 else 0.0)
            s1, s2 = _incidence(p, na)
            dd1, dd2 = _sc(s1, ev), _sc(s2, ev)
            dn = _ad(_cr(dd1, d2), _cr(d1, dd2))
            if p == 4:
                du1 = _sc(1.0 / l1, _sb(dd1, _sc(_dt(u1, dd1), u1)))
                du2 = _sc(1.0 / l2, _sb(dd2, _sc(_dt(u2, dd2), u2)))
                da = _sb(du1, du2)
            else:
                du1 = du2 = dd1
                da = dd1
            wr = _ad(_sc(1.0 / ln, _sb(_sc(_dt(e1, dn), e2), _sc(_dt(e2, dn), e1))), _sc(_dt(e2, da) / la, e3))
            de1, de2, de3 = _cr(wr, e1), _cr(wr, e2), _cr(wr, e3)
            dln, dla = _dt(e3, dn), _dt(e1, da)
            for b in range(p):
                r = _get(rs, b)
                drb = _sc((1.0 if b == na else 0.0) - 1.0 / p, ev)
                ddv[6 * b] = _dt(de1, r) + _dt(e1, drb)
                ddv[6 * b + 1] = _dt(de2, r) + _dt(e2, drb)
                ddv[6 * b + 2] = _dt(de3, r) + _dt(e3, drb)
                w = _sb(ov, wr) if b == na else _sc(-1.0, wr)
                dth = _jinv(_get(th, b), cs[b], (_dt(e1, w), _dt(e2, w), _dt(e3, w)), -1.0)
                ddv[6 * b + 3], ddv[6 * b + 4], ddv[6 * b + 5] = dth[0], dth[1], dth[2]
            for i in range(k):
                acc = 0.0
                for j in range(k):
                    acc += Kt[i, j] * ddv[j]
                dfl[i] = acc
            dV = (0.0, 0.0, 0.0)
            mdN = (0.0, 0.0, 0.0)
            for b in range(p):
                thb = _get(th, b)
                flm = (fl[6 * b + 3], fl[6 * b + 4], fl[6 * b + 5])
                dthb = (ddv[6 * b + 3], ddv[6 * b + 4], ddv[6 * b + 5])
                dnm = _ad(_jinv(thb, cs[b], (dfl[6 * b + 3], dfl[6 * b + 4], dfl[6 * b + 5]), 1.0),
                          _djinv_t(thb, cs[b], es[b], dthb, flm))
                flu = (fl[6 * b], fl[6 * b + 1], fl[6 * b + 2])
                dN = _ad(_mv(de1, de2, de3, flu), _mv(e1, e2, e3, (dfl[6 * b], dfl[6 * b + 1], dfl[6 * b + 2])))
                dM = _ad(_mv(de1, de2, de3, _get(nms, b)), _mv(e1, e2, e3, dnm))
                _put(dNs, b, dN)
                _put(dMs, b, dM)
                drb = _sc((1.0 if b == na else 0.0) - 1.0 / p, ev)
                dV = _ad(dV, _ad(_ad(_cr(drb, _get(Ns, b)), _cr(_get(rs, b), dN)), dM))
                mdN = _ad(mdN, _sc(1.0 / p, dN))
            dwn = _sb(_sc(1.0 / ln, _ad(_cr(dV, e3), _cr(V, de3))), _sc(dln / ln, wn))
            dVe3 = _dt(dV, e3) + _dt(V, de3)
            dwa = _sb(_sc(1.0 / la, _ad(_sc(dVe3, e2), _sc(Ve3, de2))), _sc(dla / la, wa))
            dg1 = _ad(_cr(dd2, wn), _cr(d2, dwn))
            dg2 = _ad(_cr(dwn, d1), _cr(wn, dd1))
            if p == 4:
                dq1 = _sb(_sc(1.0 / l1, _sb(_sb(dwa, _sc(_dt(u1, wa), du1)), _sc(_dt(du1, wa) + _dt(u1, dwa), u1))),
                          _sc(_dt(u1, dd1) / l1, q1))
                dq2 = _sb(_sc(1.0 / l2, _sb(_sb(dwa, _sc(_dt(u2, wa), du2)), _sc(_dt(du2, wa) + _dt(u2, dwa), u2))),
                          _sc(_dt(u2, dd2) / l2, q2))
                dg1, dg2 = _ad(dg1, dq1), _sb(dg2, dq2)
            else:
                dg1 = _ad(dg1, dwa)
            for b in range(p):
                t1, t2 = _incidence(p, b)
                dfb = _sb(_sb(_get(dNs, b), mdN), _ad(_sc(t1, dg1), _sc(t2, dg2)))
                for i in range(3):
                    K_out[el, 6 * b + i, col] = dfb[i]
                    K_out[el, 6 * b + 3 + i, col] = dMs[b, i]


@njit(cache=True, parallel=True)
def cr_kernel(Xl, E0, Kl, GN, KS, x, Rr, tangent, ref_fl, ref_d, forces, K_out, frames, d_out, fl_out,
              threads):  # pragma: no cover
    n = x.shape[0]
    chunks = (n + _CHUNK - 1) // _CHUNK
    for c in prange(chunks):
        cr_chunk(Xl, E0, Kl, GN, KS, x, Rr, tangent, ref_fl, ref_d, forces, K_out, frames, d_out, fl_out,
                 c * _CHUNK, min(n, (c + 1) * _CHUNK))
