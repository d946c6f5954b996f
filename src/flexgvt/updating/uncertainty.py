"""Confidence bounds of predicted frequencies from an updated model.

Linear route (Laplace approximation about the least-squares answer x^): the weighted residuals r(x)
of the updating problem are taken as independent, each of variance sigma^2, and the variables carry
a prior of the variance of a uniform distribution over their bounds (the bounds say how well each is
known, docs/method.md section 4; ``prior="none"`` leaves it out). Then

    C = (J^T J / sigma^2 + P^-1)^-1          (normalised variables; P = diag(prior variances))
    var f_k = g_k C g_k^T,   g_k = d f_k / d x  (exact sensitivities of the predicted mode)

sigma^2: from the measured frequency standard deviations (the weights the objective used), scaled
up by the fit's chi^2 per degree of freedom when the residual is larger than they explain at 95 %
(a model error or an under-stated scatter: the Birge ratio), or from the residual alone without them.

Sampling route: an affine-invariant ensemble MCMC (emcee, optional dependency ``flexgvt[mcmc]``)
of the same residuals, log p(x) = -|r(x)|^2 / (2 sigma^2) inside the bounds (uniform prior; with
Objective.prior 'bounds' the residuals carry the Gaussian prior's rows too), each
retained sample's predicted frequencies giving the percentile interval.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Callable, Sequence

import numpy as np

from ..errors import ModelError, SolverError
from ..model import Configuration, Model
from .points import DesignPointFailure
from .prior import measurement_variance, prior_std
from .settings import UncertaintySettings
from .targets import Measured, Objective
from .variables import Parametrisation, Variable

__all__ = ["Covariance", "Interval", "PredictedModes", "measurement_variance", "parameter_covariance", "prior_std",
           "propagate", "sample_posterior", "sampled_interval", "z_value"]

NULL_SHARE = 1e-3  # a prediction whose gradient has this share in a direction no data nor prior sees is unbounded


@dataclass(frozen=True)
class Covariance:
    """The normalised variables' covariance and how it was made.

    matrix (n, n); sigma2: variance of one weighted residual used; source: where sigma2 came from;
    chi2_dof: the fit's |r|^2 / (dof sigma_measured^2) (None without measured scatter); dof: residuals
    minus effective parameters; prior: the prior variances' (n,) standard deviations or None;
    null: (k, n) orthonormal directions neither the data nor a prior constrain (prior="none")."""

    matrix: np.ndarray
    sigma2: float
    source: str
    chi2_dof: float | None
    dof: float
    prior: np.ndarray | None
    null: np.ndarray

    @property
    def estimated(self) -> bool:
        """sigma2 was estimated from the fit's residual (intervals then use Student's t on dof)."""
        return self.source.startswith("residual") or "chi2" in self.source

    def quantile(self, level: float) -> float:
        """The two-sided quantile of ``level``: normal, or Student's t on dof when sigma2 was estimated."""
        if not self.estimated:
            return z_value(level)
        return _quantile(level, round(max(self.dof, 0.5), 6))

    @property
    def std(self) -> np.ndarray:
        """(n,) standard deviations of the normalised variables (inf along unconstrained directions)."""
        s = np.sqrt(np.clip(np.diag(self.matrix), 0, None))
        if len(self.null):
            s = np.where(np.sum(self.null**2, axis=0) > NULL_SHARE, np.inf, s)
        return s

    def to_dict(self) -> dict:
        return {"sigma": float(np.sqrt(self.sigma2)), "sigma_source": self.source, "chi2_per_dof": self.chi2_dof,
                "dof": self.dof, "prior": None if self.prior is None else "uniform on the bounds (its variance)",
                "unconstrained_directions": len(self.null)}


@dataclass(frozen=True)
class Interval:
    """Predicted values (n,), their standard deviations and the (low, high) bounds at ``level``."""

    value: np.ndarray
    std: np.ndarray
    low: np.ndarray
    high: np.ndarray
    level: float
    method: str


def z_value(level: float) -> float:
    """The two-sided normal quantile of ``level`` (1.96 for 0.95)."""
    if not 0.0 < level < 1.0:
        raise ModelError(f"confidence level {level} must lie in (0, 1)")
    return _quantile(level, None)


@lru_cache(maxsize=256)
def _chi2_limit(dof: float) -> float:
    """The 95 % point of chi^2 / dof on dof degrees of freedom: a fit's residual above it is more than
    the measured scatter explains."""
    from scipy.stats import chi2
    return float(chi2.ppf(0.95, dof) / dof)


