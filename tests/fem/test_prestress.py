"""Pre-stressed modes: axial load, pendulum on a cord, plunge on springs, damped support system."""

import numpy as np
import pytest

import flexgvt as fg

from fem_builders import AL, straight_beam

SEC = fg.RectangularSection(width=0.05, height=0.003, shear=False)
L = 1.5


def pinned_beam_modes(P: float, n_modes: int = 4):
    """Simply supported strip (flatwise), axial force P at the sliding end (tension > 0)."""
    model, ids = straight_beam(40, L, SEC)
    # Beam along y: pin both ends (x, z and the twist about y held), slide axially at the far end.
    cfg = fg.Configuration("axial", fixed={int(ids[0]): "1235", int(ids[-1]): "135"},
                           forces=[fg.NodalLoad(int(ids[-1]), force=(0.0, P, 0.0))])
    state = fg.solve_static(model, cfg)
    modes = fg.solve_modes(state, n_modes)
    oop = modes.frequencies_hz[np.argmax(modes.energy_fractions[:, :4], axis=1) == 0]
    return oop, state


EI = AL.E * SEC.properties()["Iy"]
P_EULER = np.pi**2 * EI / L**2


@pytest.mark.parametrize("ratio", [-0.6, -0.3, 0.5, 2.0])
def test_axial_load_shifts_bending_frequency_as_closed_form(ratio):
    f0 = pinned_beam_modes(0.0)[0][0]
    mA = AL.rho * SEC.properties()["A"]
    exact0 = np.pi / (2 * L**2) * np.sqrt(EI / mA)
    assert f0 == pytest.approx(exact0, rel=1e-3)
    f = pinned_beam_modes(ratio * P_EULER)[0][0]
    # Pinned-pinned: omega^2 = omega0^2 (1 + P / P_euler), tension positive.
    assert f == pytest.approx(exact0 * np.sqrt(1 + ratio), rel=2e-3)


def test_frequency_vanishes_at_the_euler_load():
    f0 = pinned_beam_modes(0.0)[0][0]
    f, state = pinned_beam_modes(-P_EULER)
    assert abs(f[0]) < 0.02 * f0


def test_pendulum_frequency_of_a_mass_on_a_cord():
    model = fg.Model("pendulum")
    (node,) = model.add_nodes([[0.0, 0.0, 0.0]])
    m, k, l0 = 2.0, 5000.0, 1.2
    model.add_mass(node, m, inertia=1e-3)
    cord = fg.Cord(node=int(node), anchor=(0.0, 0.0, 1.2), stiffness=k, unstretched_length=l0)
    cfg = fg.Configuration("hung", suspension=[cord], gravity=1.0)
    state = fg.solve_static(model, cfg)
    length = l0 + m * 9.80665 / k
    assert state.cord_length[0] == pytest.approx(length, rel=1e-9)
    modes = fg.solve_modes(state, 6)
    f = np.sort(modes.frequencies_hz[modes.frequencies_hz > 1e-3])
    np.testing.assert_allclose(f[:2], np.sqrt(9.80665 / length) / (2 * np.pi), rtol=1e-6)
    assert f[2] == pytest.approx(np.sqrt(k / m) / (2 * np.pi), rel=1e-6)


def test_plunge_and_pitch_of_a_rigid_strip_on_two_springs():
    """A strip made rigid by a rigid link, on two vertical springs at its ends, under gravity:
    plunge sqrt(2k/m) and pitch about its middle sqrt(6k/m) (consistent mass: I = m L^2 / 12)."""
    model, ids = straight_beam(30, L, SEC)
    mid = int(ids[15])
    model.add_rigid_link(mid, [int(i) for i in ids if i != mid])
    k = 17.0
    for node in (ids[0], ids[-1]):
        model.add_spring(int(node), None, stiffness=[0, 0, k, 0, 0, 0])
    cfg = fg.Configuration("sprung", fixed={mid: "1256"}, gravity=1.0)
    state = fg.solve_static(model, cfg)
    m = AL.rho * SEC.properties()["A"] * L
    assert state.positions[15, 2] == pytest.approx(-m * 9.80665 / (2 * k), rel=1e-6)
    modes = fg.solve_modes(state, 2)
    np.testing.assert_allclose(modes.frequencies_hz, np.sqrt(np.array([2, 6]) * k / m) / (2 * np.pi), rtol=1e-6)
    assert modes.labels[0] == "RB plunge"


