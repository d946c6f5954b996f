"""Compiled parts of the DKMT plate triangle (Katili 1993): bending with transverse shear.

Katili, "A new discrete Kirchhoff-Mindlin element based on Mindlin-Reissner plate theory and assumed
shear strain fields, Part I: an extended DKT element for thick-plate bending analysis", IJNME 36
(1993) 1859-1883. Over the DOFs [w, theta_x, theta_y] x 3 (beta_x = theta_y, beta_y = -theta_x):

  - rotations: linear plus a quadratic bubble of the tangential rotation on each side k = (i, j),
    beta = sum_n L_n beta_n + sum_k 4 L_i L_j Delta_k s_k (s_k the side's unit tangent);
  - the side's shear strain gamma_k (constant along it) from the equilibrium of the side as a
    Timoshenko beam, Q_s = dM_s/ds: gamma_k = -(2/3) phi_k Delta_k, phi_k = 12 D_k / (S_k L_k^2)
    (isotropic: 2 / (k (1 - nu)) (t / L_k)^2, Katili's phi_k);
  - the discrete Mindlin constraint int_k (w,s + beta_s - gamma_k) ds = 0 gives
    (2/3) L_k (1 + phi_k) Delta_k = -(w_j - w_i) - L_k / 2 (beta_s,i + beta_s,j);
  - the transverse shear field: the linear field whose tangential component on each side is
    gamma_k (the lowest Nedelec field, Whitney's L_i grad L_j - L_j grad L_i per side).

phi_k = 0 is DKT exactly (Batoz, Bathe & Ho 1980): same rotations, no shear energy. A section
without transverse shear stiffness (S = 0 with bending, e.g. a PSHELL with MID3 blank on a
triangle: Nastran's rigid transverse shear) takes phi_k = 0. D_k is the side's bending stiffness of
the section with the membrane strains free, D - B^T A^-1 B, so an offset (ZOFFS) or an
unsymmetric laminate does not turn membrane stiffness into shear flexibility; S_k the side's shear
stiffness s^T S s.
"""

from __future__ import annotations

import numpy as np
from numba import njit

_FAST = dict(cache=True, fastmath={"contract", "reassoc", "arcp", "nsz"}, nogil=True, error_model="numpy")


@njit(**_FAST)
def _reduced_bending(C, Dr, inv):
    """Dr (3, 3) = D - B^T A^-1 B of the section C (8, 8) (D where A is singular: no membrane);
    inv (3, 3) work."""
    a00, a01, a02 = C[0, 0], C[0, 1], C[0, 2]
    a11, a12, a22 = C[1, 1], C[1, 2], C[2, 2]
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    det = a00 * c00 + a01 * c01 + a02 * c02
    for i in range(3):
        for j in range(3):
            Dr[i, j] = C[3 + i, 3 + j]
    scale = abs(a00) + abs(a11) + abs(a22)
    if scale == 0.0 or abs(det) <= 1e-12 * scale * scale * scale:
        return
    coupled = False
    for i in range(3):
        for j in range(3):
            if C[i, 3 + j] != 0.0:
                coupled = True
    if not coupled:
        return
    inv[0, 0], inv[0, 1], inv[0, 2] = c00 / det, c01 / det, c02 / det
    inv[1, 1] = (a00 * a22 - a02 * a02) / det
    inv[1, 2] = (a01 * a02 - a00 * a12) / det
    inv[2, 2] = (a00 * a11 - a01 * a01) / det
    inv[1, 0], inv[2, 0], inv[2, 1] = inv[0, 1], inv[0, 2], inv[1, 2]
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for k in range(3):
                for m in range(3):
                    acc += C[k, 3 + i] * inv[k, m] * C[m, 3 + j]
            Dr[i, j] -= acc