@lru_cache(maxsize=256)
def _quantile(level: float, dof: float | None) -> float:
    """The two-sided quantile of ``level``: normal (dof None) or Student's t on dof (scipy's are slow)."""
    from scipy.stats import norm, t
    return float(norm.ppf(0.5 + level / 2) if dof is None else t.ppf(0.5 + level / 2, dof))


def parameter_covariance(jacobian: np.ndarray, residuals: np.ndarray, sigma2_measured: float | None = None,
                         prior: np.ndarray | None = None, scale_to_fit: bool = True,
                         rank_tolerance: float = 1e-6) -> Covariance:
    """Covariance of the normalised variables at a least-squares answer (Jacobian (m, n) and
    residuals (m,) of the weighted residual vector there).

    sigma2_measured: variance of one residual from the measured scatter (None: from the residual,
    |r|^2 / dof); scale_to_fit: when chi^2/dof of the fit exceeds its 95 % point (the scatter does
    not explain the residual), sigma^2 from the residual instead (Student's t then); prior: (n,) prior
    standard deviations or None (then directions J does not see are reported in ``null``). dof is
    m minus the effective number of parameters, trace(J C J^T) / sigma^2."""
    J = np.asarray(jacobian, float)
    r = np.asarray(residuals, float)
    m, n = J.shape
    rss = float(r @ r)
    _, s, vt = np.linalg.svd(J, full_matrices=True)
    s = np.r_[s, np.zeros(n - len(s))]
    seen = s > rank_tolerance * max(s.max(initial=0.0), 1e-300)
    p_inv = None if prior is None else 1.0 / np.asarray(prior, float) ** 2

    def posterior(sigma2: float) -> tuple[np.ndarray, float]:
        """(C, effective number of parameters) for residual variance sigma2 > 0."""
        if p_inv is None:
            inv = np.where(seen, 1.0 / np.where(seen, s, 1.0) ** 2, 0.0)
            return (vt.T * (sigma2 * inv)) @ vt, float(np.sum(seen))
        C = np.linalg.inv(J.T @ J / sigma2 + np.diag(p_inv))
        C = 0.5 * (C + C.T)
        return C, float(np.trace(J @ C @ J.T) / sigma2)

    def fit_variance(start: float, floor: float) -> tuple[float, np.ndarray, float]:
        """sigma2 = |r|^2 / (m - p_eff(sigma2)) (not below floor), by fixed-point iteration."""
        sigma2 = start
        for _ in range(100):
            C, p_eff = posterior(sigma2)
            new = max(rss / max(m - p_eff, 0.5), floor)
            if abs(new - sigma2) <= 1e-10 * sigma2:
                break
            sigma2 = new
        C, p_eff = posterior(sigma2)
        return sigma2, C, p_eff

    null = vt[~seen] if p_inv is None else np.zeros((0, n))
    chi2 = None
    if sigma2_measured is not None and sigma2_measured > 0:
        sigma2, source = sigma2_measured, "measured standard deviations"
        C, p_eff = posterior(sigma2)
        if m - p_eff > 0.5:
            chi2 = rss / ((m - p_eff) * sigma2_measured)
            if scale_to_fit and chi2 > _chi2_limit(round(m - p_eff, 6)):
                # The residual is larger than the measured scatter explains at 95 % (a model error or
                # an under-stated scatter): widen to what the fit shows (the Birge ratio). Below that
                # the scatter stands as measured (widening then would only make the interval wider).
                sigma2, C, p_eff = fit_variance(sigma2_measured * chi2, sigma2_measured)
                source = "measured standard deviations x chi2/dof of the fit"
    elif rss > 0 and m > 0:
        sigma2, C, p_eff = fit_variance(rss / m, 0.0)
        source = f"residual ({m - p_eff:.1f} degrees of freedom)"
    else:
        sigma2, C, p_eff = 0.0, np.zeros((n, n)), 0.0
    if sigma2 <= 0 or m - p_eff <= 0.5 and chi2 is None and (sigma2_measured or 0) <= 0:
        # No redundancy to estimate the scatter from and none measured: no interval can be stated.
        return Covariance(np.zeros((n, n)), 0.0, "none (no redundancy and no measured standard deviations)",
                          None, float(m - p_eff), None if prior is None else np.asarray(prior, float), np.eye(n))
    return Covariance(C, float(sigma2), source, None if chi2 is None else float(chi2), float(m - p_eff),
                      None if prior is None else np.asarray(prior, float), null)


