"""Element-independent corotational (EICR) wrapper of the linear flat shells (Rankin & Nour-Omid 1988;
Felippa & Haugen 2005): large rotations, small strains, with the exact consistent tangent.

Conventions (those of fem/rotations.py and the beam family): node rotations R are total rotations
updated by spatial spins, R <- exp(skew(w)) R; element vectors are over [dx, w] per node (6 p); the
tangent is K[a, b] = d f_a / d p_b in these variables (not symmetric away from equilibrium).

Corotated frame E (columns e1, e2, e3) of the current corners x (p, 3), a function of the corner
differences only:
  quad:     e3 along d1 x d2 (diagonals d1 = x3 - x1, d2 = x4 - x2), e1 along d1/|d1| - d2/|d2| (the
            bisector of the diagonals: exactly in the plane, symmetric in the corners; renumbering the
            corners cyclically turns it by 90 deg, which the local element does not notice);
  triangle: e3 along (x2 - x1) x (x3 - x1), e1 along side 1-2.
Local deformational displacements and rotations of corner a (X the reference corners, E0 the frame
there, x_c, X_c the centroids, R0 the reference node rotations, identity by default):
  u_a = E^T (x_a - x_c) - E0^T (X_a - X_c),   theta_a = log(E^T R_a R0_a^T E0).
Local forces f_l = K_l d with the linear element's stiffness in the frame E0 (constant). With the
frame spin w_r (dE = skew(w_r) E, w_r = sum_b G_b dx_b) and H_a = Jinv(theta_a) the inverse left
Jacobian (d theta_a = H_a E^T (w_a - w_r)), virtual work gives the global forces
  f_x,b = N_b - mean(N) - G_b^T V,   f_w,b = M_b,
  N_a = E f_l,u,a,  M_a = E H_a^T f_l,m,a,  V = sum_a (x_a - x_c) x N_a + M_a,
i.e. f = T^T P^T H^T f_l written out (P: the projector dd = P dp removing the frame's rigid motion).
The tangent is the forward derivative of these expressions, by hand (as the beam kernel): the
material part T^T P^T H^T K_l H P T, the moment-correction part from dH (Felippa-Haugen's K_M), the
rotation of N and M with the frame (K_GR) and the change of G and of the lever arms (K_GP).

corotational_terms runs the compiled kernel (_shell_cr_kernel, per element, numba threads over
chunks); corotational_terms_numpy is the same in NumPy, vectorised over elements and directions,
kept as the readable reference the kernel is tested against.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from ..errors import ModelError
from ._shell_cr_kernel import _CHUNK, cr_chunk, cr_kernel
from ._shell_elements import DRILL_FACTOR, shell_geometric, shell_matrices
from .rotations import cross, jl_inv, jl_inv_derivative_T, logm_so3


@dataclass(frozen=True)
class CorotationalShells:
    """Per-element constants of n corotational shells with p corners: X (n, p, 3) reference corners
    [m], E0 (n, 3, 3) the corotated frame there, Xl (n, p, 3) the corners about their centroid in E0,
    K (n, 6p, 6p) the linear stiffness in E0 (element DOFs [u, v, w, rx, ry, rz] per corner);
    with the initial-stress term: GN (n, 3, 6p) the element's mean membrane resultants [Nx, Ny, Nxy]
    (kernel axes) as a linear function of d, KS (n, 3, 6p, 6p) the initial-stress matrices of unit
    Nx, Ny, Nxy in E0 (shell_geometric); None without. M (n, 6p, 6p): the element mass matrices in
    E0 when asked for (they turn with the corotated frame), else None."""

    X: np.ndarray
    E0: np.ndarray
    Xl: np.ndarray
    K: np.ndarray
    GN: np.ndarray | None = None
    KS: np.ndarray | None = None
    M: np.ndarray | None = None


@dataclass(frozen=True)
class CorotationalTerms:
    """forces (n, 6p) conjugate to [dx, spin] per node [N, N m]; tangent (n, 6p, 6p) or None;
    frames (n, 3, 3) the corotated frames; d (n, 6p) the local deformational displacements and
    rotation vectors [m, rad]; f_local (n, 6p) = K_l d [N, N m]."""

    forces: np.ndarray
    tangent: np.ndarray | None
    frames: np.ndarray
    d: np.ndarray
    f_local: np.ndarray


def _dot(a, b):
    return np.sum(a * b, axis=-1)


def _diffs(x):
    """(d1, d2) of corners x (..., p, 3): diagonals of a quad, sides 1-2 and 1-3 of a triangle."""
    if x.shape[-2] == 4:
        return x[..., 2, :] - x[..., 0, :], x[..., 3, :] - x[..., 1, :]
    return x[..., 1, :] - x[..., 0, :], x[..., 2, :] - x[..., 0, :]


def _scatter(g1, g2, p):
    """Corner vectors (..., p, 3) of the gradients g1, g2 (..., 3) with respect to d1, d2."""
    out = np.zeros(g1.shape[:-1] + (p, 3))
    if p == 4:
        out[..., 0, :], out[..., 2, :] = -g1, g1
        out[..., 1, :], out[..., 3, :] = -g2, g2
    else:
        out[..., 0, :] = -g1 - g2
        out[..., 1, :], out[..., 2, :] = g1, g2
    return out


class _Frame:
    """The corotated frame of corners x (n, p, 3) with what its derivatives need."""

    def __init__(self, x):
        self.p = x.shape[-2]
        self.d1, self.d2 = _diffs(x)
        n = cross(self.d1, self.d2)
        self.ln = np.linalg.norm(n, axis=-1)
        if self.p == 4:
            self.l1 = np.linalg.norm(self.d1, axis=-1)
            self.l2 = np.linalg.norm(self.d2, axis=-1)
            self.u1, self.u2 = self.d1 / self.l1[..., None], self.d2 / self.l2[..., None]
            a = self.u1 - self.u2
        else:
            a = self.d1
        self.la = np.linalg.norm(a, axis=-1)
        self.e3 = n / self.ln[..., None]
        self.e1 = a / self.la[..., None]
        self.e2 = cross(self.e3, self.e1)
        self.E = np.stack([self.e1, self.e2, self.e3], axis=-1)

    def da(self, dd1):
        """Change of the in-plane vector a for the changes dd1, dd2 (n, k, 3) along k directions."""
        if self.p == 4:
            dd1, dd2 = dd1
            u1, u2, l1, l2 = self.u1[:, None], self.u2[:, None], self.l1[:, None, None], self.l2[:, None, None]
            du1 = (dd1 - u1 * _dot(u1, dd1)[..., None]) / l1
            du2 = (dd2 - u2 * _dot(u2, dd2)[..., None]) / l2
            return du1 - du2, du1, du2
        return dd1[0], None, None

    def grad(self, V):
        """Corner vectors g (n, p, 3) with sum_b g_b . dx_b = w_r . V (w_r the frame spin); and the
        intermediate w_n, w_a, q1, q2 for the derivative."""
        w_n = cross(V, self.e3) / self.ln[..., None]
        w_a = _dot(V, self.e3)[..., None] * self.e2 / self.la[..., None]
        g1 = cross(self.d2, w_n)
        g2 = cross(w_n, self.d1)
        q1 = q2 = None
        if self.p == 4:
            q1 = (w_a - self.u1 * _dot(self.u1, w_a)[..., None]) / self.l1[..., None]
            q2 = (w_a - self.u2 * _dot(self.u2, w_a)[..., None]) / self.l2[..., None]
            g1, g2 = g1 + q1, g2 - q2
        else:
            g1 = g1 + w_a
        return _scatter(g1, g2, self.p), (w_n, w_a, q1, q2)


def corotational_setup(X: np.ndarray, C: np.ndarray, drill_factor: float = DRILL_FACTOR,
                       ids: np.ndarray | None = None, initial_stress: bool = False,
                       mass: np.ndarray | None = None, lumped=False, drill: np.ndarray | None = None,
                       stress_matrices: bool = True) -> CorotationalShells:
    """Constants of corotational quads (X (n, 4, 3)) or triangles (X (n, 3, 3)) [m] with sections
    C (n, 8, 8) (see shell_matrices): the linear local stiffness turned into the corotated frame.
    initial_stress: add the local energy 1/2 N(d) . (d^T K_sigma d) (the membrane resultants acting on
    the element's own deformational slopes; the frame's rigid rotation is not in d, so nothing is
    counted twice), which plate buckling within coarse meshes needs. mass (n, 3), lumped: the
    element masses (see shell_matrices), turned into E0 as the stiffness. drill: the drilling
    penalties (see shell_matrices); stress_matrices=False leaves KS out (it depends on the geometry
    alone: a change of the constants keeps it)."""
    X = np.ascontiguousarray(X, dtype=float)
    lin = shell_matrices(X, C, mass, lumped, drill_factor=drill_factor, ids=ids, local=True, drill=drill)
    fr = _Frame(X)
    E0 = fr.E
    Tr = np.einsum("nji,njk->nik", E0, lin.frames)  # kernel frame -> corotated frame (about e3)
    if np.any(np.abs(Tr[:, 2, 2] - 1.0) > 1e-8):
        raise ModelError("corotational shells: the kernel's element normal differs from the corotated "
                         "frame's (a degenerate element?); check the corner order")
    p = X.shape[1]
    Tb = np.zeros((len(X), 6 * p, 6 * p))
    for b in range(2 * p):
        Tb[:, 3 * b:3 * b + 3, 3 * b:3 * b + 3] = Tr
    K = Tb @ lin.K @ np.transpose(Tb, (0, 2, 1))
    M = None if lin.M is None else np.ascontiguousarray(Tb @ lin.M @ np.transpose(Tb, (0, 2, 1)))
    Xl = np.einsum("nji,npj->npi", E0, X - X.mean(axis=1, keepdims=True))
    if not initial_stress:
        return CorotationalShells(X, *(np.ascontiguousarray(a) for a in (E0, Xl, K)), M=M)
    TbT = np.transpose(Tb, (0, 2, 1))
    GN = np.einsum("nij,njk,nkl->nil", np.ascontiguousarray(C)[:, :3, :3], _mean_strain(lin.coords), TbT)
    if not stress_matrices:
        return CorotationalShells(X, *(np.ascontiguousarray(a) for a in (E0, Xl, K)), GN=np.ascontiguousarray(GN), M=M)
    Tg = np.zeros_like(Tb)
    for b in range(2 * p):
        Tg[:, 3 * b:3 * b + 3, 3 * b:3 * b + 3] = np.transpose(E0, (0, 2, 1))
    KS = np.empty((len(X), 3, 6 * p, 6 * p))
    for j in range(3):
        unit = np.zeros((len(X), 3))
        unit[:, j] = 1.0
        KS[:, j] = Tg @ shell_geometric(X, unit) @ np.transpose(Tg, (0, 2, 1))
    return CorotationalShells(X, *(np.ascontiguousarray(a) for a in (E0, Xl, K, GN, KS)), M=M)


def corotated_frames(x: np.ndarray) -> np.ndarray:
    """(n, 3, 3) corotated frames (columns e1, e2, e3) of elements with corners x (n, p, 3) [m]."""
    return _Frame(np.asarray(x, dtype=float)).E


def _mean_strain(coords):
    """(n, 3, 6p): the mean membrane strains [ex, ey, gxy] over the element, (1/A) int grad(u) dA =
    (1/A) sum over the sides of the mean side displacement times the outward normal (exact for
    fields linear along the sides), from the corner translations in the kernel frame."""
    xl = coords[..., :2]
    n, p = xl.shape[:2]
    nxt = np.roll(np.arange(p), -1)
    dx = xl[:, nxt, 0] - xl[:, :, 0]
    dy = xl[:, nxt, 1] - xl[:, :, 1]
    area = 0.5 * np.sum(xl[:, :, 0] * xl[:, nxt, 1] - xl[:, nxt, 0] * xl[:, :, 1], axis=1)
    # int du/dx, du/dy per corner: each side i -> i+1 gives half its (dy, -dx) to both of its corners
    gx = 0.5 * (dy + np.roll(dy, 1, axis=1)) / area[:, None]
    gy = -0.5 * (dx + np.roll(dx, 1, axis=1)) / area[:, None]
    B = np.zeros((n, 3, 6 * p))
    B[:, 0, 0::6] = gx
    B[:, 1, 1::6] = gy
    B[:, 2, 0::6] = gy
    B[:, 2, 1::6] = gx
    return B


def _local(data, d):
    """Local forces and local tangent (n, 6p), (n, 6p, 6p) at deformations d."""
    fl = np.einsum("nij,nj->ni", data.K, d)
    if data.KS is None:
        return fl, data.K
    N = np.einsum("nij,nj->ni", data.GN, d)
    Kd = np.einsum("njab,nb->nja", data.KS, d)  # K_j d
    q = np.einsum("na,nja->nj", d, Kd)  # d^T K_j d
    fl = fl + np.einsum("nj,nja->na", N, Kd) + 0.5 * np.einsum("nj,nja->na", q, data.GN)
    Kt = (data.K + np.einsum("nj,njab->nab", N, data.KS) + np.einsum("nja,njb->nab", Kd, data.GN)
          + np.einsum("nja,njb->nab", data.GN, Kd))
    return fl, Kt


def corotational_terms(data: CorotationalShells, x: np.ndarray, R: np.ndarray, tangent: bool = True,
                       R0: np.ndarray | None = None, reference: CorotationalTerms | None = None) -> CorotationalTerms:
    """Internal forces and (if tangent) the exact consistent tangent of the elements at corner
    positions x (n, p, 3) [m] and total node rotations R (n, p, 3, 3) (R0: the rotations at the
    reference state, default identity), in the solver's variables [dx, spatial spin] per corner.
    reference: the terms of another state whose local forces (and deformations, for the initial
    stress) the stress-dependent parts of the tangent use instead of the element's own (the beam's
    reference_forces); the forces stay this state's. The compiled kernel (_shell_cr_kernel);
    corotational_terms_numpy is the same in NumPy."""
    x = np.ascontiguousarray(x, dtype=float)
    R = np.asarray(R, dtype=float)
    _check(data, x, R)
    Rr = np.ascontiguousarray(R if R0 is None else R @ np.transpose(np.asarray(R0, dtype=float), (0, 1, 3, 2)))
    n, p = x.shape[:2]
    k = 6 * p
    forces = np.empty((n, k))
    K = np.empty((n, k, k)) if tangent else np.empty((0, k, k))
    frames = np.empty((n, 3, 3))
    d = np.empty((n, k))
    fl = np.empty((n, k))
    GN = data.GN if data.GN is not None else np.empty((0, 3, k))
    KS = data.KS if data.KS is not None else np.empty((0, 3, k, k))
    ref_fl, ref_d = _reference(reference, n, k, tangent)
    args = (data.Xl, data.E0, data.K, GN, KS, x, Rr, bool(tangent), ref_fl, ref_d, forces, K, frames, d, fl)
    if n < 2 * _CHUNK:
        cr_chunk(*args, 0, n)
    else:
        cr_kernel(*args, numba.get_num_threads())
    return CorotationalTerms(forces, K if tangent else None, frames, d, fl)


def _reference(reference, n, k, tangent):
    if reference is None or not tangent:
        return np.empty((0, k)), np.empty((0, k))
    if reference.f_local.shape != (n, k) or reference.d.shape != (n, k):
        raise ModelError(f"corotational shells: reference terms of shape {reference.f_local.shape} for {n} "
                         f"elements with {k} DOFs each; pass the terms of the same elements")
    return np.ascontiguousarray(reference.f_local, dtype=float), np.ascontiguousarray(reference.d, dtype=float)


def _check(data, x, R):
    if x.shape != data.X.shape or R.shape != x.shape + (3,):
        raise ModelError(f"corotational shells: positions {x.shape} and rotations {R.shape} for elements "
                         f"set up with corners {data.X.shape}; expected (n, p, 3) and (n, p, 3, 3)")


def corotational_terms_numpy(data: CorotationalShells, x: np.ndarray, R: np.ndarray, tangent: bool = True,
                             R0: np.ndarray | None = None,
                             reference: CorotationalTerms | None = None) -> CorotationalTerms:
    """corotational_terms in NumPy, vectorised over elements and directions: the readable reference
    of the compiled kernel (same results to round-off, about 20 times slower)."""
    x = np.asarray(x, dtype=float)
    R = np.asarray(R, dtype=float)
    n, p = x.shape[:2]
    _check(data, x, R)
    fr = _Frame(x)
    E = fr.E
    xc = x.mean(axis=1, keepdims=True)
    r = x - xc
    u = np.einsum("nji,npj->npi", E, r) - data.Xl
    Rr = R if R0 is None else R @ np.transpose(np.asarray(R0, dtype=float), (0, 1, 3, 2))
    Rd = np.einsum("nji,npjk,nkl->npil", E, Rr, data.E0)
    theta = logm_so3(Rd)
    H, c, e = jl_inv(theta)
    d = np.concatenate([u, theta], axis=-1).reshape(n, 6 * p)
    fl, Kt = _local(data, d)
    st = _stress(fr, r, H, fl)
    flu, flm, nm, N, M, V, g, (w_n, w_a, q1, q2) = st
    fx = N - N.mean(axis=1, keepdims=True) - g
    forces = np.concatenate([fx, M], axis=-1).reshape(n, 6 * p)
    K = None
    if tangent:
        ref_fl, ref_d = _reference(reference, n, 6 * p, tangent)
        if len(ref_fl):
            Kt = _local(data, ref_d)[1]
            flu, flm, nm, N, M, V, g, (w_n, w_a, q1, q2) = _stress(fr, r, H, ref_fl)
        K = _tangent(Kt, fr, r, theta, H, c, e, flu, flm, nm, N, M, V, w_n, w_a, q1, q2)
    return CorotationalTerms(forces, K, E, d, fl)


def _stress(fr, r, H, fl):
    """The global corner forces N and moments M of local forces fl, V and G^T V."""
    n, p = r.shape[:2]
    flu = fl.reshape(n, p, 6)[..., :3]
    flm = fl.reshape(n, p, 6)[..., 3:]
    nm = np.einsum("npji,npj->npi", H, flm)  # H^T f_l,m
    N = np.einsum("nij,npj->npi", fr.E, flu)
    M = np.einsum("nij,npj->npi", fr.E, nm)
    V = np.sum(cross(r, N), axis=1) + np.sum(M, axis=1)
    g, ws = fr.grad(V)
    return flu, flm, nm, N, M, V, g, ws


def _tangent(Kt, fr, r, theta, H, c, e, flu, flm, nm, N, M, V, w_n, w_a, q1, q2):
    """Forward derivative of the forces along the 6 p unit directions at once (axis 1 = direction)."""
    n, p = r.shape[:2]
    k = 6 * p
    eye = np.eye(k).reshape(k, p, 6)
    dx = np.broadcast_to(eye[None, :, :, :3], (n, k, p, 3))
    om = np.broadcast_to(eye[None, :, :, 3:], (n, k, p, 3))
    A = lambda a: a[:, None]  # noqa: E731 - base quantity against the direction axis
    e1, e2, e3 = A(fr.e1), A(fr.e2), A(fr.e3)
    ln, la = A(fr.ln)[..., None], A(fr.la)[..., None]
    dd1, dd2 = _diffs(dx)
    dn = cross(dd1, A(fr.d2)) + cross(A(fr.d1), dd2)
    da, du1, du2 = fr.da((dd1, dd2)) if p == 4 else fr.da((dd1,))
    wr = (_dot(e1, dn)[..., None] * e2 - _dot(e2, dn)[..., None] * e1) / ln + e3 * (_dot(e2, da)[..., None] / la)
    de1, de2, de3 = cross(wr, e1), cross(wr, e2), cross(wr, e3)
    dE = np.stack([de1, de2, de3], axis=-1)
    dln, dla = _dot(e3, dn)[..., None], _dot(e1, da)[..., None]
    dr = dx - dx.mean(axis=2, keepdims=True)
    E = fr.E
    # d(d) = H P T dp: the frame's rigid motion taken out (P), the spins mapped to rotation vectors (H)
    du = np.einsum("nkji,npj->nkpi", dE, r) + np.einsum("nji,nkpj->nkpi", E, dr)
    axial = np.einsum("nji,nkpj->nkpi", E, om - wr[:, :, None])
    dth = np.einsum("npij,nkpj->nkpi", H, axial)
    ddv = np.concatenate([du, dth], axis=-1).reshape(n, k, k)
    dfl = np.einsum("nij,nkj->nki", Kt, ddv).reshape(n, k, p, 6)  # material part (K_l H P T dp)
    dflu, dflm = dfl[..., :3], dfl[..., 3:]
    # moment correction (Felippa-Haugen's K_M): the change of H^T at fixed local moments
    dH = jl_inv_derivative_T(theta, c, e, np.transpose(dth, (0, 2, 1, 3)), flm)
    dnm = np.einsum("npji,nkpj->nkpi", H, dflm) + np.transpose(dH, (0, 2, 1, 3))
    # the local forces turning with the frame (K_GR), then the change of G^T V and of the lever arms (K_GP)
    dN = np.einsum("nkij,npj->nkpi", dE, flu) + np.einsum("nij,nkpj->nkpi", E, dflu)
    dM = np.einsum("nkij,npj->nkpi", dE, nm) + np.einsum("nij,nkpj->nkpi", E, dnm)
    dV = np.sum(cross(dr, A(N)) + cross(A(r), dN) + dM, axis=2)
    Wn, Wa = A(w_n), A(w_a)
    dwn = (cross(dV, e3) + cross(A(V), de3)) / ln - Wn * dln / ln
    Ve3 = A(_dot(V, fr.e3))[..., None]
    dVe3 = (_dot(dV, e3) + _dot(A(V), de3))[..., None]
    dwa = (dVe3 * e2 + Ve3 * de2) / la - Wa * dla / la
    dg1 = cross(dd2, Wn) + cross(A(fr.d2), dwn)
    dg2 = cross(dwn, A(fr.d1)) + cross(Wn, dd1)
    if p == 4:
        for sign, u_, du_, l_, q_, dd_ in ((1, fr.u1, du1, fr.l1, q1, dd1), (-1, fr.u2, du2, fr.l2, q2, dd2)):
            U, L, Q = A(u_), A(l_)[..., None], A(q_)
            dl = _dot(U, dd_)[..., None]
            dq = (dwa - du_ * _dot(U, Wa)[..., None] - U * (_dot(du_, Wa) + _dot(U, dwa))[..., None]) / L - Q * dl / L
            if sign > 0:
                dg1 = dg1 + dq
            else:
                dg2 = dg2 - dq
    else:
        dg1 = dg1 + dwa
    dg = _scatter(dg1, dg2, p)
    dfx = dN - dN.mean(axis=2, keepdims=True) - dg
    cols = np.concatenate([dfx, dM], axis=-1).reshape(n, k, k)
    return np.transpose(cols, (0, 2, 1))
