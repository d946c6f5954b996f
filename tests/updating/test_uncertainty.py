"""Confidence bounds of predictions (flexgvt.updating.uncertainty): the stated coverage where the
covariance is exact (linear-Gaussian), the predicted modes' sensitivities against differences, and
the coverage on an FE case whose truth the variables can reach (noisy frequencies, several seeds)."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.fem import solve_modes, solve_static
from flexgvt.model import Configuration
from flexgvt.updating import Measured, UncertaintySettings, beam, update
from flexgvt.updating.uncertainty import (PredictedModes, parameter_covariance, prior_std, propagate,
                                          sample_posterior, sampled_interval)
from flexgvt.updating.variables import Parametrisation


def _linear_coverage(known: bool, rank_deficient: bool = False, trials: int = 2000, seed: int = 3, scale: bool = False):
    """Fraction of trials whose true predictions g x lie in the 95 % interval: y = J x + e, e ~ N(0, s^2)."""
    rng = np.random.default_rng(seed)
    m, n, sigma = (3, 5, 0.05) if rank_deficient else (12, 4, 0.05)
    J = rng.standard_normal((m, n))
    G = rng.standard_normal((3, n))
    prior = np.full(n, 0.2) if rank_deficient else None
    hits = np.zeros(3)
    for _ in range(trials):
        x = prior * rng.standard_normal(n) if rank_deficient else rng.standard_normal(n)
        y = J @ x + sigma * rng.standard_normal(m)
        if rank_deficient:  # the posterior mean (prior mean 0)
            C = np.linalg.inv(J.T @ J / sigma**2 + np.diag(1 / prior**2))
            xh = C @ J.T @ y / sigma**2
        else:
            xh = np.linalg.lstsq(J, y, rcond=None)[0]
        cov = parameter_covariance(J, J @ xh - y, sigma**2 if known else None, prior, scale_to_fit=scale)
        iv = propagate(G @ xh, G, cov, 0.95)
        hits += (iv.low <= G @ x) & (G @ x <= iv.high)
    return hits / trials


@pytest.mark.parametrize("known, rank_deficient, scale",
                         [(True, False, False), (False, False, False), (True, True, False), (True, False, True)])
def test_linear_gaussian_coverage_is_the_stated_rate(known, rank_deficient, scale):
    """Where the covariance is exact: sigma known (normal quantile), sigma from the residual (Student's t
    on m - n), fewer data than variables with the prior (posterior mean), and sigma known with the
    default widening to a fit that the scatter does not explain at 95 % (rarely, here): 95 % +- 1.5 %
    (2000 trials, standard error 0.5 %)."""
    coverage = _linear_coverage(known, rank_deficient, scale=scale)
    assert np.all(np.abs(coverage - 0.95) < 0.015), coverage


def test_covariance_scaled_to_the_fit_and_unseen_directions():
    rng = np.random.default_rng(0)
    J = rng.standard_normal((10, 3))
    r = 0.1 * rng.standard_normal(10)
    # Measured scatter 10 times smaller than the residual: widened by chi^2/dof to the residual's.
    cov = parameter_covariance(J, r, 1e-4)
    assert cov.chi2_dof > 50 and "chi2" in cov.source
    assert np.isclose(cov.sigma2, r @ r / 7)
    assert np.isclose(parameter_covariance(J, r, 1e-4, scale_to_fit=False).sigma2, 1e-4)
    # A variable the data do not see: unbounded without a prior, the prior's spread with one.
    J0 = np.column_stack([J, np.zeros(10)])
    g = np.array([[0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0]])
    iv = propagate(np.ones(2), g, parameter_covariance(J0, r, 1e-2))
    assert iv.std[0] == np.inf and np.isfinite(iv.std[1])
    prior = np.full(4, 0.1)
    iv = propagate(np.ones(2), g, parameter_covariance(J0, r, 1e-2, prior))
    assert np.isclose(iv.std[0], 0.1)
    # No redundancy and no measured scatter: no interval can be stated.
    cov = parameter_covariance(J[:3], r[:3])
    assert cov.sigma2 == 0 and cov.source.startswith("none") and np.all(propagate([1.0], J[:1], cov).std == np.inf)
    assert np.allclose(prior_std([beam("E", ["a"], "E", bounds=(0.75, 1.25))]), 0.5 / np.sqrt(12))


@pytest.fixture(scope="module")
def wing():
    """The X-HALE-like model (2 elements a section) on its outboard cords, three stiffness variables."""
    case = fg.cases.xhale(n_per_section=2)
    cfg = case.configurations["outboard"]
    v = [beam("E_in", ["wing_L1", "wing_R1"], "E", bounds=(0.75, 1.25)),
         beam("E_out", ["wing_L2", "wing_R2", "wing_L3", "wing_R3"], "E", bounds=(0.75, 1.25)),
         beam("G_wing", ["wing_*"], "G", bounds=(0.75, 1.25))]
    return case.model, cfg, v


def _elastic(model, cfg, n):
    modes = solve_modes(solve_static(model, cfg), n + 10, damped=False)
    f = modes.frequencies_hz
    return f[(f > 0) & (modes.energy_fractions[:, 4] < 0.5)][:n]


def test_predicted_modes_sensitivities_match_differences(wing):
    model, cfg, v = wing
    free = Configuration("free", gravity=0.0)
    x = np.array([1.05, 0.96, 1.03])
    updated = model.copy("x")
    Parametrisation(model, [cfg], v).apply(updated, x)
    f = _elastic(updated, free, 6)
    pm = PredictedModes(model, [cfg], v, x, {"free": (free, f)})
    g = pm.sensitivities()["free"]
    h = 1e-4
    fd = np.column_stack([(pm.at(x + h * e)["free"] - pm.at(x - h * e)["free"]) / (2 * h) for e in np.eye(3)])
    assert np.abs(g - fd).max() < 1e-4 * np.abs(g).max()
    assert np.allclose(pm.at(x)["free"], f, rtol=1e-6)  # the same modes (two eigen-solvers' tolerances)


def test_fe_coverage_over_noise_seeds(wing):
    """Truth inside the variables' reach: the free-free prediction's 95 % interval covers the truth's
    free-free modes at about the stated rate over noise seeds (measured scatter 0.5 %)."""
    model, cfg, v = wing
    free = Configuration("free", gravity=0.0)
    x_true = np.array([1.06, 0.95, 1.04])
    truth = model.copy("truth")
    Parametrisation(model, [cfg], v).apply(truth, x_true)
    f_meas = _elastic(truth, cfg, 6)
    z, hits = [], []
    for seed in range(5):
        rng = np.random.default_rng(seed)
        sd = 0.005 * f_meas
        res = update(model, [cfg], [Measured(cfg.name, f_meas + sd * rng.standard_normal(6), frequency_std_hz=sd)],
                     v, max_iterations=30)
        f = _elastic(res.model, free, 6)
        pm = PredictedModes(model, [cfg], v, res.x, {"free": (free, f)})
        cov = parameter_covariance(res.final.jacobian, res.final.residuals, (0.005) ** 2, prior_std(v))
        iv = propagate(f, pm.sensitivities()["free"], cov)
        f_true = pm.at(x_true)["free"]
        z += list((f - f_true) / iv.std)
        hits += list((iv.low <= f_true) & (f_true <= iv.high))
    # 30 predictions from 5 fits (correlated within a fit): coverage near 95 %, and the errors
    # neither far larger nor far smaller than the stated standard deviations.
    assert np.mean(hits) >= 0.85, np.mean(hits)
    assert 0.3 < np.mean(np.square(z)) < 2.0, np.mean(np.square(z))


def test_mcmc_agrees_with_the_linear_route_on_a_nearly_linear_case():
    """emcee on y = J x + e (linear residuals): the sampled 95 % interval of g x matches the linear one."""
    pytest.importorskip("emcee")
    rng = np.random.default_rng(1)
    J = rng.standard_normal((8, 2))
    x_true = np.array([1.0, 1.0])
    y = J @ x_true + 0.02 * rng.standard_normal(8)
    xh = np.linalg.lstsq(J, y, rcond=None)[0]
    cov = parameter_covariance(J, J @ xh - y, 0.02**2, scale_to_fit=False)
    settings = UncertaintySettings(method="mcmc", walkers=16, steps=600, burn=200, thin=2, seed=2)
    chain = sample_posterior(lambda x: (J @ x - y) / 1.0, xh, cov, np.zeros(2), np.full(2, 2.0), settings)
    g = np.array([[1.0, -0.5]])
    lin = propagate(g @ xh, g, cov)
    mc = sampled_interval(g @ xh, chain @ g.T, 0.95)
    assert abs(mc.std[0] / lin.std[0] - 1) < 0.15
    assert abs(mc.low[0] - lin.low[0]) < 0.3 * lin.std[0] and abs(mc.high[0] - lin.high[0]) < 0.3 * lin.std[0]