def propagate(values: np.ndarray, gradient: np.ndarray, covariance: Covariance, level: float = 0.95) -> Interval:
    """Linearised interval of ``values`` (k,) with ``gradient`` (k, n) d value / d x: std = sqrt(g C g^T),
    bounds value -+ q std (q: covariance.quantile(level)); a value whose gradient reaches a direction
    nothing constrains is unbounded (std inf, bounds -inf / inf)."""
    f = np.asarray(values, float)
    G = np.asarray(gradient, float)
    var = np.einsum("ki,ij,kj->k", G, covariance.matrix, G)
    std = np.sqrt(np.clip(var, 0, None))
    if len(covariance.null):
        share = np.sum((G @ covariance.null.T) ** 2, axis=1) / np.maximum(np.sum(G**2, axis=1), 1e-300)
        std = np.where(share > NULL_SHARE, np.inf, std)
    q = covariance.quantile(level)
    return Interval(f, std, f - q * std, f + q * std, level, "linear")


# ---------------------------------------------------------------------- sensitivities of predictions
def _prediction_variables(parametrisation: Parametrisation, names: set[str]) -> tuple[list[Variable], list[int]]:
    """The variables as they bind on a prediction's configurations: those on configuration items
    (cords, a configuration's own masses) restricted to the tested configurations they bound to that
    are predicted (dropped when none is); with their positions in the full variable list."""
    out, keep = [], []
    for k, b in enumerate(parametrisation.bindings):
        v = b.variable
        if v.per_configuration:
            bound = tuple(dict.fromkeys(idx[0] for idx in b.indices if idx[0] in names))
            if not bound:
                continue
            v = replace(v, configurations=bound)
        out.append(v)
        keep.append(k)
    return out, keep


class PredictedModes:
    """Predicted modes followed across design points, with their exact sensitivities.

    model and tested: the initial model and the configurations the ``variables`` were bound on
    (the updating's); x: the updated design point; cases: {key: (configuration as the initial model
    defines it, the mode frequencies [Hz] predicted at x, all > 0)}. The modes are found again at x by
    frequency (SolverError when one is not within rtol) and followed from there by MAC."""

    def __init__(self, model: Model, tested: Sequence[Configuration], variables: Sequence[Variable],
                 x: np.ndarray, cases: dict[str, tuple[Configuration, np.ndarray]], rtol: float = 1e-6):
        from .problem import UpdatingProblem
        full = Parametrisation(model, tested, variables)
        self.n = len(full)
        self.cases = {key: (cfg, np.asarray(f, float)) for key, (cfg, f) in cases.items()}
        used, self.keep = _prediction_variables(full, {c.name for c, _ in self.cases.values()})
        self.problem = None
        self.point = None
        if not used:
            return
        measured = [Measured(cfg.name, f) for cfg, f in self.cases.values()]
        objective = Objective(mass=0.0, cg=0.0, inertia=0.0, use_std=False, max_frequency_ratio=None)
        self.problem = UpdatingProblem(model, [cfg for cfg, _ in self.cases.values()], measured, used,
                                       objective=objective, n_modes=max(len(f) for _, f in self.cases.values()) + 8)
        xs = np.asarray(x, float)[self.keep]
        self.point = self.problem.evaluate(xs, gradient=True)
        for key, (cfg, f) in self.cases.items():
            p = self.point.configurations[cfg.name]
            fa = p.frequencies_hz[np.maximum(p.paired, 0)]
            # a pendulum mode far below the band moves with the static state's last digits (a heavy
            # cord's yaw pendulum: 3e-7 of its 0.065 Hz): its tolerance is taken at 5 % of the band's top
            bad = np.flatnonzero((p.paired < 0) | (np.abs(fa - f) > rtol * np.maximum(f, 0.05 * f.max())))
            if len(bad):
                raise SolverError(f"confidence bounds, configuration '{key}': predicted mode(s) "
                                  f"{(bad + 1).tolist()} ({f[bad].round(4).tolist()} Hz) not found again for "
                                  "their sensitivities")
        self.problem.set_pairing_reference(self.problem.reference_of(self.point))  # followed by MAC from here

    def sensitivities(self) -> dict[str, np.ndarray]:
        """{key: d f / d x (k, n)} at the updated point (the eigenvalue sensitivities about each
        configuration's equilibrium, as the updating's Jacobian)."""
        out = {}
        for key, (cfg, f) in self.cases.items():
            g = np.zeros((len(f), self.n))
            if self.point is not None:  # a block's first rows: (f - fm) / fm, so d f = fm d row
                g[:, self.keep] = self.point.configurations[cfg.name].block.jacobian[:len(f)] * f[:, None]
            out[key] = g
        return out

    def at(self, x: np.ndarray) -> dict[str, np.ndarray]:
        """{key: the predicted frequencies (k,) at design point x} (NaN for a mode lost on the way)."""
        if self.problem is None:
            return {key: f.copy() for key, (_, f) in self.cases.items()}
        point = self.problem.evaluate(np.asarray(x, float)[self.keep])
        out = {}
        for key, (cfg, _) in self.cases.items():
            p = point.configurations[cfg.name]
            out[key] = np.where(p.paired >= 0, p.frequencies_hz[np.maximum(p.paired, 0)], np.nan)
        return out


