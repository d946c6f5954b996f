"""Grounded springs used as clamps (1e6 to 1e18 N/m): the answer tends to the clamped one and never
degrades into garbage. Before, the shift-invert factorisations and the dense eigensolver lost the
modes once the spring was ~1e9 times stiffer than the structure (a 20-element strip: first
frequency 2.4 % off at 1e12 N/m, negative at 1e13; the issue's deck: 4.6e-4 at 1e15, +104 % at
1e18). Measured now: the frequencies' difference from the clamped strip falls as 1/k (1.4e-3 at
1e6 N/m) to 1e-9 (dense) / 4e-9 (sparse, 40 elements) and is exactly zero once every DOF is held."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import FlexGVTWarning

from fem_builders import straight_beam

RATES = 10.0 ** np.arange(6, 19, 2)


def _solve(n_el, spring=None, clamp=False, frame=None):
    model, ids = straight_beam(n_el)
    if clamp:
        cfg = fg.Configuration("clamped", fixed={int(ids[0]): "123456"}, gravity=1.0)
    else:
        cfg = fg.Configuration("spring", gravity=1.0,
                               springs=(fg.Spring.make(int(ids[0]), None, stiffness=np.full(6, spring), frame=frame),))
    state = fg.solve_static(model, cfg)
    return state, fg.solve_modes(state, 6, label=False).frequencies_hz


@pytest.mark.parametrize("n_el", [20, 40])  # the dense (120 DOFs) and the sparse (240) eigensolver paths
def test_stiff_grounded_springs_converge_to_the_clamped_answer(n_el):
    clamped, f_ref = _solve(n_el, clamp=True)
    tip_ref = clamped.displacements[-1, 2]
    errors, tips = [], []
    for k in RATES:
        with warnings.catch_warnings():
            warnings.simplefilter("error", FlexGVTWarning)  # every DOF either held or harmless as a spring
            state, f = _solve(n_el, k)
        errors.append(np.max(np.abs(f - f_ref) / f_ref))
        tips.append(abs(state.displacements[-1, 2] - tip_ref) / abs(tip_ref))
    errors, tips = np.array(errors), np.array(tips)
    # The spring's own compliance: the difference falls as 1/k, down to the eigensolver's round-off.
    assert np.all(errors <= 2 * errors[0] * RATES[0] / RATES + 2e-8), errors
    assert np.all(tips <= 2 * tips[0] * RATES[0] / RATES + 1e-12), tips
    assert errors[0] > 1e-3  # a 1e6 N/m spring is a physical spring, not a clamp
    assert errors[-1] == 0.0 and tips[-1] == 0.0  # 1e18 N/m: every DOF held, the clamped model


def test_held_dofs_are_the_ones_far_stiffer_than_the_structure():
    state, _ = _solve(20, 1e14)
    # Strip along y: its axial (y, EA/L = 1.4e8 N/m) and in-plane (x, 6e7 N/m) stiffness stay within
    # 1e8 of 1e14; bending (z, 2e5 N/m) and all three rotations (<= 1.2e5 N m/rad) do not.
    assert state.system.spring_clamped.tolist() == [2, 3, 4, 5]
    assert fg.fem.system.SPRING_CLAMP_RATIO == 1e8


def test_stiff_springs_that_cannot_be_held_are_warned():
    c, s = np.cos(0.3), np.sin(0.3)
    turned = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    with pytest.warns(FlexGVTWarning, match="more than 1e\\+12 times stiffer.*Fix the DOFs"):
        state, _ = _solve(20, 1e18, frame=turned)
    assert state.system.spring_clamped.tolist() == [2]  # z held; x, y and rotations turned with the frame: kept
    model, ids = straight_beam(20)
    other = model.add_nodes([[0.0, 1.5, 0.0]])
    model.add_spring(int(ids[-1]), int(other[0]), stiffness=np.full(6, 1e18))
    with pytest.warns(FlexGVTWarning, match="cannot hold those DOFs as constraints"):
        fg.fem.System(model, fg.Configuration("joint", fixed={int(ids[0]): "123456"}))


def test_a_spring_made_stiff_between_warm_started_solves_holds_its_dofs():
    model, ids = straight_beam(20)
    model.add_spring(int(ids[0]), None, stiffness=np.full(6, 1e6))
    cfg = fg.Configuration("spring", gravity=1.0)
    soft = fg.solve_static(model, cfg)
    model.set_spring(0, stiffness=np.full(6, 1e18))
    stiff = fg.solve_static(model, cfg, start=soft)
    assert len(stiff.system.spring_clamped) == 6
    np.testing.assert_array_equal(stiff.positions[0], model.xyz[0])  # the held root at rest, not where 1e6 left it
    np.testing.assert_array_equal(stiff.rotations[0], np.eye(3))
    clamped, _ = _solve(20, clamp=True)
    # Both Newton solutions meet the residual tolerance 1e-8: about 1e-9 m apart on 0.3 m.
    np.testing.assert_allclose(stiff.positions, clamped.positions, rtol=0, atol=1e-8)