def test_support_structure_system_damped_modes_match_method_formulas():
    """docs/method.md section 2: two masses on supports joined by the structure; complex modes give
    w_sup, z_sup (in phase) and w_m, z_m (out of phase)."""
    m, k_sup, c_sup, k_st, c_st = 0.8, 5.06, 0.28, 40.0, 0.05
    model = fg.Model("support-structure")
    a, b = model.add_nodes([[0, -1, 0], [0, 1, 0]])
    for n in (a, b):
        model.add_mass(int(n), m, inertia=1.0)
        model.add_spring(int(n), None, stiffness=[0, 0, k_sup, 0, 0, 0], damping=[0, 0, c_sup, 0, 0, 0])
    model.add_spring(int(a), int(b), stiffness=[0, 0, k_st / 2, 0, 0, 0], damping=[0, 0, c_st / 2, 0, 0, 0])
    cfg = fg.Configuration("2dof", fixed={int(a): "12456", int(b): "12456"})
    modes = fg.solve_modes(fg.solve_linear_static(model, cfg), 2)
    w_sup = np.sqrt(k_sup / m)
    w_m = np.sqrt((k_sup + k_st) / m)
    np.testing.assert_allclose(modes.frequencies_hz * 2 * np.pi, [w_sup, w_m], rtol=1e-9)
    np.testing.assert_allclose(modes.damping_ratio, [c_sup / (2 * m * w_sup), (c_sup + c_st) / (2 * m * w_m)],
                               rtol=1e-9)
    zeta = modes.damping_ratio
    np.testing.assert_allclose(modes.damped_frequencies_hz * 2 * np.pi,
                               [w_sup * np.sqrt(1 - zeta[0] ** 2), w_m * np.sqrt(1 - zeta[1] ** 2)], rtol=1e-9)


def test_lateral_torsional_buckling_of_a_tip_loaded_strip():
    """In-plane tip force on the cantilever strip: the lowest eigenvalue of the pre-stressed tangent
    vanishes at Timoshenko's P_cr = 4.013 sqrt(EI_weak GJ) / L^2, raised by the pre-buckling factor
    1 / sqrt((1 - EI_weak/EI_strong)(1 - GJ/EI_strong)). This is the bending-torsion coupling that
    self-weight produces on very flexible strips."""
    p = SEC.properties()
    A, B, C = AL.E * p["Iz"], AL.E * p["Iy"], AL.shear_modulus * p["J"]
    p_cr = 4.013 * np.sqrt(B * C) / L**2 / np.sqrt((1 - B / A) * (1 - C / A))

    def lowest_eigenvalue(P):
        model, ids = straight_beam(60, L, SEC)
        cfg = fg.Configuration("tip", fixed={int(ids[0]): "123456"},
                               forces=[fg.NodalLoad(int(ids[-1]), force=(P, 0.0, 0.0))])
        return fg.solve_modes(fg.solve_static(model, cfg), 2).eigenvalues[0]

    loads = np.array([0.8, 0.9, 0.95]) * p_cr
    fit = np.polyfit(loads, [lowest_eigenvalue(P) for P in loads], 2)
    crossing = min(r.real for r in np.roots(fit) if abs(r.imag) < 1e-9 and r.real > 0.5 * p_cr)
    assert crossing == pytest.approx(p_cr, rel=5e-3)


