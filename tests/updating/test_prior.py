"""The MAP estimate (Objective(prior="bounds")): each variable's bounds give it a Gaussian prior of
the uniform distribution's variance, weighed against the data by the measured frequency scatter."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem import solve_modes, solve_static
from flexgvt.updating import Measured, Objective, beam, update
from flexgvt.updating.variables import Parametrisation


@pytest.fixture(scope="module")
def wing():
    """The X-HALE-like model on its outboard cords; three stiffness variables, two measured modes
    (one direction of the design space the data cannot see)."""
    case = fg.cases.xhale(n_per_section=2)
    cfg = case.configurations["outboard"]
    v = [beam("E_in", ["wing_L1", "wing_R1"], "E", bounds=(0.75, 1.25)),
         beam("E_out", ["wing_L2", "wing_R2", "wing_L3", "wing_R3"], "E", bounds=(0.75, 1.25)),
         beam("G_wing", ["wing_*"], "G", bounds=(0.8, 1.2))]
    truth = case.model.copy("truth")
    Parametrisation(case.model, [cfg], v).apply(truth, np.array([1.06, 0.95, 1.04]))
    modes = solve_modes(solve_static(truth, cfg), 16, damped=False)
    f = modes.frequencies_hz
    f = f[(f > 0) & (modes.energy_fractions[:, 4] < 0.5)][:2]
    return case.model, cfg, v, f


def test_map_answer_is_stationary_on_data_plus_prior(wing):
    model, cfg, v, f = wing
    sd = 0.005 * f
    res = update(model, [cfg], [Measured(cfg.name, f, frequency_std_hz=sd)], v, unidentifiable="free",
                 objective=Objective(prior="bounds"), tolerance=1e-12, max_iterations=60)
    # The prior rows: sigma / s_k (x - 1), sigma = 0.5 % (one relative frequency residual), s_k the
    # uniform distribution's standard deviation over the bounds.
    w = 0.005 / (np.array([0.5, 0.5, 0.4]) / np.sqrt(12))
    final = res.final
    assert final.n_prior == 3 and len(final.data_residuals) == len(final.residuals) - 3
    assert np.allclose(final.residuals[-3:], w * (res.x - 1), rtol=1e-12, atol=0)
    assert np.allclose(final.jacobian[-3:], np.diag(w), rtol=1e-12, atol=0)
    # MAP stationarity: J^T r + W^2 (x - 1) = 0 within the optimiser's tolerance, against the
    # data gradient's size at the start.
    g_data = final.data_jacobian.T @ final.data_residuals
    g_prior = w**2 * (res.x - 1)
    g0 = res.initial.data_jacobian.T @ res.initial.data_residuals
    assert np.linalg.norm(g_data + g_prior) < 1e-6 * np.linalg.norm(g0)
    assert np.linalg.norm(g_prior) > 1e-3 * np.linalg.norm(g0)  # the prior does act: the data alone are not at rest
    # What the data see is judged without the prior's rows: two modes, three variables -> rank 2.
    assert res.identifiability["rank"] == 2 and res.identifiability["n_residuals"] == len(final.data_residuals)


def test_map_needs_the_measured_scatter(wing):
    model, cfg, v, f = wing
    with pytest.raises(ModelError, match="prior"):
        update(model, [cfg], [Measured(cfg.name, f)], v, objective=Objective(prior="bounds"))
    with pytest.raises(ModelError, match="prior 'uniform' must be one of"):
        Objective(prior="uniform")
