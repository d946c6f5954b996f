"""Compiled kernels of the linear flat shell elements, 6 DOF per node, all elements at once.

Local DOFs per node [u, v, w, theta_x, theta_y, theta_z] in the element frame (x, y in the plane,
z the normal); theta_z is the drilling rotation. Rotations are right-handed about the axes, so the
rotations of the normal are beta_x = theta_y, beta_y = -theta_x (u = u0 + z beta_x).

Quadrilateral (4 nodes):
  - membrane: Allman-type interpolation of the in-plane displacements (Ibrahimbegovic, Taylor &
    Wilson 1990: the serendipity field with the midside displacements made from the corner drilling
    rotations, u_mid = (u_i + u_j)/2 + l_ij/8 (w_j - w_i) n_ij) plus the Hughes-Brezzi penalty
    gamma int (skew(grad u) - theta_z)^2 dA that ties the drilling rotation to the in-plane rotation
    (gamma = the in-plane shear stiffness A33, as Ibrahimbegovic et al.); 2 x 2 Gauss;
  - bending: bilinear rotations (Mindlin), 2 x 2 Gauss; transverse shear: MITC4 (Bathe & Dvorkin
    1985), covariant shear strains tied at the edge midpoints;
  - a warped quad is projected on its mean plane (normal along the cross product of the diagonals)
    and the nodes joined to their projections by rigid links (Taylor's warping correction).
Triangle (3 nodes):
  - membrane: ANDES-OPT (Felippa 2003; Felippa & Militello 1992), basic stiffness with
    alpha_b = 3/2 plus the higher-order stiffness of natural strains on the hierarchical drilling
    rotations (signature beta1..9 = 1, 2, 1, 0, 1, -1, -1, -1, -2; beta0 = (1 - 4 nu^2)/2 on the
    scale that makes pure in-plane bending of a rectangular unit exact, tested): an Allman field
    with a Hughes-Brezzi penalty was tried first and gave 0.14 of the MacNeal-Harder in-plane
    shear (a spar web locks), ANDES-OPT 1.05;
  - bending and transverse shear: DKMT (Katili 1993, _shell_dkmt.py), the shear-deformable
    extension of DKT (Batoz, Bathe & Ho 1980) to which it reduces as t/L -> 0 and exactly for a
    section without shear stiffness; the membrane-bending coupling B acts on the basic (constant)
    membrane strain.
Sections enter as C (8, 8) = [[A, B, 0], [B^T, D, 0], [0, 0, S]] in element axes and mass (3,) =
[m0, m1, m2] per unit area (see _shell_section.py). Masses: consistent (the bilinear/linear shape
functions on u, v, w, beta; no drilling inertia) or lumped (int N_i dA per node).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ._shell_dkmt import dkmt_point, dkmt_sides

_FAST = dict(cache=True, fastmath={"contract", "reassoc", "arcp", "nsz"}, nogil=True, error_model="numpy")
_G = 0.5773502691896257  # 1/sqrt(3): the 2 x 2 Gauss points
_CHUNK = 128  # elements per thread below which a parallel region costs more than it saves

# status codes per element
OK = 0
BAD_JACOBIAN = 1  # det J <= 0 at a Gauss point (or a vanishing area): inverted, degenerate or too distorted


@njit(**_FAST)
def quad_frame(X, E, xl, h):
    """Frame E (3, 3) (columns x, y, z) of a quad with corners X (4, 3): z along the cross product of
    the diagonals, x along the side 1-2 projected on the mean plane. xl (4, 2) the corners' projected
    local coordinates about the centroid, h (4,) their distances from the mean plane [m]."""
    d1 = X[2] - X[0]
    d2 = X[3] - X[1]
    z0 = d1[1] * d2[2] - d1[2] * d2[1]
    z1 = d1[2] * d2[0] - d1[0] * d2[2]
    z2 = d1[0] * d2[1] - d1[1] * d2[0]
    nz = np.sqrt(z0 * z0 + z1 * z1 + z2 * z2)
    z0, z1, z2 = z0 / nz, z1 / nz, z2 / nz
    a0, a1, a2 = X[1, 0] - X[0, 0], X[1, 1] - X[0, 1], X[1, 2] - X[0, 2]
    p = a0 * z0 + a1 * z1 + a2 * z2
    a0, a1, a2 = a0 - p * z0, a1 - p * z1, a2 - p * z2
    na = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    a0, a1, a2 = a0 / na, a1 / na, a2 / na
    E[0, 0], E[1, 0], E[2, 0] = a0, a1, a2
    E[0, 1], E[1, 1], E[2, 1] = z1 * a2 - z2 * a1, z2 * a0 - z0 * a2, z0 * a1 - z1 * a0
    E[0, 2], E[1, 2], E[2, 2] = z0, z1, z2
    c0 = 0.25 * (X[0, 0] + X[1, 0] + X[2, 0] + X[3, 0])
    c1 = 0.25 * (X[0, 1] + X[1, 1] + X[2, 1] + X[3, 1])
    c2 = 0.25 * (X[0, 2] + X[1, 2] + X[2, 2] + X[3, 2])
    for i in range(4):
        r0, r1, r2 = X[i, 0] - c0, X[i, 1] - c1, X[i, 2] - c2
        xl[i, 0] = r0 * E[0, 0] + r1 * E[1, 0] + r2 * E[2, 0]
        xl[i, 1] = r0 * E[0, 1] + r1 * E[1, 1] + r2 * E[2, 1]
        h[i] = r0 * z0 + r1 * z1 + r2 * z2


@njit(**_FAST)
def tri_frame(X, E, xl):
    """Frame E (3, 3) of a triangle X (3, 3): x along side 1-2, z the normal; xl (3, 2) local
    coordinates about the centroid."""
    a0, a1, a2 = X[1, 0] - X[0, 0], X[1, 1] - X[0, 1], X[1, 2] - X[0, 2]
    b0, b1, b2 = X[2, 0] - X[0, 0], X[2, 1] - X[0, 1], X[2, 2] - X[0, 2]
    z0, z1, z2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
    nz = np.sqrt(z0 * z0 + z1 * z1 + z2 * z2)
    z0, z1, z2 = z0 / nz, z1 / nz, z2 / nz
    na = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    a0, a1, a2 = a0 / na, a1 / na, a2 / na
    E[0, 0], E[1, 0], E[2, 0] = a0, a1, a2
    E[0, 1], E[1, 1], E[2, 1] = z1 * a2 - z2 * a1, z2 * a0 - z0 * a2, z0 * a1 - z1 * a0
    E[0, 2], E[1, 2], E[2, 2] = z0, z1, z2
    c0 = (X[0, 0] + X[1, 0] + X[2, 0]) / 3
    c1 = (X[0, 1] + X[1, 1] + X[2, 1]) / 3
    c2 = (X[0, 2] + X[1, 2] + X[2, 2]) / 3
    for i in range(3):
        r0, r1, r2 = X[i, 0] - c0, X[i, 1] - c1, X[i, 2] - c2
        xl[i, 0] = r0 * E[0, 0] + r1 * E[1, 0] + r2 * E[2, 0]
        xl[i, 1] = r0 * E[0, 1] + r1 * E[1, 1] + r2 * E[2, 1]


@njit(**_FAST)
def _add_btcb(K, Bm, C, w, CB, nd):
    """K[:nd, :nd] += w B^T C B for B (8, nd) (rows: membrane 3, bending 3, shear 2)."""
    for a in range(8):
        for j in range(nd):
            acc = 0.0
            for b in range(8):
                acc += C[a, b] * Bm[b, j]
            CB[a, j] = acc * w
    for i in range(nd):
        for j in range(i, nd):
            acc = 0.0
            for a in range(8):
                acc += Bm[a, i] * CB[a, j]
            K[i, j] += acc
            if j != i:
                K[j, i] += acc


@njit(**_FAST)
def _add_quad_point(K, Mr, Br, Sr, bp, C, w, gam, coupled, nA, nB, mD, qS):
    """K += w [B^T C B + gam bp bp^T] at one Gauss point, block by block on the non-zero columns:
    Mr (3, 12) membrane strains over [u, v, theta_z] x 4, Br (3, 8) curvatures over
    [theta_x, theta_y] x 4, Sr (2, 12) shear strains over [w, theta_x, theta_y] x 4, bp (12,) the
    drilling penalty row over the membrane columns."""
    for i in range(12):
        for r in range(3):
            nA[r, i] = w * (C[r, 0] * Mr[0, i] + C[r, 1] * Mr[1, i] + C[r, 2] * Mr[2, i])
            if coupled:
                nB[r, i] = w * (C[0, 3 + r] * Mr[0, i] + C[1, 3 + r] * Mr[1, i] + C[2, 3 + r] * Mr[2, i])
        for r in range(2):
            qS[r, i] = w * (C[6 + r, 6] * Sr[0, i] + C[6 + r, 7] * Sr[1, i])
    for j in range(8):
        for r in range(3):
            mD[r, j] = w * (C[3 + r, 3] * Br[0, j] + C[3 + r, 4] * Br[1, j] + C[3 + r, 5] * Br[2, j])
    gw = gam * w
    for i in range(12):
        gi = 6 * (i // 3) + (i % 3 if i % 3 < 2 else 5)
        for k in range(12):
            gk = 6 * (k // 3) + (k % 3 if k % 3 < 2 else 5)
            K[gi, gk] += Mr[0, i] * nA[0, k] + Mr[1, i] * nA[1, k] + Mr[2, i] * nA[2, k] + gw * bp[i] * bp[k]
        if coupled:
            for j in range(8):
                gj = 6 * (j // 2) + 3 + j % 2
                acc = nB[0, i] * Br[0, j] + nB[1, i] * Br[1, j] + nB[2, i] * Br[2, j]
                K[gi, gj] += acc
                K[gj, gi] += acc
    for j in range(8):
        gj = 6 * (j // 2) + 3 + j % 2
        for k in range(8):
            gk = 6 * (k // 2) + 3 + k % 2
            K[gj, gk] += Br[0, j] * mD[0, k] + Br[1, j] * mD[1, k] + Br[2, j] * mD[2, k]
    for i in range(12):
        gi = 6 * (i // 3) + 2 + i % 3
        for k in range(12):
            gk = 6 * (k // 3) + 2 + k % 3
            K[gi, gk] += Sr[0, i] * qS[0, k] + Sr[1, i] * qS[1, k]


@njit(**_FAST)
def quad_local_stiffness(xl, C, drill, K, work, tie):
    """Local stiffness K (24, 24) (overwritten) of a flat quad at local corners xl (4, 2).
    Work arrays: work (23, 12), tie (4, 12). Returns the smallest det J."""
    for i in range(24):
        for j in range(24):
            K[i, j] = 0.0
    coupled = False
    for r in range(3):
        for c in range(3):
            if C[r, 3 + c] != 0.0:
                coupled = True
    # MITC4 tying strains: covariant transverse shear at the edge midpoints as rows over
    # [w, theta_x, theta_y] x 4. Edge a -> b along increasing natural coordinate: g = (w_b - w_a)/2
    # + dx/4 (bx_a + bx_b) + dy/4 (by_a + by_b), beta_x = theta_y, beta_y = -theta_x.
    for t in range(4):
        if t == 0:
            a, b = 0, 1  # g_xi at eta = -1
        elif t == 1:
            a, b = 3, 2  # g_xi at eta = +1
        elif t == 2:
            a, b = 1, 2  # g_eta at xi = +1
        else:
            a, b = 0, 3  # g_eta at xi = -1
        for j in range(12):
            tie[t, j] = 0.0
        dx = xl[b, 0] - xl[a, 0]
        dy = xl[b, 1] - xl[a, 1]
        tie[t, 3 * b] = 0.5
        tie[t, 3 * a] = -0.5
        tie[t, 3 * a + 2] = 0.25 * dx
        tie[t, 3 * b + 2] = 0.25 * dx
        tie[t, 3 * a + 1] = -0.25 * dy
        tie[t, 3 * b + 1] = -0.25 * dy
    nA = work[0:3]
    nB = work[3:6]
    qS = work[6:8]
    mD = work[8:11, :8]
    Mr = work[11:14]
    Br = work[14:17, :8]
    Sr = work[17:19]
    bp = work[19]
    ex, ey = work[20, 0:4], work[20, 4:8]
    dNx, dNy, N = work[21, 0:4], work[21, 4:8], work[21, 8:12]
    Px, Py = work[22, 0:4], work[22, 4:8]
    for r in range(11, 17):
        for j in range(12):
            work[r, j] = 0.0
    for k in range(4):
        k1 = (k + 1) % 4
        ex[k] = xl[k1, 0] - xl[k, 0]
        ey[k] = xl[k1, 1] - xl[k, 1]
    detmin = 1e300
    for gp in range(4):
        xi = -_G if gp == 0 or gp == 3 else _G
        eta = -_G if gp < 2 else _G
        dxi0, dxi1, dxi2, dxi3 = -0.25 * (1 - eta), 0.25 * (1 - eta), 0.25 * (1 + eta), -0.25 * (1 + eta)
        det0, det1, det2, det3 = -0.25 * (1 - xi), -0.25 * (1 + xi), 0.25 * (1 + xi), 0.25 * (1 - xi)
        N[0] = 0.25 * (1 - xi) * (1 - eta)
        N[1] = 0.25 * (1 + xi) * (1 - eta)
        N[2] = 0.25 * (1 + xi) * (1 + eta)
        N[3] = 0.25 * (1 - xi) * (1 + eta)
        J00 = dxi0 * xl[0, 0] + dxi1 * xl[1, 0] + dxi2 * xl[2, 0] + dxi3 * xl[3, 0]
        J01 = dxi0 * xl[0, 1] + dxi1 * xl[1, 1] + dxi2 * xl[2, 1] + dxi3 * xl[3, 1]
        J10 = det0 * xl[0, 0] + det1 * xl[1, 0] + det2 * xl[2, 0] + det3 * xl[3, 0]
        J11 = det0 * xl[0, 1] + det1 * xl[1, 1] + det2 * xl[2, 1] + det3 * xl[3, 1]
        dj = J00 * J11 - J01 * J10
        detmin = min(detmin, dj)
        i00, i01, i10, i11 = J11 / dj, -J01 / dj, -J10 / dj, J00 / dj
        for i in range(4):
            dn_xi = dxi0 if i == 0 else (dxi1 if i == 1 else (dxi2 if i == 2 else dxi3))
            dn_eta = det0 if i == 0 else (det1 if i == 1 else (det2 if i == 2 else det3))
            dNx[i] = i00 * dn_xi + i01 * dn_eta
            dNy[i] = i10 * dn_xi + i11 * dn_eta
        # serendipity midside functions of edges 1-2, 2-3, 3-4, 4-1 and their x, y derivatives
        for k in range(4):
            if k == 0:
                pxi, peta = -xi * (1 - eta), -0.5 * (1 - xi * xi)
            elif k == 1:
                pxi, peta = 0.5 * (1 - eta * eta), -(1 + xi) * eta
            elif k == 2:
                pxi, peta = -xi * (1 + eta), 0.5 * (1 - xi * xi)
            else:
                pxi, peta = -0.5 * (1 - eta * eta), -(1 - xi) * eta
            Px[k] = i00 * pxi + i01 * peta
            Py[k] = i10 * pxi + i11 * peta
        for i in range(4):
            km = (i + 3) % 4
            # Allman field of the drilling rotation of node i: u = (-ey_i P_i + ey_km P_km)/8,
            # v = (ex_i P_i - ex_km P_km)/8
            uwx = (-ey[i] * Px[i] + ey[km] * Px[km]) * 0.125
            uwy = (-ey[i] * Py[i] + ey[km] * Py[km]) * 0.125
            vwx = (ex[i] * Px[i] - ex[km] * Px[km]) * 0.125
            vwy = (ex[i] * Py[i] - ex[km] * Py[km]) * 0.125
            m = 3 * i
            Mr[0, m], Mr[0, m + 2] = dNx[i], uwx
            Mr[1, m + 1], Mr[1, m + 2] = dNy[i], vwy
            Mr[2, m], Mr[2, m + 1], Mr[2, m + 2] = dNy[i], dNx[i], uwy + vwx
            bp[m], bp[m + 1], bp[m + 2] = -0.5 * dNy[i], 0.5 * dNx[i], 0.5 * (vwx - uwy) - N[i]
            b = 2 * i  # [theta_x, theta_y]: kx = dty/dx, ky = -dtx/dy, kxy = dty/dy - dtx/dx
            Br[0, b + 1] = dNx[i]
            Br[1, b] = -dNy[i]
            Br[2, b], Br[2, b + 1] = -dNx[i], dNy[i]
        # MITC4 shear: covariant strains interpolated from the tying points, then Cartesian
        for j in range(12):
            gx = 0.5 * (1 - eta) * tie[0, j] + 0.5 * (1 + eta) * tie[1, j]
            ge = 0.5 * (1 + xi) * tie[2, j] + 0.5 * (1 - xi) * tie[3, j]
            Sr[0, j] = i00 * gx + i01 * ge
            Sr[1, j] = i10 * gx + i11 * ge
        _add_quad_point(K, Mr, Br, Sr, bp, C, dj, drill, coupled, nA, nB, mD, qS)
    return detmin


@njit(**_FAST)
def quad_local_mass(xl, mass, lumped, M):
    """Local mass M (24, 24) (overwritten): consistent (bilinear shape functions) or lumped."""
    for i in range(24):
        for j in range(24):
            M[i, j] = 0.0
    m0, m1, m2 = mass[0], mass[1], mass[2]
    N = np.empty(4)
    for gp in range(4):
        xi = -_G if gp == 0 or gp == 3 else _G
        eta = -_G if gp < 2 else _G
        N[0] = 0.25 * (1 - xi) * (1 - eta)
        N[1] = 0.25 * (1 + xi) * (1 - eta)
        N[2] = 0.25 * (1 + xi) * (1 + eta)
        N[3] = 0.25 * (1 - xi) * (1 + eta)
        J00 = 0.25 * ((1 - eta) * (xl[1, 0] - xl[0, 0]) + (1 + eta) * (xl[2, 0] - xl[3, 0]))
        J01 = 0.25 * ((1 - eta) * (xl[1, 1] - xl[0, 1]) + (1 + eta) * (xl[2, 1] - xl[3, 1]))
        J10 = 0.25 * ((1 - xi) * (xl[3, 0] - xl[0, 0]) + (1 + xi) * (xl[2, 0] - xl[1, 0]))
        J11 = 0.25 * ((1 - xi) * (xl[3, 1] - xl[0, 1]) + (1 + xi) * (xl[2, 1] - xl[1, 1]))
        dA = J00 * J11 - J01 * J10
        _add_mass(M, N, 4, dA, m0, m1, m2, lumped)


@njit(**_FAST)
def _add_mass(M, N, nn, dA, m0, m1, m2, lumped):
    """Adds int N_i N_j (consistent) or int N_i on the diagonal (lumped) times the section's mass
    terms: m0 on u, v, w; m2 on beta_x = theta_y, beta_y = -theta_x; m1 coupling u-beta_x, v-beta_y."""
    for i in range(nn):
        for j in range(nn):
            if lumped:
                if i != j:
                    continue
                s = N[i] * dA
            else:
                s = N[i] * N[j] * dA
            a, b = 6 * i, 6 * j
            M[a, b] += m0 * s
            M[a + 1, b + 1] += m0 * s
            M[a + 2, b + 2] += m0 * s
            M[a + 3, b + 3] += m2 * s
            M[a + 4, b + 4] += m2 * s
            M[a, b + 4] += m1 * s
            M[b + 4, a] += m1 * s
            M[a + 1, b + 3] -= m1 * s
            M[b + 3, a + 1] -= m1 * s


@njit(**_FAST)
def warp_links(K, h, nn):
    """K <- W^T K W for the rigid links from the nodes to their projections on the mean plane:
    u_flat = u - h theta_y, v_flat = v + h theta_x (h the node's height above the plane)."""
    n = 6 * nn
    for i in range(nn):
        if h[i] == 0.0:
            continue
        for r in range(n):  # columns: K W
            K[r, 6 * i + 4] -= h[i] * K[r, 6 * i]
            K[r, 6 * i + 3] += h[i] * K[r, 6 * i + 1]
    for i in range(nn):
        if h[i] == 0.0:
            continue
        for c in range(n):  # rows: W^T (K W)
            K[6 * i + 4, c] -= h[i] * K[6 * i, c]
            K[6 * i + 3, c] += h[i] * K[6 * i + 1, c]


@njit(**_FAST)
def to_global(E, Kl, Kg, nn, tmp):
    """Kg = T^T Kl T with T = diag(E^T, ...) over the 2 nn three-component blocks."""
    nb = 2 * nn
    for bi in range(nb):
        for bj in range(nb):
            r0, c0 = 3 * bi, 3 * bj
            for i in range(3):
                for j in range(3):
                    tmp[i, j] = Kl[r0 + i, c0] * E[j, 0] + Kl[r0 + i, c0 + 1] * E[j, 1] + Kl[r0 + i, c0 + 2] * E[j, 2]
            for i in range(3):
                for j in range(3):
                    Kg[r0 + i, c0 + j] = E[i, 0] * tmp[0, j] + E[i, 1] * tmp[1, j] + E[i, 2] * tmp[2, j]


_DEGENERATE = 1e-10  # det J (quad) or area (triangle) below this times the squared side: degenerate


@njit(**_FAST)
def _size2(xl, nn):
    """Sum of the squared side lengths of the element with local corners xl (nn, 2)."""
    acc = 0.0
    for i in range(nn):
        j = (i + 1) % nn
        acc += (xl[j, 0] - xl[i, 0]) ** 2 + (xl[j, 1] - xl[i, 1]) ** 2
    return acc


@njit(**_FAST)
def _store(E, Kl, out, nn, tmp, local):
    """out = Kl (local axes) or its rotation to global axes."""
    if local:
        for i in range(6 * nn):
            for j in range(6 * nn):
                out[i, j] = Kl[i, j]
    else:
        to_global(E, Kl, out, nn, tmp)


@njit(**_FAST)
def _quad_chunk(X, C, mass, drill, lumped, want_mass, local, K_out, M_out, frames, coords, status, start,
                stop):
    Xe = np.empty((4, 3))
    E = np.empty((3, 3))
    xl = np.empty((4, 2))
    h = np.empty(4)
    Kl = np.empty((24, 24))
    work = np.empty((23, 12))
    tie = np.empty((4, 12))
    tmp = np.empty((3, 3))
    for el in range(start, stop):
        for i in range(4):
            for j in range(3):
                Xe[i, j] = X[el, i, j]
        quad_frame(Xe, E, xl, h)
        for i in range(3):
            for j in range(3):
                frames[el, i, j] = E[i, j]
        for i in range(4):
            coords[el, i, 0], coords[el, i, 1], coords[el, i, 2] = xl[i, 0], xl[i, 1], h[i]
        dmin = quad_local_stiffness(xl, C[el], drill[el], Kl, work, tie)
        status[el] = OK if dmin > _DEGENERATE * _size2(xl, 4) else BAD_JACOBIAN
        warp_links(Kl, h, 4)
        _store(E, Kl, K_out[el], 4, tmp, local)
        if want_mass:
            quad_local_mass(xl, mass[el], lumped[el], Kl)
            warp_links(Kl, h, 4)
            _store(E, Kl, M_out[el], 4, tmp, local)


@njit(cache=True, nogil=True, parallel=True)
def quad_kernel(X, C, mass, drill, lumped, want_mass, local, K_out, M_out, frames, coords, status, threads):
    """Stiffness K_out (n, 24, 24) and mass M_out of n quads with corners X (n, 4, 3), in global axes or
    (local) in the element frames; frames (n, 3, 3) and coords (n, 4, 3) = projected local x, y and
    the warp height of each corner."""
    n = X.shape[0]
    chunks = min(max(n // _CHUNK, 1), threads)
    for c in prange(chunks):
        _quad_chunk(X, C, mass, drill, lumped, want_mass, local, K_out, M_out, frames, coords, status,
                    c * n // chunks, (c + 1) * n // chunks)


# ------------------------------------------------------------------------------------------ triangle
# 3-point rule (interior points) on the triangle, exact for quadratics: area coordinates, weight 1/3
_TRI_L = np.array([[2.0 / 3, 1.0 / 6, 1.0 / 6], [1.0 / 6, 2.0 / 3, 1.0 / 6], [1.0 / 6, 1.0 / 6, 2.0 / 3]])


@njit(**_FAST)
def _dkt_coefficients(xl, Cx, Cy, abcde):
    """Hx = Cx N, Hy = Cy N (9 x 6): the DKT rotations beta_x, beta_y as combinations of the six
    quadratic functions N (corners 1-3, midsides 4 = 2-3, 5 = 3-1, 6 = 1-2) over the DOFs
    [w, theta_x, theta_y] x 3 (Batoz, Bathe & Ho 1980); abcde (5, 3) work."""
    a, b, c, d, e = abcde[0], abcde[1], abcde[2], abcde[3], abcde[4]
    for m in range(3):  # midside 4 + m: edge (i, j) = (2, 3), (3, 1), (1, 2)
        i, j = (1, 2) if m == 0 else ((2, 0) if m == 1 else (0, 1))
        x = xl[i, 0] - xl[j, 0]
        y = xl[i, 1] - xl[j, 1]
        l2 = x * x + y * y
        a[m] = -x / l2
        b[m] = 0.75 * x * y / l2
        c[m] = (0.25 * x * x - 0.5 * y * y) / l2
        d[m] = -y / l2
        e[m] = (0.25 * y * y - 0.5 * x * x) / l2
    for r in range(9):
        for s in range(6):
            Cx[r, s] = 0.0
            Cy[r, s] = 0.0
    # node k (0, 1, 2) with its corner function k, and the midsides (p, q) that touch it:
    # node 1: midsides 6 (index 5) and 5 (index 4); node 2: 4 and 6; node 3: 5 and 4.
    for k in range(3):
        if k == 0:
            p, q = 5, 4  # Hx1 = 1.5 (a6 N6 - a5 N5)
        elif k == 1:
            p, q = 3, 5  # Hx4 = 1.5 (a4 N4 - a6 N6)
        else:
            p, q = 4, 3  # Hx7 = 1.5 (a5 N5 - a4 N4)
        mp, mq = p - 3, q - 3
        r = 3 * k
        Cx[r, p] = 1.5 * a[mp]
        Cx[r, q] = -1.5 * a[mq]
        Cx[r + 1, p] = b[mp]
        Cx[r + 1, q] = b[mq]
        Cx[r + 2, k] = 1.0
        Cx[r + 2, p] = -c[mp]
        Cx[r + 2, q] = -c[mq]
        Cy[r, p] = 1.5 * d[mp]
        Cy[r, q] = -1.5 * d[mq]
        Cy[r + 1, k] = -1.0
        Cy[r + 1, p] = e[mp]
        Cy[r + 1, q] = e[mq]
        Cy[r + 2, p] = -b[mp]
        Cy[r + 2, q] = -b[mq]



# ANDES optimal membrane (Felippa 2003): alpha_b of the basic stiffness and the signature beta1..beta9
_ALPHA_B = 1.5
_BETA = np.array([1.0, 2.0, 1.0, 0.0, 1.0, -1.0, -1.0, -1.0, -2.0])


@njit(**_FAST)
def andes_membrane(xl, Am, Bc, Kh, work):
    """ANDES-OPT membrane triangle with drilling rotations (Felippa, CMAME 192, 2003), over the nine
    DOFs [u, v, theta_z] x 3: Bc (3, 9) the basic constant strain (the basic stiffness is
    A Bc^T Am Bc, alpha_b = 3/2), Kh (9, 9) (overwritten) the higher-order stiffness from the
    natural strains at the midpoints with beta0 = (1 - 4 nu^2)/2 (nu = Am12 / sqrt(Am11 Am22),
    at least 0.01). Am (3, 3) membrane stiffness per length [N/m]; work (9, 9). Returns the area."""
    x1, y1 = xl[0, 0], xl[0, 1]
    x2, y2 = xl[1, 0], xl[1, 1]
    x3, y3 = xl[2, 0], xl[2, 1]
    x12, x21, x13, x31, x23, x32 = x1 - x2, x2 - x1, x1 - x3, x3 - x1, x2 - x3, x3 - x2
    y12, y21, y13, y31, y23, y32 = y1 - y2, y2 - y1, y1 - y3, y3 - y1, y2 - y3, y3 - y2
    A = 0.5 * (x21 * y31 - x31 * y21)
    if A <= 0.0:
        return A
    a = _ALPHA_B
    # L^T / A (L: Felippa's lumping matrix per unit thickness, rows the nine DOFs)
    f = 0.5 / A
    Bc[0, 0], Bc[1, 0], Bc[2, 0] = f * y23, 0.0, f * x32
    Bc[0, 1], Bc[1, 1], Bc[2, 1] = 0.0, f * x32, f * y23
    Bc[0, 2] = f * a / 6 * y23 * (y13 - y21)
    Bc[1, 2] = f * a / 6 * x32 * (x31 - x12)
    Bc[2, 2] = f * a / 3 * (x31 * y13 - x12 * y21)
    Bc[0, 3], Bc[1, 3], Bc[2, 3] = f * y31, 0.0, f * x13
    Bc[0, 4], Bc[1, 4], Bc[2, 4] = 0.0, f * x13, f * y31
    Bc[0, 5] = f * a / 6 * y31 * (y21 - y32)
    Bc[1, 5] = f * a / 6 * x13 * (x12 - x23)
    Bc[2, 5] = f * a / 3 * (x12 * y21 - x23 * y32)
    Bc[0, 6], Bc[1, 6], Bc[2, 6] = f * y12, 0.0, f * x21
    Bc[0, 7], Bc[1, 7], Bc[2, 7] = 0.0, f * x21, f * y12
    Bc[0, 8] = f * a / 6 * y12 * (y32 - y13)
    Bc[1, 8] = f * a / 6 * x21 * (x23 - x31)
    Bc[2, 8] = f * a / 3 * (x23 * y32 - x31 * y13)
    l21 = x21 * x21 + y21 * y21
    l32 = x32 * x32 + y32 * y32
    l13 = x13 * x13 + y13 * y13
    # Cartesian strains from the natural (side) strains: eps = Te eps_nat
    Te = work[0:3, 0:3]
    En = work[0:3, 3:6]
    Kt = work[0:3, 6:9]
    Qm = work[3:6, 0:3]
    T = work[6:9, :]
    g = 1.0 / (4 * A * A)
    Te[0, 0], Te[0, 1], Te[0, 2] = g * y23 * y13 * l21, g * y31 * y21 * l32, g * y12 * y32 * l13
    Te[1, 0], Te[1, 1], Te[1, 2] = g * x23 * x13 * l21, g * x31 * x21 * l32, g * x12 * x32 * l13
    Te[2, 0] = g * (y23 * x31 + x32 * y13) * l21
    Te[2, 1] = g * (y31 * x12 + x13 * y21) * l32
    Te[2, 2] = g * (y12 * x23 + x21 * y32) * l13
    for i in range(3):  # En = Te^T Am Te
        for j in range(3):
            acc = 0.0
            for k in range(3):
                for m in range(3):
                    acc += Te[k, i] * Am[k, m] * Te[m, j]
            En[i, j] = acc
    b = _BETA
    c = 2 * A / 3
    # natural strains at the corners from the hierarchical rotations: Q_n[r, col] = c beta[idx] / l_r^2
    idx = ((0, 1, 2, 3, 4, 5, 6, 7, 8), (8, 6, 7, 2, 0, 1, 5, 3, 4), (4, 5, 3, 7, 8, 6, 1, 2, 0))
    for i in range(3):
        for j in range(3):
            Kt[i, j] = 0.0
    for m in range(3):  # midpoints 4, 5, 6 = (1, 2), (2, 3), (3, 1): Q_m = (Q_n1 + Q_n2) / 2
        n1, n2 = m, (m + 1) % 3
        for r in range(3):
            lr = l21 if r == 0 else (l32 if r == 1 else l13)
            for col in range(3):
                Qm[r, col] = 0.5 * c * (b[idx[n1][3 * r + col]] + b[idx[n2][3 * r + col]]) / lr
        for i in range(3):
            for j in range(3):
                acc = 0.0
                for k in range(3):
                    for l_ in range(3):
                        acc += Qm[k, i] * En[k, l_] * Qm[l_, j]
                Kt[i, j] += acc * A / 3
    nu = Am[0, 1] / np.sqrt(Am[0, 0] * Am[1, 1]) if Am[0, 0] > 0 and Am[1, 1] > 0 else 0.0
    beta0 = max(0.5 * (1 - 4 * nu * nu), 0.01)
    # hierarchical rotations theta_i - theta_0 (theta_0 the rotation of the linear field)
    h = 0.25 / A
    for i in range(3):
        for j in range(9):
            T[i, j] = 0.0
        T[i, 0], T[i, 1] = h * x32, h * y32
        T[i, 3], T[i, 4] = h * x13, h * y13
        T[i, 6], T[i, 7] = h * x21, h * y21
        T[i, 3 * i + 2] = 1.0
    for i in range(9):
        for j in range(9):
            acc = 0.0
            for k in range(3):
                for m in range(3):
                    acc += T[k, i] * Kt[k, m] * T[m, j]
            # 9/4: with Q normalised as here, the scale at which beta0 = (1 - 4 nu^2)/2 makes
            # pure bending of a rectangular unit exact (test_andes_membrane_is_optimal_in_pure_bending)
            Kh[i, j] = 2.25 * beta0 * acc
    return A


@njit(**_FAST)
def tri_local_stiffness(xl, C, K, Bm, CB, al, side, Bc, Kh, work):
    """Local stiffness K (18, 18) (overwritten) of a flat triangle at local corners xl (3, 2): ANDES-OPT
    membrane, DKMT bending and transverse shear (DKT where the section has no shear stiffness), the
    membrane-bending coupling on the basic (constant) membrane strain. Work arrays Bm, CB (8, 18),
    al (3, 9), side (4, 3), Bc (3, 9), Kh (9, 9), work (9, 9). Returns the signed area."""
    for i in range(18):
        for j in range(18):
            K[i, j] = 0.0
    Am = C[:3, :3]
    area = andes_membrane(xl, Am, Bc, Kh, work)
    if area <= 0.0:
        return area
    geo, gl, lam = side[0:3], side[3], work[0, 0:3]
    dkmt_sides(xl, C, al, gl, geo, work[1:4, 0:3], work[4:7, 0:3])
    w = area / 3.0
    for a in range(8):
        for j in range(18):
            Bm[a, j] = 0.0
    for i in range(3):  # the basic membrane strain, constant over the element
        for r in range(3):
            Bm[r, 6 * i] = Bc[r, 3 * i]
            Bm[r, 6 * i + 1] = Bc[r, 3 * i + 1]
            Bm[r, 6 * i + 5] = Bc[r, 3 * i + 2]
    for gp in range(3):  # curvatures and shear strains are linear: the 3-point rule is exact
        for i in range(3):
            lam[i] = _TRI_L[gp, i]
        dkmt_point(xl, lam, al, gl, geo, Bm)
        _add_btcb(K, Bm, C, w, CB, 18)
    for i in range(9):
        gi = 6 * (i // 3) + (i % 3 if i % 3 < 2 else 5)
        for j in range(9):
            gj = 6 * (j // 3) + (j % 3 if j % 3 < 2 else 5)
            K[gi, gj] += Kh[i, j]
    return area


@njit(**_FAST)
def tri_local_mass(xl, mass, lumped, M):
    """Local mass M (18, 18) (overwritten): consistent (linear shape functions) or lumped (A/3)."""
    for i in range(18):
        for j in range(18):
            M[i, j] = 0.0
    A2 = (xl[1, 0] - xl[0, 0]) * (xl[2, 1] - xl[0, 1]) - (xl[2, 0] - xl[0, 0]) * (xl[1, 1] - xl[0, 1])
    N = np.empty(3)
    for gp in range(3):
        for i in range(3):
            N[i] = _TRI_L[gp, i]
        _add_mass(M, N, 3, A2 / 6.0, mass[0], mass[1], mass[2], lumped)


@njit(**_FAST)
def _tri_chunk(X, C, mass, drill, lumped, want_mass, local, K_out, M_out, frames, coords, status, start,
               stop):
    Xe = np.empty((3, 3))
    E = np.empty((3, 3))
    xl = np.empty((3, 2))
    Kl = np.empty((18, 18))
    Bm = np.empty((8, 18))
    CB = np.empty((8, 18))
    al = np.empty((3, 9))
    side = np.empty((4, 3))
    Bc = np.empty((3, 9))
    Kh = np.empty((9, 9))
    work = np.empty((9, 9))
    tmp = np.empty((3, 3))
    for el in range(start, stop):
        for i in range(3):
            for j in range(3):
                Xe[i, j] = X[el, i, j]
        tri_frame(Xe, E, xl)
        for i in range(3):
            for j in range(3):
                frames[el, i, j] = E[i, j]
        for i in range(3):
            coords[el, i, 0], coords[el, i, 1], coords[el, i, 2] = xl[i, 0], xl[i, 1], 0.0
        a2 = tri_local_stiffness(xl, C[el], Kl, Bm, CB, al, side, Bc, Kh, work)
        status[el] = OK if a2 > _DEGENERATE * _size2(xl, 3) else BAD_JACOBIAN
        _store(E, Kl, K_out[el], 3, tmp, local)
        if want_mass:
            tri_local_mass(xl, mass[el], lumped[el], Kl)
            _store(E, Kl, M_out[el], 3, tmp, local)


@njit(cache=True, nogil=True, parallel=True)
def tri_kernel(X, C, mass, drill, lumped, want_mass, local, K_out, M_out, frames, coords, status, threads):
    """Global stiffness K_out (n, 18, 18) and mass M_out of n triangles with corners X (n, 3, 3)."""
    n = X.shape[0]
    chunks = min(max(n // _CHUNK, 1), threads)
    for c in prange(chunks):
        _tri_chunk(X, C, mass, drill, lumped, want_mass, local, K_out, M_out, frames, coords, status,
                   c * n // chunks, (c + 1) * n // chunks)


# ------------------------------------------------------------------------------- initial stress
# 6-point rule on the triangle, exact for quartics (Dunavant 1985): xi, eta, weight (sum 1)
_TRI6 = np.array([[0.445948490915965, 0.445948490915965, 0.223381589678011],
                  [0.445948490915965, 0.108103018168070, 0.223381589678011],
                  [0.108103018168070, 0.445948490915965, 0.223381589678011],
                  [0.091576213509771, 0.091576213509771, 0.109951743655322],
                  [0.091576213509771, 0.816847572980459, 0.109951743655322],
                  [0.816847572980459, 0.091576213509771, 0.109951743655322]])

@njit(**_FAST)
def _add_geometric(Kg, gx, gy, nn, Nx, Ny, Nxy, w):
    """Kg += w sum over u, v, w of (grad c)^T N (grad c) with grad c from the corner functions'
    gradients gx, gy (nn,); N = [[Nx, Nxy], [Nxy, Ny]] the membrane resultants [N/m]."""
    for i in range(nn):
        for j in range(nn):
            s = w * (gx[i] * (Nx * gx[j] + Nxy * gy[j]) + gy[i] * (Nxy * gx[j] + Ny * gy[j]))
            for c in range(3):
                Kg[6 * i + c, 6 * j + c] += s


@njit(**_FAST)
def _geometric_chunk(X, N, K_out, start, stop):
    """Initial-stress stiffness (global axes) of quads (X (n, 4, 3)) or triangles (X (n, 3, 3)) under
    constant membrane resultants N (n, 3) = [Nx, Ny, Nxy] in element axes: the Green strain's
    quadratic terms of the corner (bilinear or linear) translation fields, 2 x 2 Gauss on quads."""
    nn = X.shape[1]
    Xe = np.empty((nn, 3))
    E = np.empty((3, 3))
    xl = np.empty((nn, 2))
    h = np.empty(nn)
    Kl = np.empty((6 * nn, 6 * nn))
    gx = np.empty(nn)
    gy = np.empty(nn)
    tmp = np.empty((3, 3))
    Cx = np.empty((9, 6))
    Cy = np.empty((9, 6))
    q = np.empty(6)
    abcde = np.empty((5, 3))
    hx = np.empty(9)
    hy = np.empty(9)
    for el in range(start, stop):
        for i in range(nn):
            for j in range(3):
                Xe[i, j] = X[el, i, j]
        for i in range(6 * nn):
            for j in range(6 * nn):
                Kl[i, j] = 0.0
        Nx, Ny, Nxy = N[el, 0], N[el, 1], N[el, 2]
        if nn == 4:
            quad_frame(Xe, E, xl, h)
            for gp in range(4):
                xi = -_G if gp == 0 or gp == 3 else _G
                eta = -_G if gp < 2 else _G
                dxi = (-0.25 * (1 - eta), 0.25 * (1 - eta), 0.25 * (1 + eta), -0.25 * (1 + eta))
                deta = (-0.25 * (1 - xi), -0.25 * (1 + xi), 0.25 * (1 + xi), 0.25 * (1 - xi))
                J00 = J01 = J10 = J11 = 0.0
                for i in range(4):
                    J00 += dxi[i] * xl[i, 0]
                    J01 += dxi[i] * xl[i, 1]
                    J10 += deta[i] * xl[i, 0]
                    J11 += deta[i] * xl[i, 1]
                dj = J00 * J11 - J01 * J10
                for i in range(4):
                    gx[i] = (J11 * dxi[i] - J01 * deta[i]) / dj
                    gy[i] = (-J10 * dxi[i] + J00 * deta[i]) / dj
                _add_geometric(Kl, gx, gy, 4, Nx, Ny, Nxy, dj)
            warp_links(Kl, h, 4)
        else:
            tri_frame(Xe, E, xl)
            A2 = (xl[1, 0] - xl[0, 0]) * (xl[2, 1] - xl[0, 1]) - (xl[2, 0] - xl[0, 0]) * (xl[1, 1] - xl[0, 1])
            for i in range(3):
                j, k = (i + 1) % 3, (i + 2) % 3
                gx[i] = (xl[j, 1] - xl[k, 1]) / A2
                gy[i] = (xl[k, 0] - xl[j, 0]) / A2
            _add_geometric(Kl, gx, gy, 3, Nx, Ny, Nxy, 0.5 * A2)
            # w: the slopes are DKT's rotations, grad w = -(beta_x, beta_y) (a linear w would let
            # the discrete Kirchhoff field buckle about 1 % below the plate's load)
            for r in range(9):
                for c in range(9):
                    Kl[6 * (r // 3) + 2 + r % 3, 6 * (c // 3) + 2 + c % 3] = 0.0
            _dkt_coefficients(xl, Cx, Cy, abcde)
            for gp in range(6):
                xi, eta, wgt = _TRI6[gp, 0], _TRI6[gp, 1], _TRI6[gp, 2] * 0.5 * A2
                l0 = 1.0 - xi - eta
                q[0], q[1], q[2] = l0 * (2 * l0 - 1), xi * (2 * xi - 1), eta * (2 * eta - 1)
                q[3], q[4], q[5] = 4 * xi * eta, 4 * eta * l0, 4 * xi * l0
                for r in range(9):
                    hx[r] = 0.0
                    hy[r] = 0.0
                    for s_ in range(6):
                        hx[r] += Cx[r, s_] * q[s_]
                        hy[r] += Cy[r, s_] * q[s_]
                for r in range(9):
                    gr = 6 * (r // 3) + 2 + r % 3
                    for c in range(9):
                        Kl[gr, 6 * (c // 3) + 2 + c % 3] += wgt * (hx[r] * (Nx * hx[c] + Nxy * hy[c])
                                                                  + hy[r] * (Nxy * hx[c] + Ny * hy[c]))
        to_global(E, Kl, K_out[el], nn, tmp)


@njit(cache=True, nogil=True)
def turn_blocks(M, E, out):
    """out[e] = E_e M_ab E_e^T on each 3 x 3 block (a, b) of the element matrices M (n, d, d) with
    frames E (n, 3, 3): the products in the order of two batched matmuls (M E^T first), without
    their per-block call overhead (three times faster on 1,024 quads)."""
    n, d = M.shape[0], M.shape[1]
    nb = d // 3
    T = np.empty((3, 3))
    for e in range(n):
        for a in range(nb):
            for b in range(nb):
                for j in range(3):
                    for m in range(3):
                        t = 0.0
                        for k in range(3):
                            t += M[e, 3 * a + j, 3 * b + k] * E[e, m, k]
                        T[j, m] = t
                for i in range(3):
                    for m in range(3):
                        s = 0.0
                        for j in range(3):
                            s += E[e, i, j] * T[j, m]
                        out[e, 3 * a + i, 3 * b + m] = s
    return out
