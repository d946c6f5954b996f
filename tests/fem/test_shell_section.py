"""Shell sections: MAT1/MAT2/MAT8, PSHELL and laminates (classical lamination theory) against
hand-computed A, B, D (textbook ply data: Kaw, Mechanics of Composite Materials, ex. 2.6/4.x)."""

import numpy as np
import pytest

from flexgvt.errors import ModelError
from flexgvt.fem._shell_section import Ply, mat1, mat2, mat8, pcomp, pshell, section_arrays

# Kaw's graphite/epoxy ply: E1 181 GPa, E2 10.3 GPa, nu12 0.28, G12 7.17 GPa ->
# Q11 181.8, Q12 2.897, Q22 10.35, Q66 7.17 GPa (Kaw, Example 2.6).
PLY = mat8(181e9, 10.3e9, 0.28, 7.17e9, rho=1590.0)
Q11, Q12, Q22, Q66 = 181.8e9, 2.897e9, 10.35e9, 7.17e9


def test_mat8_reduced_stiffness_matches_textbook():
    assert np.allclose(PLY.Q[[0, 0, 1, 2], [0, 1, 1, 2]], [Q11, Q12, Q22, Q66], rtol=2e-3)


def test_cross_ply_symmetric_laminate():
    t = 0.125e-3
    s = pcomp([Ply(PLY, t, 0.0), Ply(PLY, t, 90.0)], lam="SYM")  # [0/90]s, 4 plies
    Q = PLY.Q
    # hand: A11 = 2t (Q11 + Q22), A12 = 4t Q12, A66 = 4t Q66; D11 = (14 Q11 + 2 Q22) t^3/3
    assert np.allclose(s.A[0, 0], 2 * t * (Q[0, 0] + Q[1, 1]), rtol=1e-12)
    assert np.allclose(s.A[0, 1], 4 * t * Q[0, 1], rtol=1e-12)
    assert np.allclose(s.A[2, 2], 4 * t * Q[2, 2], rtol=1e-12)
    assert np.allclose(s.D[0, 0], (14 * Q[0, 0] + 2 * Q[1, 1]) * t**3 / 3, rtol=1e-12)
    assert np.allclose(s.D[1, 1], (2 * Q[0, 0] + 14 * Q[1, 1]) * t**3 / 3, rtol=1e-12)
    assert np.abs(s.B).max() < 1e-12 * np.abs(s.A).max() * t
    assert np.isclose(s.m0, 4 * t * 1590.0) and abs(s.m1) < 1e-15
    # in textbook units: A11 = 2 * 0.125e-3 * (181.8 + 10.35) GPa = 48.04 MN/m
    assert np.isclose(s.A[0, 0], 48.04e6, rtol=2e-3)


def test_unsymmetric_cross_ply_has_coupling():
    t = 0.125e-3
    s = pcomp([Ply(PLY, t, 0.0), Ply(PLY, t, 90.0)])  # [0/90], bottom ply at 0 deg
    Q = PLY.Q
    assert np.isclose(s.A[0, 0], t * (Q[0, 0] + Q[1, 1]), rtol=1e-12)
    assert np.isclose(s.B[0, 0], (Q[1, 1] - Q[0, 0]) * t**2 / 2, rtol=1e-12)
    assert np.isclose(s.B[1, 1], (Q[0, 0] - Q[1, 1]) * t**2 / 2, rtol=1e-12)
    assert abs(s.B[0, 1]) < 1e-9 * abs(s.B[0, 0]) and abs(s.B[2, 2]) < 1e-9 * abs(s.B[0, 0])
    assert np.isclose(s.D[0, 0], (Q[0, 0] + Q[1, 1]) * t**3 / 3, rtol=1e-12)


