"""Design variables on tapered beam groups: material values are updated like a uniform group's
(exact partial derivatives, whole-solve Jacobian against finite differences); section values of a
tapered group are refused with a message that says what to do."""

import numpy as np
import pytest
from sensitivity_reference import beam_parameter_derivative
from test_gradients import TIGHT, _check

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.errors import ModelError
from flexgvt.updating.derivatives import partial_derivatives

AL = fg.Material("Al", E=70e9, nu=0.33, rho=2700.0)


def tapered_strip(n=24, length=1.5):
    """A cantilever strip whose outer half tapers (width 50 -> 20 mm, thickness 4 -> 3 mm), tip mass."""
    model = fg.Model("tapered strip")
    s = np.linspace(0, 1, n + 1)
    ids = model.add_nodes(np.c_[0 * s, s * length, 0 * s])
    half = n // 2
    model.add_beams(np.c_[ids[:half], ids[1:half + 1]], AL, fg.RectangularSection(0.05, 0.004, shear=False),
                    rotary_inertia=False, name="root")
    for k in range(half, n):
        t = [(s[j] - 0.5) / 0.5 for j in (k, k + 1)]
        a, b = (fg.RectangularSection(0.05 - 0.03 * v, 0.004 - 0.001 * v, shear=False) for v in t)
        model.add_beams([[ids[k], ids[k + 1]]], AL, fg.TaperedSection(a, b), rotary_inertia=False, name="outer")
    model.add_mass(int(ids[-1]), 0.01, offset=(0.01, 0.0, 0.0))
    cfgs = [fg.Configuration("self_weight", fixed={int(ids[0]): "123456"}, gravity=1.0),
            fg.Configuration("unloaded", fixed={int(ids[0]): "123456"}, gravity=0.0)]
    return model, cfgs


@pytest.mark.parametrize("attribute", ["E", "G", "rho"])
def test_partial_derivatives_of_a_tapered_group_match_the_exact_ones(attribute):
    """The updating layer's route (the group's values differentiated by a four-point rule) against
    fem.sensitivity's complex-step derivative of the tapered element's coefficients."""
    model, cfgs = tapered_strip()
    cfg = cfgs[0]
    par = up.Parametrisation(model, [cfg], [up.beam("v", "outer", attribute)])
    work = model.copy()
    par.apply(work, np.ones(1))
    state = fg.solve_static(work, cfg)
    dR, dK, dM = partial_derivatives(par, work, np.ones(1), state, 0)
    ref = beam_parameter_derivative(state, "outer", attribute)
    p0 = par.bindings[0].initial[0]
    ev = state.system.evaluate(state.positions, state.rotations, state.load_factor)
    K = ev.tangent.toarray()
    M = state.system.mass_matrix(state.positions, state.rotations).toarray()
    # floors: the four-point rule's round-off on values that do not change (M with E, K's material part with rho)
    for a, b, floor in ((dR, ref.residual * p0, 1e-13 * np.abs(ev.external).max()),
                        (dK.toarray(), ref.stiffness.toarray() * p0, 1e-13 * np.abs(K).max()),
                        (dM.toarray(), ref.mass.toarray() * p0, 1e-13 * np.abs(M).max())):
        assert np.abs(a - b).max() <= 1e-8 * np.abs(b).max() + floor


def test_jacobian_with_tapered_groups_matches_finite_differences():
    model, cfgs = tapered_strip()
    data = []
    for c in cfgs:
        modes = fg.solve_modes(fg.solve_static(model, c), 6, label=False)
        static = {(int(model.node_ids[-1]), 3): -0.05} if c.gravity else {}
        data.append(up.Measured(c.name, modes.frequencies_hz[:5] * 1.02, static=static))
    variables = [up.beam("E_outer", "outer", "E"), up.beam("rho_outer", "outer", "rho"),
                 up.beam("t_root", "root", "thickness")]
    problem = up.UpdatingProblem(model, cfgs, data, variables, objective=up.Objective(static=1.0),
                                 static_settings=TIGHT)
    _check(problem, np.array([1.03, 0.98, 1.01]))


def test_section_values_of_a_tapered_group_are_refused_with_a_remedy():
    model, cfgs = tapered_strip()
    with pytest.raises(ModelError, match=r"TaperedSection .* use its material's \('E', 'G', 'rho'\)"):
        up.Parametrisation(model, cfgs, [up.beam("w", "outer", "width")])