@njit(**_FAST)
def dkmt_sides(xl, C, al, gl, geo, Dr, inv):
    """Per side k = (0, 1), (1, 2), (2, 0) of the triangle at local corners xl (3, 2) with section C:
    al (3, 9) the bubble amplitude Delta_k = al[k] . [w, theta_x, theta_y] x 3, gl (3,) its shear
    strain factor gamma_k = gl[k] Delta_k, geo (3, 3) the side's [length, cos, sin]; Dr, inv (3, 3)
    work (Dr: the reduced bending stiffness). Returns the largest phi_k."""
    _reduced_bending(C, Dr, inv)
    S00, S01, S11 = C[6, 6], C[6, 7], C[7, 7]
    phimax = 0.0
    for k in range(3):
        i, j = k, (k + 1) % 3
        dx, dy = xl[j, 0] - xl[i, 0], xl[j, 1] - xl[i, 1]
        L = np.sqrt(dx * dx + dy * dy)
        c, s = dx / L, dy / L
        geo[k, 0], geo[k, 1], geo[k, 2] = L, c, s
        a0, a1, a2 = c * c, s * s, 2 * c * s
        Dk = (a0 * (Dr[0, 0] * a0 + Dr[0, 1] * a1 + Dr[0, 2] * a2)
              + a1 * (Dr[1, 0] * a0 + Dr[1, 1] * a1 + Dr[1, 2] * a2)
              + a2 * (Dr[2, 0] * a0 + Dr[2, 1] * a1 + Dr[2, 2] * a2))
        Sk = c * c * S00 + 2 * c * s * S01 + s * s * S11
        phi = 12.0 * Dk / (Sk * L * L) if Sk > 0.0 and Dk > 0.0 else 0.0
        phimax = max(phimax, phi)
        g = -1.5 / (L * (1.0 + phi))
        for r in range(9):
            al[k, r] = 0.0
        # beta_s at a corner = c beta_x + s beta_y = c theta_y - s theta_x
        al[k, 3 * j] = g
        al[k, 3 * i] = -g
        for n in (i, j):
            al[k, 3 * n + 1] = -0.5 * L * s * g
            al[k, 3 * n + 2] = 0.5 * L * c * g
        gl[k] = -2.0 / 3.0 * phi
    return phimax


@njit(**_FAST)
def dkmt_point(xl, lam, al, gl, geo, Bm):
    """Curvature rows Bm[3:6] and transverse shear rows Bm[6:8] (columns of the 18 shell DOFs) at
    the point of area coordinates lam (3,). Only the w, theta_x, theta_y columns are written."""
    A2 = (xl[1, 0] - xl[0, 0]) * (xl[2, 1] - xl[0, 1]) - (xl[2, 0] - xl[0, 0]) * (xl[1, 1] - xl[0, 1])
    bx0, bx1, bx2 = (xl[1, 1] - xl[2, 1]) / A2, (xl[2, 1] - xl[0, 1]) / A2, (xl[0, 1] - xl[1, 1]) / A2
    by0, by1, by2 = (xl[2, 0] - xl[1, 0]) / A2, (xl[0, 0] - xl[2, 0]) / A2, (xl[1, 0] - xl[0, 0]) / A2
    for r in range(9):
        col = 6 * (r // 3) + 2 + r % 3
        for a in range(3, 8):
            Bm[a, col] = 0.0
    for n in range(3):
        gx = bx0 if n == 0 else (bx1 if n == 1 else bx2)
        gy = by0 if n == 0 else (by1 if n == 1 else by2)
        ctx, cty = 6 * n + 3, 6 * n + 4
        Bm[3, cty] += gx  # kx = d beta_x / dx, beta_x = theta_y
        Bm[4, ctx] -= gy  # ky = d beta_y / dy, beta_y = -theta_x
        Bm[5, cty] += gy
        Bm[5, ctx] -= gx
    for k in range(3):
        i, j = k, (k + 1) % 3
        gxi = bx0 if i == 0 else (bx1 if i == 1 else bx2)
        gyi = by0 if i == 0 else (by1 if i == 1 else by2)
        gxj = bx0 if j == 0 else (bx1 if j == 1 else bx2)
        gyj = by0 if j == 0 else (by1 if j == 1 else by2)
        L, c, s = geo[k, 0], geo[k, 1], geo[k, 2]
        px = 4.0 * (lam[i] * gxj + lam[j] * gxi)  # grad of the bubble 4 L_i L_j
        py = 4.0 * (lam[i] * gyj + lam[j] * gyi)
        wx = gl[k] * L * (lam[i] * gxj - lam[j] * gxi)  # gamma_k times Whitney's side field
        wy = gl[k] * L * (lam[i] * gyj - lam[j] * gyi)
        for r in range(9):
            v = al[k, r]
            if v == 0.0:
                continue
            col = 6 * (r // 3) + 2 + r % 3
            Bm[3, col] += px * c * v
            Bm[4, col] += py * s * v
            Bm[5, col] += (py * c + px * s) * v
            Bm[6, col] += wx * v
            Bm[7, col] += wy * v