def test_free_strip_with_a_damper_complex_modes_count_each_rigid_motion_once():
    """A free strip with a grounded damper at its tip (no stiffness): each of the six rigid
    motions is one zero root (the state space holds it twice), the damped rigid motion adds its
    overdamped root, and the elastic roots agree with the dense state-space solution."""
    import scipy.linalg as sla

    from flexgvt.model.components import Spring

    sec = fg.RectangularSection(width=0.05, height=0.003, shear=False)
    model, ids = straight_beam(40, 1.5, sec)
    damper = Spring.make(int(ids[-1]), None, stiffness=0.0, damping=[0, 0, 0.05, 0, 0, 0])
    state = fg.solve_linear_static(model, fg.Configuration("free, damped", fixed={}, springs=(damper,)))
    modes = fg.solve_modes(state, 12, label=False)
    s = modes.eigenvalues
    assert np.sum(s == 0) == 6
    system = state.system
    x, R = state.positions, state.rotations
    M = system.mass_matrix(x, R).toarray()
    C = system.damping_matrix(x, R).toarray()
    K = system.newton_matrix(system.evaluate(x, R, 1.0, assemble=False), system.mass_matrix(x, R), 0.0).toarray()
    n = K.shape[0]
    assert n > fg.fem.modes.DENSE_LIMIT // 2  # the sparse path is the one tested
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    roots = sla.eig(A, B, right=False)
    elastic = roots[np.isfinite(roots) & (roots.imag > 1.0)]
    elastic = elastic[np.argsort(elastic.imag)][:4]
    overdamped = roots[np.isfinite(roots) & (np.abs(roots.imag) < 1e-6) & (roots.real < -0.1)]  # not round-off
    np.testing.assert_allclose(s[6], overdamped.real.max(), rtol=1e-6)  # the rigid plunge under the damper
    np.testing.assert_allclose(s[7:11], elastic, rtol=1e-7)
    # zeta = -Re(s) / |s| carries the roots' relative error as an absolute one
    np.testing.assert_allclose(modes.damping_ratio[7:11], -elastic.real / np.abs(elastic), rtol=0, atol=1e-7)


def test_strip_hung_on_its_axis_with_its_centre_of_mass_off_it_rolls_until_held():
    """The 3.66 m strip on two cords along its axis, its leading-edge sensors moved 10 mm further
    forward: flat, nothing restrains the roll the offset weight pushes; sagged, the strip is held.
    The solve ramps the load with the roll held by a spring, then releases it: the equilibrium
    has its centre of mass under the cords' line (vertical cords carry no chordwise force) and
    every mode at a positive frequency. Ramping freely rolled it edgewise (an unstable branch)."""
    from flexgvt.fem.massprops import system_mass_properties
    case = fg.cases.strip_366()
    model = case.model
    for k in range(0, 26, 2):
        model.set_mass(k, offset=np.array(model.masses[k].offset) + (-0.01, 0.0, 0.0))
    state = fg.solve_static(model, case.configurations["outboard"])
    cg = system_mass_properties(state.system, state.positions, state.rotations).cg
    assert abs(cg[0]) < 1e-6  # the cords' attachments and anchors lie at x = 0
    z = state.positions[:, 2]
    assert 0.55 < z.max() - z.min() < 0.6  # bowed flat-wise as the symmetric strip (0.57 m), not edgewise
    roll = np.abs(state.rotations[:, 0, 2]).max()  # the section normal's chordwise tilt
    assert 1e-5 < roll < 0.01
    f = fg.solve_modes(state, 8, damped=False, label=False).frequencies_hz
    assert np.all(f > 0.2)


def test_top_heavy_strip_on_its_axis_is_refused():
    """The strip with 1 kg on a 2 m mast above mid-span (5 mm off the axis): its centre of mass sits
    above the cords' line, so the equilibrium left when the holding spring is released is unstable
    (it would roll over): refused, naming the cause."""
    from flexgvt.errors import SingularModelError
    case = fg.cases.strip_366()
    case.model.add_mass(case.references["mid_node"], 1.0, offset=(0.005, 0.0, 2.0))
    with pytest.raises(SingularModelError, match="rotation about y.*is unstable"):
        fg.solve_static(case.model, case.configurations["outboard"])
