"""The DKMT triangle (Katili 1993): DKT in the thin limit and without shear stiffness, transverse
shear flexibility of thick plates against Mindlin references (Navier series and closed-form
frequencies, the pb-2 Ritz series of Liew et al. for clamped plates), with flexgvt's MITC4 quad
beside it; patch tests at thick t and a Timoshenko cantilever (constant shear force)."""

import numpy as np
import pytest
from mindlin_reference import navier_centre_deflection, navier_frequencies, ritz_square_plate
from test_shell_kernel import PATCH_TRIS, PATCH_XY, grid, matrices, plane, plate_modes, pressure_loads, solve

import flexgvt as fg
from flexgvt.fem._shell_elements import shell_matrices
from flexgvt.fem._shell_kernel import _TRI_L, _dkt_coefficients
from flexgvt.fem._shell_model import compile_shells
from flexgvt.fem._shell_section import mat1, pshell, section_arrays

BENDING = np.array([2, 3, 4, 8, 9, 10, 14, 15, 16])  # w, theta_x, theta_y of the three corners
XL = np.array([[0.0, 0.0], [1.0, 0.0], [0.3, 0.8]])  # side 1-2 along x: the kernel's frame is the plane's


def dkt_bending(xl, D):
    """DKT bending stiffness (9, 9) by Batoz, Bathe & Ho's six quadratic functions (the route the
    kernel took before DKMT), 3-point rule (exact: linear curvatures)."""
    xl = np.ascontiguousarray(xl - xl.mean(0))
    Cx, Cy = np.empty((9, 6)), np.empty((9, 6))
    _dkt_coefficients(xl, Cx, Cy, np.empty((5, 3)))
    A2 = (xl[1, 0] - xl[0, 0]) * (xl[2, 1] - xl[0, 1]) - (xl[2, 0] - xl[0, 0]) * (xl[1, 1] - xl[0, 1])
    (x31, y31), (x12, y12) = xl[2] - xl[0], xl[0] - xl[1]
    K = np.zeros((9, 9))
    for xi, eta in _TRI_L[:, 1:]:
        l0 = 1 - xi - eta
        dxi = np.array([1 - 4 * l0, 4 * xi - 1, 0, 4 * eta, -4 * eta, 4 * (l0 - xi)])
        deta = np.array([1 - 4 * l0, 0, 4 * eta - 1, 4 * xi, 4 * (l0 - eta), -4 * xi])
        B = np.array([y31 * Cx @ dxi + y12 * Cx @ deta, -x31 * Cy @ dxi - x12 * Cy @ deta,
                      -x31 * Cx @ dxi - x12 * Cx @ deta + y31 * Cy @ dxi + y12 * Cy @ deta]) / A2
        K += B.T @ D @ B * A2 / 6
    return K


def bending_block(t, rigid_shear=False, nu=0.3):
    m = mat1(7e10, nu=nu)
    sec = pshell(t, m, m)
    C, _ = section_arrays([sec], [0])
    if rigid_shear:
        C[:, 6:, 6:] = 0.0
    K = shell_matrices(np.c_[XL, np.zeros(3)][None], C, local=True).K[0]
    return K[np.ix_(BENDING, BENDING)], sec.D


def test_dkmt_is_dkt_without_shear_stiffness_and_in_the_thin_limit():
    K, D = bending_block(0.01, rigid_shear=True)
    ref = dkt_bending(XL, D)
    assert np.abs(K - ref).max() < 1e-14 * np.abs(ref).max()  # measured 4e-16
    # with shear stiffness the difference is of order phi = 2/(k(1 - nu)) (t/L)^2: measured
    # 4.4e-4, 4.4e-6, 4.4e-8 of max |K| at t/L = 1e-2, 1e-3, 1e-4 (element sides 0.81-1.0)
    diffs = []
    for t in (1e-2, 1e-3, 1e-4):
        K, D = bending_block(t)
        ref = dkt_bending(XL, D)
        diffs.append(np.abs(K - ref).max() / np.abs(ref).max())
    assert diffs[2] < 1e-7
    assert np.allclose(np.array(diffs[:2]) / diffs[1:], 100.0, rtol=0.01), diffs


def test_side_factors_ignore_offsets_and_scale_as_thickness_squared():
    """phi_k = 12 D_k / (S_k L_k^2) from the bending stiffness with the membrane free: an offset
    section (B = z A, D + z^2 A) has the same phi_k as the plain one; isotropic phi_k =
    2 / (k (1 - nu)) (t / L_k)^2 (Katili)."""
    from flexgvt.fem._shell_dkmt import dkmt_sides
    m = mat1(7e10, nu=0.3)

    def phis(sec):
        C = section_arrays([sec], [0])[0][0]
        al, gl, geo = np.empty((3, 9)), np.empty(3), np.empty((3, 3))
        dkmt_sides(np.ascontiguousarray(XL - XL.mean(0)), C, al, gl, geo, np.empty((3, 3)), np.empty((3, 3)))
        return -1.5 * gl, geo[:, 0]

    phi, L = phis(pshell(0.05, m, m))
    assert np.allclose(phi, 2 / (5 / 6 * 0.7) * (0.05 / L) ** 2, rtol=1e-12)
    assert np.allclose(phis(pshell(0.05, m, m).offset(0.3))[0], phi, rtol=1e-9)


