"""Confidence bounds of a run's free-flying prediction: the updated variables' uncertainty (from the
measured frequencies' scatter and the fit, flexgvt.updating.uncertainty) carried to every predicted
frequency, free-free and of every predicted configuration, by the linear route or by MCMC."""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..errors import ModelError, SolverError
from ..model import Configuration
from ..updating import UncertaintySettings, UpdateResult, UpdatingProblem
from ..updating.uncertainty import (Covariance, Interval, PredictedModes, measurement_variance, parameter_covariance,
                                    prior_std, propagate, sample_posterior, sampled_interval)
from .identification import Identified, measured
from .project import Project, ProjectError
from .steps import Prediction, objective

FREE = "free"  # the cases' key of the free-free modes


def _cases(project: Project, prediction: Prediction) -> dict[str, tuple[Configuration, np.ndarray]]:
    """{key: (configuration as the initial model defines it, the predicted frequencies > 0 [Hz])}: each
    predicted configuration and the free-free case (built as flexgvt.suspension.remove_suspension
    builds it from the last configuration predicted)."""
    out = {}
    last = None
    for name, modes in prediction.proposed.items():
        if name in project.spec.prediction.proposed:
            cfg = project.available.get(name) or project.configurations[name]
        else:
            cfg = project.configurations[name]
        f = np.asarray(modes.frequencies_hz)
        out[name] = (cfg, f[f > 0])
        last = cfg
    if last is not None:
        free = Configuration(f"{last.name} (free-free)", gravity=0.0, gravity_direction=last.gravity_direction,
                             g=last.g, masses=last.masses)
        f = np.asarray(prediction.free.frequencies_hz)
        out[FREE] = (free, f[f > 0])
    return out


def require(settings: UncertaintySettings, where: str) -> None:
    """ProjectError before any computation when the settings need what is not installed (emcee)."""
    if settings.method == "mcmc":
        try:
            import emcee  # noqa: F401
        except ImportError:
            raise ProjectError(f"{where}: prediction.uncertainty method \"mcmc\" needs the emcee package: pip install "
                               "'flexgvt[mcmc]' (or emcee), or use method = \"linear\"") from None


def updating_problem(project: Project, identified: dict[str, Identified]) -> UpdatingProblem:
    """The project's updating problem (as flexgvt.workflow.update_model poses it)."""
    obj, target = objective(project)
    names = project.to_update
    return UpdatingProblem(project.model, [project.configurations[n] for n in names],
                           [measured(identified[n], project) for n in names], project.variables, target, obj,
                           project.spec.optimiser.n_modes)


def variable_covariance(project: Project, result: UpdateResult, problem: UpdatingProblem,
                        settings: UncertaintySettings) -> Covariance:
    """The updated variables' covariance at the answer (its Jacobian and residuals)."""
    sigma2 = measurement_variance(list(problem.measured.values()), problem.objective, problem.blocks.frequency_weights)
    prior = prior_std(project.variables) if settings.prior == "bounds" else None
    return parameter_covariance(result.final.data_jacobian, result.final.data_residuals, sigma2, prior,
                                settings.scale_to_fit)