def test_angle_ply_rotation_against_transformed_stiffness():
    # Qbar11 at 45 deg = (Q11 + Q22 + 2 Q12 + 4 Q66) / 4; Qbar16 = (Q11 - Q22) / 4
    s = pcomp([Ply(PLY, 1e-3, 45.0)])
    Q = PLY.Q
    assert np.isclose(s.A[0, 0] / 1e-3, (Q[0, 0] + Q[1, 1] + 2 * Q[0, 1] + 4 * Q[2, 2]) / 4, rtol=1e-12)
    assert np.isclose(s.A[0, 2] / 1e-3, (Q[0, 0] - Q[1, 1]) / 4, rtol=1e-12)


def test_isotropic_single_ply_equals_pshell():
    E, nu, t, rho = 70e9, 0.3, 2e-3, 2700.0
    G = E / (2 * (1 + nu))
    ply = mat8(E, E, nu, G, G, G, rho=rho)
    lam = pcomp([Ply(ply, t, 30.0)])
    sh = pshell(t, mat1(E, nu=nu, rho=rho), mat1(E, nu=nu, rho=rho))
    for a, b in ((lam.A, sh.A), (lam.D, sh.D), (lam.S, sh.S)):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())
    assert np.abs(lam.B).max() < 1e-9 * np.abs(sh.A).max() * t
    assert np.isclose(lam.m0, sh.m0) and np.isclose(lam.m2, sh.m2)


def test_pshell_fields_and_offset():
    m1 = mat1(70e9, nu=0.3, rho=2700.0)
    s = pshell(0.002, m1, m1, bmir=2.0, tst=0.5, nsm=1.5)
    assert np.allclose(s.A, 0.002 * m1.Q)
    assert np.allclose(s.D, 2.0 * 0.002**3 / 12 * m1.Q)
    assert np.allclose(s.S, 0.5 * 0.002 * m1.G)
    assert np.isclose(s.m0, 2700 * 0.002 + 1.5)
    # an offset z: the same energy for strains measured at the nodes' plane: B = z A, D + z^2 A
    z = 0.01
    o = s.offset(z)
    assert np.allclose(o.B, z * s.A) and np.allclose(o.D, s.D + z * z * s.A)
    assert np.isclose(o.m1, z * 2700 * 0.002) and np.isclose(o.m2, s.m2 + z * z * 2700 * 0.002)
    # membrane only: no bending or shear
    mem = pshell(0.002, m1)
    assert not mem.D.any() and not mem.S.any()


def test_mat2_and_rotation_invariants():
    m = mat2(100e9, 30e9, 0.0, 50e9, 0.0, 20e9, rho=1000.0)
    s = pshell(0.001, m, m)
    r = s.rotated(np.radians(37.0))
    # the trace invariants of a rotated stiffness: Q11 + Q22 + 2 Q12 and Q66 - Q12
    for M0, M1 in ((s.A, r.A), (s.D, r.D)):
        assert np.isclose(M0[0, 0] + M0[1, 1] + 2 * M0[0, 1], M1[0, 0] + M1[1, 1] + 2 * M1[0, 1])
        assert np.isclose(M0[2, 2] - M0[0, 1], M1[2, 2] - M1[0, 1])
    C, mass = section_arrays([s, r], np.array([1, 0, 1]))
    assert C.shape == (3, 8, 8) and np.allclose(C[0, :3, :3], r.A) and np.allclose(mass[1], [s.m0, s.m1, s.m2])


@pytest.mark.parametrize("bad", [
    lambda: pshell(0.0, mat1(70e9, nu=0.3)),
    lambda: pshell(-1e-3, mat1(70e9, nu=0.3)),
    lambda: pcomp([]),
    lambda: pcomp([Ply(PLY, 0.0, 0.0)]),
    lambda: pcomp([Ply(PLY, 1e-3, 0.0)], lam="SMEAR"),
    lambda: mat1(70e9, nu=0.6),
    lambda: mat8(1e9, 1e9, 1.5, 1e9),
])
def test_bad_sections_raise_clear_errors(bad):
    with pytest.raises(ModelError, match=r"(PSHELL|PCOMP|MAT1|MAT8).*"):
        bad()