def test_constant_curvature_patch_and_rigid_modes_at_any_thickness():
    """MacNeal-Harder's patch (0.24 x 0.12) as triangles, t = 0.001 and 0.1 (thicker than the
    elements): a constant-curvature state has no shear (Mindlin: Q = div M = 0), so the interior
    nodes reproduce it exactly; a free patch keeps exactly six rigid-body modes."""
    xyz = np.c_[PATCH_XY, np.zeros(8)]
    x, y = PATCH_XY.T
    exact = np.zeros((8, 6))
    exact[:, 2] = 1e-3 * (x * x + x * y + y * y) / 2
    exact[:, 3] = 1e-3 * (x / 2 + y)
    exact[:, 4] = -1e-3 * (x + y / 2)
    for t in (0.001, 0.1):
        K = matrices(xyz, PATCH_TRIS, pshell(t, mat1(1e6, nu=0.25), mat1(1e6, nu=0.25)))[0]
        u = solve(K, np.zeros(48), np.arange(24), exact[:4].ravel()).reshape(8, 6)
        assert np.abs(u[4:, 2:5] - exact[4:, 2:5]).max() < 1e-11 * max(1.0, t / 0.001)
        ev = np.linalg.eigvalsh(K.toarray())
        assert np.all(np.abs(ev[:6]) < 1e-12 * ev[-1]) and ev[6] > 1e4 * np.abs(ev[:6]).max()


@pytest.mark.parametrize("t", [0.2, 0.01], ids=["L/t=5", "L/t=100"])
def test_timoshenko_cantilever_under_end_shear(t):
    """Constant shear force: a strip L 1, b 0.2, nu = 0 (a plate strip is then a beam), clamped,
    uniform end shear P: tip P L^3 / (3 E I) + P L / (k G A), k = 5/6. DKMT 8 x 2 (32 triangles):
    measured 0.99936 (L/t = 5), 0.99985 (100); MITC4 8 x 2 gives 0.9962 / 0.9961."""
    L, b, E = 1.0, 0.2, 1e7
    m = mat1(E, nu=0.0)
    ref = L**3 / (3 * E * b * t**3 / 12) + L / (5 / 6 * E / 2 * b * t)
    xyz, conn = grid(plane(L, b), 8, 2, tri=True)
    x, y = xyz[:, 0], xyz[:, 1]
    root, tip = np.flatnonzero(np.isclose(x, 0)), np.flatnonzero(np.isclose(x, L))
    fix = np.unique(np.concatenate([6 * root + k for k in range(6)] + [6 * np.arange(len(x)) + k for k in (0, 1, 5)]))
    tip = tip[np.argsort(y[tip])]
    f = np.zeros(6 * len(x))
    share = np.diff(y[tip]) / b / 2  # consistent shares of a uniform edge shear, P = 1
    np.add.at(f, 6 * tip[:-1] + 2, share)
    np.add.at(f, 6 * tip[1:] + 2, share)
    u = solve(matrices(xyz, conn, pshell(t, m, m))[0], f, fix)
    assert abs(np.mean(u[6 * tip + 2]) / ref - 1) < 1e-3


# Mindlin references (a = 1, nu = 0.3, k = 5/6): centre deflection w D / (q a^4) and
# lambda = omega a^2 / pi^2 sqrt(rho t / D) of the first four modes. Simply supported: Navier series
# and the closed-form frequencies (mindlin_reference); clamped: the pb-2 Ritz series at p = 20,
# whose frequencies equal Liew, Xiang & Kitipornchai's table (1993, J. Sound Vib.; h/b = 0.1: 3.2954,
# 6.2858, 6.2858, 8.8098; 0.2: 2.6875) to the digits printed there.
MINDLIN = {
    ("ss", 10): (0.0042728422, [1.9316850, 4.6083590, 4.6083590, 7.0716477]),
    ("ss", 5): (0.0049043110, [1.7679119, 3.8656227, 3.8656227, 5.5878711]),
    ("clamped", 10): (0.0015046256, [3.2953981, 6.2858213, 6.2858213, 8.8097708]),
    ("clamped", 5): (0.0021721605, [2.6874528, 4.6907278, 4.6907278, 6.2984896]),
}


def test_mindlin_references_agree_with_each_other():
    """The Ritz series against the closed forms (simply supported) and the stored values."""
    a, E, nu, rho = 1.0, 7e10, 0.3, 2700.0
    for ratio in (10, 5):
        t = a / ratio
        D = E * t**3 / (12 * (1 - nu**2))
        scale = a**2 / np.pi**2 * np.sqrt(rho * t / D)
        w, f = ritz_square_plate(a, t, E, nu, rho, clamped=False, p=12, modes=4)
        assert np.isclose(w, navier_centre_deflection(a, t, E, nu), rtol=1e-6)
        assert np.allclose(f, navier_frequencies(a, t, E, nu, rho)[:4], rtol=1e-9)
        assert np.isclose(w * D / a**4, MINDLIN["ss", ratio][0], rtol=1e-6)
        assert np.allclose(f * scale, MINDLIN["ss", ratio][1], rtol=1e-6)
        w, f = ritz_square_plate(a, t, E, nu, rho, clamped=True, p=12, modes=4)
        assert np.isclose(w * D / a**4, MINDLIN["clamped", ratio][0], rtol=1e-5)
        assert np.allclose(f * scale, MINDLIN["clamped", ratio][1], rtol=1e-6)