# ---------------------------------------------------------------------- sampling
def sample_posterior(residuals: Callable[[np.ndarray], np.ndarray], x_hat: np.ndarray, covariance: Covariance,
                     lower: np.ndarray, upper: np.ndarray,
                     settings: UncertaintySettings = UncertaintySettings(method="mcmc"),
                     progress: Callable[[str], None] | None = None) -> np.ndarray:
    """Posterior samples (k, n) of the normalised variables by emcee's ensemble sampler:
    log p(x) = -|r(x)|^2 / (2 sigma^2) inside [lower, upper] (uniform prior), sigma^2 the
    covariance's; walkers start in a small ball (0.1 of the linear standard deviations) about
    x^. residuals(x) may raise DesignPointFailure (that x gets probability 0). Returns the chain after
    ``settings.burn`` steps, thinned by ``settings.thin``."""
    try:
        import emcee
    except ImportError:
        raise ModelError("confidence bounds by MCMC need the emcee package: pip install 'flexgvt[mcmc]' "
                         "(or emcee), or set [prediction.uncertainty] method = \"linear\"") from None
    if covariance.sigma2 <= 0:
        raise ModelError("confidence bounds by MCMC: the residual variance is zero (no redundancy and no "
                         "measured standard deviations); give frequency standard deviations or more modes")
    x_hat = np.asarray(x_hat, float)
    n = len(x_hat)
    lo, hi = np.asarray(lower, float), np.asarray(upper, float)
    walkers = max(settings.walkers, 2 * n + 2)
    if settings.steps <= settings.burn:
        raise ModelError(f"MCMC: steps ({settings.steps}) must exceed burn ({settings.burn})")

    def log_prob(x: np.ndarray) -> float:
        if np.any(x < lo) or np.any(x > hi):
            return -np.inf
        try:
            r = residuals(x)
        except DesignPointFailure:
            return -np.inf
        return -0.5 * float(r @ r) / covariance.sigma2

    rng = np.random.default_rng(settings.seed)
    std = np.where(np.isfinite(covariance.std), covariance.std, 0.0)
    scale = np.maximum(0.1 * std, 1e-6 * (hi - lo))
    start = np.clip(x_hat + scale * rng.standard_normal((walkers, n)), lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
    sampler = emcee.EnsembleSampler(walkers, n, log_prob)
    state = emcee.State(start, random_state=np.random.RandomState(settings.seed).get_state())
    step = max(1, settings.steps // 10)
    for k, _ in enumerate(sampler.sample(state, iterations=settings.steps)):
        if progress is not None and (k + 1) % step == 0:
            progress(f"  MCMC step {k + 1}/{settings.steps}, acceptance {np.mean(sampler.acceptance_fraction):.2f}")
    return sampler.get_chain(discard=settings.burn, thin=settings.thin, flat=True)


def sampled_interval(values: np.ndarray, samples: np.ndarray, level: float) -> Interval:
    """Percentile interval at ``level`` of predicted values (k,) from their samples (s, k); std: the
    samples' standard deviation."""
    q = 50 * (1 - level)
    low, high = np.nanpercentile(samples, [q, 100 - q], axis=0)
    return Interval(np.asarray(values, float), np.nanstd(samples, axis=0, ddof=1), low, high, level, "mcmc")
