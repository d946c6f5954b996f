"""FRFs: a frequency-response matrix on one frequency axis with its DOF labels and, where known,
coherence and variance. Produced by the UFF readers (flexgvt.io.read_uff), the estimators
(flexgvt.ema.estimate_frf) and the synthesisers; taken by every EMA function."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .dofs import as_dofs


@dataclass(frozen=True, eq=False)
class FRFs:
    """frequencies_hz (n_freq,); H (n_freq, n_outputs, n_inputs) complex; outputs, inputs: (n, 2) DOFs
    (point id, direction code; empty when unknown); units: 'ordinate/denominator' labels;
    coherence (n_freq, n_outputs) (multiple coherence for several inputs) or None; variance
    (n_freq, n_outputs, n_inputs): E|H_est - H|^2 per line [H units squared] or None (the weights
    of flexgvt.ema.refine); n_averages and estimator ('H1', 'H2', 'Hv') of an estimate."""

    frequencies_hz: np.ndarray
    H: np.ndarray
    outputs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), int))
    inputs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), int))
    units: str = ""
    coherence: np.ndarray | None = None
    variance: np.ndarray | None = None
    n_averages: int | None = None
    estimator: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "outputs", as_dofs(self.outputs, "FRFs.outputs"))
        object.__setattr__(self, "inputs", as_dofs(self.inputs, "FRFs.inputs"))

    @property
    def n_outputs(self) -> int:
        return int(np.shape(self.H)[1])

    @property
    def n_inputs(self) -> int:
        return int(np.shape(self.H)[2])
