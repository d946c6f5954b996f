"""Linear frequencies of straight beams against closed-form solutions (within 0.1 %), and their
convergence with mesh refinement."""

import numpy as np
import scipy.linalg

import flexgvt as fg

from fem_builders import AL, straight_beam

L = 1.5
BETA_CANTILEVER = np.array([1.87510407, 4.69409113, 7.85475744])
BETA_FREE = np.array([4.73004074, 7.85320462, 10.99560784])


def modes_of(model, fixed, n=40):
    cfg = fg.Configuration("linear", fixed=fixed)
    return fg.solve_modes(fg.solve_linear_static(model, cfg), n)


def pick(modes, cls):
    """Frequencies of the modes whose dominant energy class is cls, ascending."""
    idx = {"OOP": 0, "IP": 1, "T": 2, "EXT": 3}[cls]
    fr = modes.energy_fractions
    mask = (np.argmax(fr[:, :4], axis=1) == idx) & (modes.frequencies_hz > 1e-6)
    return modes.frequencies_hz[mask]


def test_cantilever_bending_both_planes_torsion_and_axial(strip_props):
    sec, p = strip_props
    model, ids = straight_beam(40, L, sec)
    modes = modes_of(model, {int(ids[0]): "123456"})
    mA = AL.rho * p["A"]
    flap = BETA_CANTILEVER**2 * np.sqrt(AL.E * p["Iy"] / (mA * L**4)) / (2 * np.pi)
    edge = BETA_CANTILEVER[:2] ** 2 * np.sqrt(AL.E * p["Iz"] / (mA * L**4)) / (2 * np.pi)
    k = 2 * np.arange(1, 3) - 1
    torsion = k / (4 * L) * np.sqrt(AL.shear_modulus * p["J"] / (AL.rho * p["Ip"]))
    axial = np.array([1.0]) / (4 * L) * np.sqrt(AL.E / AL.rho)
    np.testing.assert_allclose(pick(modes, "OOP")[:3], flap, rtol=1e-3)
    np.testing.assert_allclose(pick(modes, "IP")[:2], edge, rtol=1e-3)
    np.testing.assert_allclose(pick(modes, "T")[:2], torsion, rtol=1e-3)
    np.testing.assert_allclose(pick(modes, "EXT")[:1], axial, rtol=1e-3)


def test_free_free_bending_and_rigid_body_modes(strip_props):
    sec, p = strip_props
    model, ids = straight_beam(40, L, sec)
    modes = modes_of(model, {}, n=12)
    assert np.sum(np.abs(modes.frequencies_hz) < 1e-3) == 6  # six rigid-body modes at 0 Hz
    mA = AL.rho * p["A"]
    flap = BETA_FREE**2 * np.sqrt(AL.E * p["Iy"] / (mA * L**4)) / (2 * np.pi)
    np.testing.assert_allclose(pick(modes, "OOP")[:3], flap, rtol=1e-3)
    assert all(lab.startswith("RB") for lab in modes.labels[:6])


def test_frequency_error_converges_with_mesh_refinement(strip_props):
    sec, p = strip_props
    exact = BETA_CANTILEVER[2] ** 2 * np.sqrt(AL.E * p["Iy"] / (AL.rho * p["A"] * L**4)) / (2 * np.pi)
    errors = []
    for n in (3, 6, 12, 24):
        model, ids = straight_beam(n, L, sec)
        f = pick(modes_of(model, {int(ids[0]): "123456"}, n=10), "OOP")[2]
        errors.append(abs(f - exact) / exact)
    errors = np.array(errors)
    assert np.all(np.diff(errors) < 0)
    rates = np.log2(errors[:-1] / errors[1:])
    assert rates[-1] > 3.5  # cubic Hermite elements with consistent mass: O(h^4) in frequency


def test_timoshenko_shear_lowers_frequency_of_a_deep_beam():
    """A deep beam: shear deformation lowers the second bending frequency as Timoshenko theory says."""
    deep = fg.RectangularSection(width=0.05, height=0.3, shear=True)
    eb = fg.RectangularSection(width=0.05, height=0.3, shear=False)
    f = []
    for sec in (deep, eb):
        model, ids = straight_beam(60, 1.5, sec, rotary_inertia=True)
        f.append(pick(modes_of(model, {int(ids[0]): "123456"}, n=12), "OOP")[:2])
    assert f[0][1] < 0.95 * f[1][1]
    assert f[0][0] < f[1][0]


