"""The assembled tangent equals the finite-difference derivative of the residual (relative error
below 1e-6) at a deformed, non-equilibrium state, with every component type present."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.fem.beam import beam_forces
from flexgvt.fem.rotations import expm_so3
from flexgvt.fem.system import System

from fem_builders import AL, perturbed_state, tangent_error


def curved_model(with_links, springs: bool = True):
    """with_links: False, True (a full rigid link), "partial" (a full link and a '13' link
    whose dependent keeps its own rotations and y translation) or "interpolation" (a full link
    and an RBE3-like interpolation link carrying an offset mass and a load, plus an MPC)."""
    model = fg.Model("tangent check")
    s = np.linspace(0, 1, 9)
    ids = model.add_nodes(np.c_[0.2 * np.sin(2 * s), s, 0.1 * s**2])
    sec = fg.RectangularSection(width=0.05, height=0.01, shear=True)
    model.add_beams(np.c_[ids[:-1], ids[1:]], AL, sec, orientation=(0.3, 0, 1))
    model.add_mass(int(ids[4]), 0.3, offset=(0.05, 0.01, 0.02), inertia=[1e-4, 2e-4, 3e-4])
    model.add_mass(int(ids[8]), 0.2, offset=(-0.03, 0.0, 0.04))
    if springs:
        model.add_spring(int(ids[0]), None, stiffness=[1e5, 2e5, 3e5, 40, 50, 60])
        model.add_spring(int(ids[3]), int(ids[6]), stiffness=[1e3, 2e3, 3e3, 4, 5, 6])
    if with_links:
        (extra,) = model.add_nodes([[0.1, 0.5, 0.2]])
        model.add_mass(int(extra), 0.5, offset=(0.02, 0.0, 0.0))
        model.add_rigid_link(int(ids[5]), [int(extra)])
        if with_links == "partial":
            (loose,) = model.add_nodes([[0.3, 0.7, -0.1]])
            model.add_mass(int(loose), 0.4, offset=(0.0, 0.03, 0.01), inertia=[1e-4, 1e-4, 1e-4])
            model.add_rigid_link(int(ids[6]), [int(loose)], components="13")
            model.add_spring(int(loose), None, stiffness=[0, 300.0, 0, 2.0, 3.0, 4.0])
        if with_links == "interpolation":
            (ref,) = model.add_nodes([[0.25, 0.45, 0.15]])
            model.add_mass(int(ref), 0.6, offset=(0.02, -0.01, 0.03), inertia=[2e-4, 1e-4, 3e-4])
            model.add_interpolation(int(ref), [int(i) for i in ids[2:7]], weights=[1.0, 2.0, 0.5, 1.5, 1.0])
            model.add_constraint([(int(ids[1]), 3, 2.0), (int(ids[2]), 1, -1.0), (int(ids[7]), 2, 0.5)])
            model.add_constraint([(int(ids[3]), 5, 1.0), (int(ids[4]), 4, -0.7), (int(ids[2]), 3, 0.2)])
    cords = [fg.Cord(node=int(ids[8]), anchor=(0.3, 1.1, 1.5), stiffness=800.0, unstretched_length=1.0,
                     offset=(0.01, 0.0, 0.02))]
    forces = [fg.NodalLoad(int(ids[7]), force=(1.0, 2.0, -3.0), moment=(0.1, 0.2, 0.3))]
    if with_links == "interpolation":
        forces.append(fg.NodalLoad(int(ref), force=(-4.0, 1.0, 2.0), moment=(0.3, -0.2, 0.1)))
    cfg = fg.Configuration("check", suspension=cords, gravity=3.0, fixed={int(ids[0]): "12"}, forces=forces)
    return model, cfg


@pytest.mark.parametrize("with_links", [False, True, "partial", "interpolation"])
def test_tangent_matches_finite_differences(with_links):
    model, cfg = curved_model(with_links)
    system = System(model, cfg)
    err, K = tangent_error(system, *perturbed_state(system, 3), lam=0.7)
    assert err < 1e-6
    # The tangent is genuinely non-symmetric away from equilibrium: the check is not trivial.
    assert np.abs(K - K.T).max() / np.abs(K).max() > 1e-8


def test_rigid_body_motion_gives_zero_internal_force():
    model, _ = curved_model(True, springs=False)  # springs act in fixed axes (see model.Spring)
    system = System(model, fg.Configuration("free"))
    x0, R0 = system.undeformed
    Q = expm_so3(np.array([0.7, -1.9, 2.4]))
    x = x0 @ Q.T + np.array([3.0, -2.0, 5.0])
    R = np.broadcast_to(Q, R0.shape).copy()
    g = system.evaluate(x, R, 0.0, tangent=False).internal
    scale = AL.E * 0.05 * 0.01 * 1e-3  # force of a 1e-3 strain
    assert np.abs(g).max() < 1e-9 * scale


def test_rotated_structure_has_the_same_frequencies_loaded_and_unloaded():
    case = fg.cases.cantilever_strip(n_elements=30)
    Q = expm_so3(np.array([0.4, 1.1, -0.8]))
    rotated = fg.Model("rotated strip")
    rotated.add_nodes(case.model.xyz @ Q.T, ids=case.model.node_ids)
    for group in case.model.beams:
        rotated.add_beams(group.nodes, group.material, group.section, orientation=group.orientation @ Q.T,
                          rotary_inertia=group.rotary_inertia, name=group.name)
    for name in ("unloaded", "flatwise_2g"):
        cfg = case.configurations[name]
        f0 = fg.solve_modes(fg.solve_static(case.model, cfg), 8).frequencies_hz
        cfg_r = cfg.with_(gravity_direction=tuple(Q @ np.array(cfg.gravity_direction)))
        f1 = fg.solve_modes(fg.solve_static(rotated, cfg_r), 8).frequencies_hz
        np.testing.assert_allclose(f1, f0, rtol=1e-7)


def test_reference_forces_replace_only_the_stress_dependent_part():
    """Newton's first tangent of an increment takes the last converged state's beam forces in its
    geometric part: with the element's own forces it is the exact tangent, with zero forces the
    (symmetric) material tangent, and it is affine in the reference forces; the residual is exact."""
    model, cfg = curved_model(False)
    system = System(model, cfg)
    rng = np.random.default_rng(5)
    x, R = system.undeformed
    x, R = system.update(x, R, 0.02 * rng.standard_normal(system.n_free) * np.where(system.rotation_mask, 10.0, 1.0))
    beams = system.cm.beams
    own = beam_forces(x, R, beams, False)[2]
    K_exact = beam_forces(x, R, beams, True)[1]
    g_ref, K_own, _ = beam_forces(x, R, beams, True, reference_forces=own)
    np.testing.assert_allclose(K_own, K_exact, rtol=0, atol=1e-9 * np.abs(K_exact).max())
    np.testing.assert_array_equal(g_ref, beam_forces(x, R, beams, False)[0])
    K_zero = beam_forces(x, R, beams, True, reference_forces=np.zeros_like(own))[1]
    scale = np.abs(K_zero).max()
    assert np.abs(K_zero - K_zero.transpose(0, 2, 1)).max() < 1e-12 * scale
    assert np.abs(K_exact - K_zero).max() > 1e-6 * scale  # the state is stressed: the check is not trivial
    other = 3.0 * rng.standard_normal(own.shape) * np.abs(own).max()
    K_a = beam_forces(x, R, beams, True, reference_forces=other)[1]
    K_b = beam_forces(x, R, beams, True, reference_forces=2 * other)[1]
    np.testing.assert_allclose(K_b - K_a, K_a - K_zero, rtol=0, atol=1e-9 * np.abs(K_a).max())
    with pytest.raises(ValueError, match="reference_forces"):
        beam_forces(x, R, beams, True, reference_forces=own[:-1])