def _square_plate(bc, ratio, nx, tri):
    """Centre deflection / Mindlin and the first four frequencies / Mindlin - 1 of the square plate."""
    a, E, nu, rho = 1.0, 7e10, 0.3, 2700.0
    t = a / ratio
    D = E * t**3 / (12 * (1 - nu**2))
    m = mat1(E, nu=nu, rho=rho)
    sec = pshell(t, m, m)
    xyz, conn = grid(plane(a, a), nx, nx, tri)
    x, y = xyz[:, 0], xyz[:, 1]
    onx = np.isclose(x, 0) | np.isclose(x, a)
    ony = np.isclose(y, 0) | np.isclose(y, a)
    fix = [6 * np.arange(len(x)) + k for k in (0, 1, 5)] + [6 * np.flatnonzero(onx | ony) + 2]
    if bc == "ss":  # hard support: the rotation of the normal along the edge is held
        fix += [6 * np.flatnonzero(onx) + 3, 6 * np.flatnonzero(ony) + 4]
    else:
        fix += [6 * np.flatnonzero(onx | ony) + 3, 6 * np.flatnonzero(onx | ony) + 4]
    fix = np.unique(np.concatenate(fix))
    u = solve(matrices(xyz, conn, sec)[0], pressure_loads(xyz, conn, 1.0), fix)
    c = np.argmin((x - a / 2) ** 2 + (y - a / 2) ** 2)
    w_ref, lam_ref = MINDLIN[bc, ratio]
    lam = plate_modes(xyz, conn, sec, fix, 4) * a**2 / np.pi**2 * np.sqrt(rho * t / D)
    return u[6 * c + 2] * D / a**4 / w_ref, lam / lam_ref - 1


# measured centre deflection / Mindlin on 8, 16, 32 (triangles | quads):
#   ss L/t = 10:      0.9865, 0.9964, 0.9991 | 0.9957, 0.9989, 0.9997
#   ss L/t = 5:       0.9859, 0.9964, 0.9991 | 0.9979, 0.9995, 0.9999
#   clamped L/t = 10: 1.0134, 1.0024, 1.0005 | 0.9889, 0.9972, 0.9993
#   clamped L/t = 5:  1.0002, 0.9997, 0.9999 | 0.9932, 0.9983, 0.9996
# first four frequencies on 32 x 32: triangles +0.13..+0.57 %, quads +0.09..+0.53 % (from above, h^2)
@pytest.mark.parametrize("tri", [True, False], ids=["DKMT", "MITC4"])
@pytest.mark.parametrize("bc,ratio", list(MINDLIN), ids=[f"{b}-L/t={r}" for b, r in MINDLIN])
def test_thick_square_plate_against_mindlin(bc, ratio, tri):
    w8, f8 = _square_plate(bc, ratio, 8, tri)
    w16, f16 = _square_plate(bc, ratio, 16, tri)
    w32, f32 = _square_plate(bc, ratio, 32, tri)
    assert abs(w32 - 1) < 0.002 and abs(w16 - 1) < 0.005 and abs(w8 - 1) < 0.015, (w8, w16, w32)
    assert abs(w32 - 1) <= abs(w8 - 1)
    assert np.all(f32 > 0) and np.all(f32 < 0.01), f32
    assert np.all(f16 / f32 > 3.5) and np.all(f8 / f16 > 3.0), (f8, f16, f32)  # second order (3.4-4.1 measured)


def test_triangles_of_a_pshell_without_mid3_are_rigid_in_shear():
    """Nastran semantics: a PSHELL with MID2 and no MID3 is rigid in transverse shear; triangles take
    it (DKT), quads keep MID2's shear times TS/T (MITC4 would lock; docs/shells.md)."""
    model = fg.Model("mid3")
    model.add_nodes([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], ids=[1, 2, 3, 4])
    al = fg.Material("Al", E=70e9, nu=0.3, rho=2700.0)
    blank = fg.model.ShellProperty("no_mid3", 0.1, al, al)
    model.add_shells([[1, 2, 3, 4]], blank, name="quad")
    model.add_shells([[1, 2, 3], [1, 3, 4]], blank, name="tri")
    model.add_shells([[1, 2, 3]], fg.model.ShellProperty.isotropic(al, 0.1), name="tri_mid3")
    quads, tris = compile_shells(model, model.xyz)
    assert np.all(quads.C[:, 6:, 6:].diagonal(axis1=1, axis2=2) > 0)
    rigid = tris.group_names == "tri"
    assert np.all(tris.C[rigid, 6:, 6:] == 0) and np.all(tris.C[~rigid, 6:, 6:].diagonal(axis1=1, axis2=2) > 0)