def test_square_cantilever_finds_both_members_of_every_repeated_pair():
    """A square section bends alike in both planes: every bending frequency is double. The sparse
    eigensolver (no margin of extra pairs for a clamped structure) must return both copies,
    from any starting vector, as the Euler-Bernoulli closed form and the dense solution say."""
    sec = fg.RectangularSection(width=0.02, height=0.02, shear=False)
    model, ids = straight_beam(60, L, sec)
    cfg = fg.Configuration("clamped", fixed={int(ids[0]): "123456"})
    state = fg.solve_linear_static(model, cfg)
    p = sec.properties()
    bending = BETA_CANTILEVER**2 * np.sqrt(AL.E * p["Iy"] / (AL.rho * p["A"] * L**4)) / (2 * np.pi)
    system = state.system
    M = system.mass_matrix(state.positions, state.rotations)
    K = system.newton_matrix(system.evaluate(state.positions, state.rotations, 1.0, assemble=False), M, 0.0)
    dense = scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True)[:20]
    assert K.shape[0] > fg.fem.modes.DENSE_LIMIT  # the sparse path is the one tested
    for _ in range(3):  # ARPACK starts from a different random vector each call
        modes = fg.solve_modes(state, 20, label=False)
        np.testing.assert_allclose(modes.eigenvalues, dense, rtol=1e-6)  # a missed copy: O(1) error
        f = modes.frequencies_hz
        np.testing.assert_allclose(f[0:6:2], bending, rtol=1e-3)
        np.testing.assert_allclose(f[1:6:2], bending, rtol=1e-3)


def test_modes_are_mass_orthonormal_on_every_eigensolver_path(strip_props):
    """phi^T M phi = I for the sparse (clamped and free) and the dense eigensolver paths."""
    sec, _ = strip_props
    for n_el, fixed in ((60, "123456"), (60, None), (10, "123456")):
        model, ids = straight_beam(n_el, L, sec)
        cfg = fg.Configuration("c", fixed={int(ids[0]): fixed} if fixed else {})
        state = fg.solve_linear_static(model, cfg)
        system = state.system
        M = system.mass_matrix(state.positions, state.rotations)
        K = system.newton_matrix(system.evaluate(state.positions, state.rotations, 1.0, assemble=False), M, 0.0)
        clamped = fixed is not None
        lam, phi = fg.fem.modes.real_modes(K, M, 12, clamped=clamped)
        assert (K.shape[0] > fg.fem.modes.DENSE_LIMIT) == (n_el == 60)
        np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(12), atol=1e-10)
        np.testing.assert_allclose(phi.T @ (K @ phi), np.diag(lam), atol=1e-8 * max(abs(lam).max(), 1.0))


def test_free_free_elastic_eigenvalues_agree_with_the_dense_solution(strip_props):
    """A free structure's rigid-body eigenvalues are zero only to round-off (eps * lambda_max):
    the sparse shift-invert must keep its shift clear of them, or the elastic eigenvalues lose
    accuracy (with a shift of -(2 pi 0.01 Hz)^2 they were off by up to 3e-4 on this strip)."""
    sec, _ = strip_props
    model, ids = straight_beam(60, L, sec)
    state = fg.solve_linear_static(model, fg.Configuration("free", fixed={}))
    system = state.system
    M = system.mass_matrix(state.positions, state.rotations)
    K = system.newton_matrix(system.evaluate(state.positions, state.rotations, 1.0, assemble=False), M, 0.0)
    everything = scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True)
    dense = everything[6:16]
    # The dense reference's own error is up to eps * lambda_max in every eigenvalue (its backward
    # error; lambda_max ~ 5e13 here, 1.7e-7 of the first elastic eigenvalue measured against the
    # sparse solution on one machine and less on another): ten times that, 6e-5 of the first
    # elastic eigenvalue, which the faulty shift missed by 3e-4.
    atol = 10 * np.finfo(float).eps * everything[-1]
    assert atol < 1e-4 * dense[0]
    lam = fg.solve_modes(state, 16, label=False).eigenvalues
    np.testing.assert_allclose(lam[:6], 0.0, atol=1e-6 * dense[0])
    np.testing.assert_allclose(lam[6:], dense, rtol=1e-9, atol=atol)


def test_modes_with_superlu_forced_agree_with_the_default_path(strip_props):
    """solve_modes(cholmod=False) takes SuperLU's shift-invert (the path without a fast backend). The
    two agree within the sum of their eigenvalues' error bounds, |K phi - lam M phi| / |M phi| for
    M-normalised phi (symmetric-definite Bauer-Fike; about 3e-8 relative on mode 3 here, where
    PARDISO and SuperLU differ by 1.2e-9) and to 1e-9 everywhere else."""
    sec, _ = strip_props
    model, ids = straight_beam(60, L, sec)
    state = fg.solve_linear_static(model, fg.Configuration("clamped", fixed={int(ids[0]): "123456"}))
    default = fg.solve_modes(state, 12, label=False)
    forced = fg.solve_modes(state, 12, label=False, cholmod=False)
    system = state.system
    K = system.evaluate(state.positions, state.rotations, 1.0).tangent
    M = system.mass_matrix(state.positions, state.rotations)

    def bound(modes):
        out = []
        for lam, shape in zip(modes.eigenvalues, modes.shapes):
            phi = system.reduce_displacement(shape.reshape(-1))
            out.append(np.linalg.norm(K @ phi - lam * (M @ phi)) / np.linalg.norm(M @ phi))
        return np.array(out)

    allowed = np.maximum(bound(default) + bound(forced), 1e-9 * np.abs(default.eigenvalues))
    assert np.all(np.abs(forced.eigenvalues - default.eigenvalues) <= allowed)
    assert np.all(allowed <= 1e-7 * np.abs(default.eigenvalues))  # the bound itself is tight
