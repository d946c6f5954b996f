"""Rigid-body modes are the rigid motions nothing restrains, not every mode below a round-off bound:
a hung structure with a very stiff member keeps its slow pendulum and yaw modes."""

import numpy as np
import pytest

import flexgvt as fg


def test_bungee_yaw_mode_is_not_taken_for_a_rigid_body_mode():
    case = fg.cases.xhale()
    hung = fg.solve_modes(fg.solve_static(case.model, case.configurations["bungee_inboard"]), 12, damped=False)
    # The 1e8 N/m wing-tail springs put eps * max(K/M) near 2 rad^2/s^2: above the yaw pendulum's
    # eigenvalue (about 0.17). The yaw mode is restrained by the bungees' sideways stiffness T/L.
    assert np.all(hung.frequencies_hz > 0.01)
    free = fg.solve_modes(fg.solve_static(case.model, case.configurations["free_free"]), 12, damped=False)
    assert np.sum(free.frequencies_hz == 0) == 6 and free.frequencies_hz[6] > 0.5


def test_a_pinned_structure_keeps_its_gravity_pendulum():
    """Translations fixed at one node, gravity on: the two swinging rotations are restrained by the
    weight's load stiffness only (a pendulum, ~0.5 Hz), the spin about the vertical is free (one
    zero mode); without gravity all three rotations are rigid (three zeros)."""
    model = fg.Model("pendulum")
    ids = model.add_nodes([[0, 0, 0], [0, 0, -0.5], [0, 0, -1.0]])
    model.add_beams([[ids[0], ids[1]], [ids[1], ids[2]]], fg.Material("steel", E=2e11, nu=0.3, rho=7800),
                    fg.CircularTubeSection(0.01, 0.008), orientation=(1, 0, 0))
    model.add_mass(int(ids[2]), 2.0)
    hung = fg.Configuration("hung", fixed={int(ids[0]): "123"}, gravity=1.0)
    m = fg.solve_modes(fg.solve_static(model, hung), 4, damped=False)
    assert m.frequencies_hz[0] == 0 and m.labels[0] == "RB yaw"
    assert np.allclose(m.frequencies_hz[1:3], m.frequencies_hz[1], rtol=1e-6) and m.frequencies_hz[1] > 0.4
    free = fg.solve_modes(fg.solve_static(model, hung.with_(gravity=0.0)), 4, damped=False)
    assert np.sum(free.frequencies_hz == 0) == 3


def test_dense_modes_with_a_massless_dof_are_the_condensed_ones():
    """Three DOFs in a line, the middle one massless (m, 0, m; springs k between them, and k to
    ground at the first or not): the dense path solves B phi = mu (A - sigma B) phi, symmetric
    despite the singular mass matrix, and gives the statically condensed system's modes (the two
    springs in series, k/2) with M-orthonormal shapes."""
    import scipy.sparse as sp

    from flexgvt.fem.modes import real_modes
    m, k = 2.0, 800.0
    M = sp.csc_matrix(np.diag([m, 0.0, m]))
    for ground in (0.0, k):
        K = sp.csc_matrix(np.array([[k + ground, -k, 0.0], [-k, 2 * k, -k], [0.0, -k, k]]))
        lam, phi = real_modes(K, M, 2)
        Kc = np.array([[ground + k / 2, -k / 2], [-k / 2, k / 2]])  # the middle DOF condensed out
        expected = np.sort(np.linalg.eigvalsh(Kc / m))
        assert lam == pytest.approx(expected, abs=1e-9 * k / m)
        assert phi.T @ M @ phi == pytest.approx(np.eye(2), abs=1e-12)