def add_bounds(project: Project, result: UpdateResult, prediction: Prediction, identified: dict[str, Identified],
               settings: UncertaintySettings | None = None,
               progress: Callable[[str], None] | None = None) -> Prediction:
    """Confidence bounds on every frequency of ``prediction`` (of result's updated model): the rows
    get <value>_low_hz and <value>_high_hz for free_hz and each <configuration>_hz, the mode lists
    low_hz and high_hz, and prediction.uncertainty says how (method, confidence, sigma and its source,
    chi^2 per degree of freedom of the fit, the variables' standard deviations). settings: the
    project's [prediction.uncertainty] by default. Returns ``prediction`` (changed in place)."""
    settings = settings or project.spec.prediction.uncertainty
    if settings.method == "none" or not prediction.proposed:
        return prediction
    log = progress or (lambda s: None)
    problem = updating_problem(project, identified)
    cov = variable_covariance(project, result, problem, settings)
    cases = _cases(project, prediction)
    tested = [project.configurations[n] for n in project.to_update]
    try:
        modes = PredictedModes(project.model, tested, project.variables, result.x, cases)
        if settings.method == "linear":
            grads = modes.sensitivities()
            intervals = {k: propagate(f, grads[k], cov, settings.confidence) for k, (_, f) in cases.items()}
        else:
            intervals = _sampled(problem, result, modes, cases, cov, settings, log)
    except SolverError as exc:  # the prediction stands; say why it has no bounds
        prediction.uncertainty = {"method": settings.method, "confidence": settings.confidence, "failed": str(exc)}
        log(f"confidence bounds: not computed ({exc})")
        return prediction
    _write(prediction, intervals)
    prediction.uncertainty = {"method": settings.method, "confidence": settings.confidence, **cov.to_dict(),
                              "variables": {v.name: float(s) if np.isfinite(s) else None
                                            for v, s in zip(project.variables, cov.std)}}
    log(f"confidence bounds ({settings.method}, {100 * settings.confidence:g} %): sigma {np.sqrt(cov.sigma2):.3g} "
        f"from {cov.source}")
    return prediction


def _sampled(problem: UpdatingProblem, result: UpdateResult, modes: PredictedModes, cases: dict,
             cov: Covariance, settings: UncertaintySettings, log) -> dict[str, Interval]:
    """Percentile intervals from posterior samples of the updating residuals (emcee)."""
    initial = problem.evaluate(problem.x0)
    problem.set_pairing_reference(problem.reference_of(initial))  # the pairing the update started from
    at = problem.evaluate(result.x)
    if not np.isclose(at.objective, result.final.objective, rtol=1e-6, atol=1e-12):
        raise ModelError(f"MCMC bounds: the updating problem posed again gives objective {at.objective:.6g} at the "
                         f"answer, not the update's {result.final.objective:.6g}; use method = \"linear\"")
    problem.set_pairing_reference(problem.reference_of(at))
    lo, hi = problem.par.lower, problem.par.upper
    log(f"confidence bounds by MCMC: {max(settings.walkers, 2 * len(lo) + 2)} walkers x {settings.steps} steps")
    chain = sample_posterior(lambda x: problem.evaluate(x).residuals, result.x, cov, lo, hi, settings, log)
    rng = np.random.default_rng(settings.seed)
    pick = chain[rng.choice(len(chain), size=min(settings.samples, len(chain)), replace=False)]
    values = {k: [] for k in cases}
    for x in pick:
        for k, f in modes.at(x).items():
            values[k].append(f)
    return {k: sampled_interval(f, np.array(values[k]), settings.confidence) for k, (_, f) in cases.items()}


def _write(prediction: Prediction, intervals: dict[str, Interval]) -> None:
    """The intervals into the rows (by free mode) and into the configurations' mode lists."""
    def bounds(iv: Interval, i: int) -> tuple[float | None, float | None]:
        lo, hi = float(iv.low[i]), float(iv.high[i])
        return (lo if np.isfinite(lo) else None), (hi if np.isfinite(hi) else None)

    free = intervals.get(FREE)
    by_free = {r["free_mode"]: r for r in prediction.rows}
    if free is not None:
        f = np.asarray(prediction.free.frequencies_hz)
        index = {int(j) + 1: i for i, j in enumerate(np.flatnonzero(f > 0))}
        for r in prediction.rows:
            r["free_low_hz"], r["free_high_hz"] = bounds(free, index[r["free_mode"]])
    for name, rows in prediction.modes.items():
        iv = intervals.get(name)
        if iv is None:
            continue
        for i, m in enumerate(rows):
            m["low_hz"], m["high_hz"] = bounds(iv, i)
        for r in prediction.rows:
            r[f"{name}_low_hz"] = r[f"{name}_high_hz"] = None
        for m in rows:
            if m["free_mode"] in by_free:
                row = by_free[m["free_mode"]]
                row[f"{name}_low_hz"], row[f"{name}_high_hz"] = m["low_hz"], m["high_hz"]
