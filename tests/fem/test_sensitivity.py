"""Parameter derivatives of residual, tangent and mass agree with finite differences."""

import numpy as np
import pytest
from sensitivity_reference import beam_parameter_derivative, frequency_derivatives

import flexgvt as fg
from flexgvt.fem.system import System


def strip(**kw):
    return fg.cases.cantilever_strip(n_elements=30, **kw)


def perturbed(parameter, h):
    """The cantilever strip with one parameter of region 2 scaled by (1 + h)."""
    case = strip()
    model = fg.Model("perturbed")
    model.add_nodes(case.model.xyz, ids=case.model.node_ids)
    for g in case.model.beams:
        mat, sec = g.material, g.section
        if g.name == "region2":
            if parameter in ("E", "rho"):
                mat = fg.Material(mat.name, E=mat.E * (1 + h * (parameter == "E")), nu=mat.nu,
                                  rho=mat.rho * (1 + h * (parameter == "rho")))
            else:
                sec = fg.RectangularSection(width=sec.width * (1 + h * (parameter == "width")),
                                            height=sec.height * (1 + h * (parameter == "height")))
        model.add_beams(g.nodes, mat, sec, orientation=g.orientation, rotary_inertia=g.rotary_inertia, name=g.name)
    return model, case


@pytest.mark.parametrize("parameter", ["E", "rho", "width", "height"])
def test_parameter_derivatives_match_finite_differences(parameter):
    case = strip()
    cfg = case.configurations["flatwise_2g"]
    state = fg.solve_static(case.model, cfg)
    d = beam_parameter_derivative(state, "region2", parameter)
    base = {"E": 70e9, "rho": 2700.0, "width": 0.05, "height": 0.003}[parameter]
    h = 1e-6
    out = []
    for sign in (1, -1):
        model, _ = perturbed(parameter, sign * h)
        system = System(model, cfg)
        ev = system.evaluate(state.positions, state.rotations, state.load_factor)
        out.append((ev.internal - ev.external, ev.tangent.toarray(), system.mass_matrix(state.positions,
                                                                                        state.rotations).toarray()))
    fd = [(a - b) / (2 * h * base) for a, b in zip(out[0], out[1])]
    for name, exact, approx in zip(("residual", "K", "M"), (d.residual, d.stiffness.toarray(), d.mass.toarray()), fd):
        scale = max(np.abs(approx).max(), 1e-300)
        assert np.abs(exact - approx).max() < 1e-5 * scale, name


def _with_region_modulus(scale):
    c = fg.cases.cantilever_strip(n_elements=30)
    model = fg.Model()
    model.add_nodes(c.model.xyz, ids=c.model.node_ids)
    for g in c.model.beams:
        mat = g.material
        if g.name == "region1":
            mat = fg.Material(mat.name, E=mat.E * scale, nu=mat.nu, rho=mat.rho)
        model.add_beams(g.nodes, mat, g.section, orientation=g.orientation, rotary_inertia=False, name=g.name)
    return model, c.configurations["unloaded"]


def test_frequency_derivative_matches_finite_differences():
    model, cfg = _with_region_modulus(1.0)
    state = fg.solve_static(model, cfg)
    df = frequency_derivatives(fg.solve_modes(state, 5), beam_parameter_derivative(state, "region1", "E"))
    # Eigenvalues of a strip (EA/L ~ 1e10 against bending) carry ~1e-8 relative noise: a step of
    # 1e-3 keeps both that noise and the O(h^2) truncation near 1e-6.
    h = 1e-3
    f = [fg.solve_modes(fg.solve_static(*_with_region_modulus(1 + s * h)), 5).frequencies_hz for s in (1, -1)]
    np.testing.assert_allclose(df, (f[0] - f[1]) / (2 * h * 70e9), rtol=1e-5)
