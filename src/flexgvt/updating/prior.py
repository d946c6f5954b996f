"""The variables' prior and the measured scatter it is weighed against: the bounds as a uniform
prior (its standard deviation), the variance of one weighted frequency residual from the measured
standard deviations. Shared by the MAP objective (updating.problem) and the confidence bounds
(updating.uncertainty)."""

from __future__ import annotations

from typing import Callable, Sequence

import numpy as np

from .targets import Measured, Objective
from .variables import Variable


def prior_std(variables: Sequence[Variable]) -> np.ndarray:
    """(n,) standard deviation of a uniform distribution over each variable's normalised bounds."""
    return np.array([(v.bounds[1] - v.bounds[0]) / np.sqrt(12.0) for v in variables])


def measurement_variance(measured: Sequence[Measured], objective: Objective,
                         weights: Callable[[Measured], np.ndarray]) -> float | None:
    """Variance of one weighted frequency residual w (f - fm) / fm from the measured standard
    deviations (``weights``: the objective's per-mode weights of a Measured), None when none are given."""
    with_std = [m for m in measured if m.frequency_std_hz is not None and np.any(m.frequency_std_hz > 0)]
    if not with_std:
        return None
    terms = np.concatenate([objective.frequency * weights(m) * m.frequency_std_hz / m.frequencies_hz
                            for m in with_std])
    terms = terms[terms > 0]
    return float(np.mean(terms**2))
