"""The one-factorisation solves of the derivatives (updating.modesolve): against direct sparse solves
of the same systems, and the whole Jacobian (frequencies, MAC, cross-orthogonality, static
deflection, shell variables about the deformed self-weight state) against the per-mode Nelson
factorisations it replaces and against finite differences of whole solves."""

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from test_gradients import TIGHT, _check
from test_shell_variables import shell_strip

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.errors import SolverError
from flexgvt.fem.eigen import real_modes
from flexgvt.updating import blocks
from flexgvt.updating.modesolve import ModeSolver


@pytest.fixture(scope="module")
def strip():
    model, cfgs, ids = shell_strip()
    sensors = fg.correlation.Sensors.uniaxial(ids[:, 3::3].ravel(), (0.0, 0.0, 1.0))
    data = []
    for c in cfgs:
        state = fg.solve_static(model, c, settings=TIGHT)
        modes = fg.solve_modes(state, 6, label=False)
        S = sensors.matrix(state.node_ids, state)
        static = {(int(ids[0, -1]), 3): -0.02} if c.gravity else {}
        data.append(up.Measured(c.name, modes.frequencies_hz[:5] * 1.02, np.asarray(S @ modes.matrix()).T[:5],
                                sensors, static=static))
    variables = [up.shell("t_root", "root", "thickness"), up.shell("E_all", "*", "E"),
                 up.shell("rho_outer", "outer", "rho"), up.shell("G_tip", "tip", "G")]
    return model, cfgs, data, variables


def _matrices(model, cfg):
    state = fg.solve_static(model, cfg, settings=TIGHT)
    ev = state.system.evaluate(state.positions, state.rotations, state.load_factor)
    K = (0.5 * (ev.tangent + ev.tangent.T)).tocsc()
    M = state.system.mass_matrix(state.positions, state.rotations).tocsc()
    lam, phi = real_modes(K, M, 10, None, True)
    return K, M, lam, phi


def test_solves_match_direct_factorisations(strip):
    """G_i r (M-orthogonal to phi_i) and K^-1 r against SuperLU of the same systems, at the deformed
    self-weight state: relative 1e-8 (the direct solves' own round-off, cond(K) eps, is ~1e-10)."""
    model, cfgs, _, _ = strip
    K, M, lam, phi = _matrices(model, cfgs[0])
    solver = ModeSolver(K, M, lam, phi)
    rng = np.random.default_rng(3)
    R = rng.standard_normal((K.shape[0], 3))
    direct = spla.splu(K).solve(R)
    assert np.abs(solver.solve_stiffness(R) - direct).max() <= 1e-8 * np.abs(direct).max()
    for i in (0, 3):
        r = R - (M @ phi[:, i])[:, None] * (phi[:, i] @ R)[None, :]  # consistent: phi_i^T r = 0
        A = (K - lam[i] * M).tocsc()
        v = solver.solve(r, np.full(3, i))
        assert np.abs(phi[:, i] @ (M @ v)).max() <= 1e-10 * np.abs(v).max()
        assert np.abs(A @ v - r).max() <= 1e-8 * np.abs(r).max()
    assert solver.iterations < 60  # a few steps per block: (K - sigma M)^-1 preconditions well


def test_repeated_eigenvalues_are_refused(strip):
    model, cfgs, _, _ = strip
    K, M, lam, phi = _matrices(model, cfgs[1])
    lam = lam.copy()
    lam[2] = lam[1]
    with pytest.raises(SolverError, match="repeated"):
        ModeSolver(K, M, lam, phi).solve(np.ones((K.shape[0], 1)), np.array([1]))


@pytest.mark.parametrize("orthogonality", [0.0, 1.0])
def test_jacobian_equals_the_per_mode_factorisations(strip, monkeypatch, orthogonality):
    """MAC rows by the adjoint (orthogonality 0) and shapes at the sensors by direct solves
    (cross-orthogonality), with and without the shared factorisation: the same Jacobian to 1e-8."""
    model, cfgs, data, variables = strip
    objective = up.Objective(mac=1.0, static=1.0, orthogonality=orthogonality)
    x = np.array([1.03, 0.98, 1.01, 1.02])
    monkeypatch.setattr(blocks, "SHARED_FACTOR_MIN_DOF", 0)  # the strip is small
    used = []
    original = blocks._solver
    monkeypatch.setattr(blocks, "_solver", lambda p: used.append(1) or original(p))
    J = up.UpdatingProblem(model, cfgs, data, variables, objective=objective,
                           static_settings=TIGHT).evaluate(x, gradient=True).jacobian
    assert len(used) == 2
    monkeypatch.setattr(blocks, "_solver", lambda p: None)
    J0 = up.UpdatingProblem(model, cfgs, data, variables, objective=objective,
                            static_settings=TIGHT).evaluate(x, gradient=True).jacobian
    assert np.abs(J - J0).max() <= 1e-8 * np.abs(J0).max()


def test_jacobian_with_shapes_matches_finite_differences(strip, monkeypatch):
    """Frequencies, MAC and the static tip deflection of the deformed self-weight strip and the
    unloaded one, every shell variable type but nsm, against whole solves (with the shared
    factorisation)."""
    monkeypatch.setattr(blocks, "SHARED_FACTOR_MIN_DOF", 0)
    model, cfgs, data, variables = strip
    problem = up.UpdatingProblem(model, cfgs, data, variables, objective=up.Objective(mac=1.0, static=1.0),
                                 static_settings=TIGHT)
    _check(problem, np.array([1.03, 0.98, 1.01, 1.02]))
