"""Time histories (dataset 58, function type 1) as simultaneous channels ready for FRF estimation
(flexgvt.ema.estimate_frf_from_time): io reads, ema estimates."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import FileFormatError
from .uff_scan import DIRECTIONS

FORCE_SPEC_TYPE = 13  # UFF 58 ordinate specific data type 13: excitation force


@dataclass(frozen=True)
class TimeHistories:
    """Simultaneous channels: data (n_channels, n_samples) [file units, see ``units``], dofs
    (n_channels, 2) (point id, direction code in the point's displacement CS), sample_rate_hz, t0_s,
    units (one label per channel), spec_types (UFF ordinate specific data type per channel: 13 force,
    12 acceleration, 8 displacement, 11 velocity...), names (channel names from the file)."""

    data: np.ndarray
    dofs: np.ndarray
    sample_rate_hz: float
    t0_s: float = 0.0
    units: tuple = ()
    spec_types: tuple = ()
    names: tuple = ()
    source: str = ""

    @property
    def n_samples(self) -> int:
        return int(self.data.shape[1])

    def channel_names(self) -> list[str]:
        return [f"{int(p)}{DIRECTIONS.get(int(d), '?')}" for p, d in self.dofs]

    def reference_rows(self, references=None) -> np.ndarray:
        """Rows of the reference (force) channels: ``references`` as (point, code) pairs, else the
        channels whose ordinate is a force (specific data type 13, or unit 'N'/'lbf')."""
        if references is not None:
            refs = np.asarray(references, int).reshape(-1, 2)
            rows = []
            for p, d in refs:
                hit = np.flatnonzero((self.dofs[:, 0] == p) & (self.dofs[:, 1] == d))
                if not len(hit):
                    raise FileFormatError(f"{self.source}: reference {p}{DIRECTIONS.get(int(d), '?')} is not among "
                                          f"the channels {self.channel_names()}")
                rows.append(int(hit[0]))
            return np.array(rows, int)
        force = [k for k in range(len(self.dofs))
                 if (k < len(self.spec_types) and self.spec_types[k] == FORCE_SPEC_TYPE)
                 or (k < len(self.units) and str(self.units[k]).strip() in ("N", "lbf", "kN", "mN"))]
        if not force:
            raise FileFormatError(f"{self.source}: no channel is marked as a force (ordinate type 13 or unit N) among "
                                  f"{self.channel_names()}; name the reference channels: references=[(point, "
                                  "direction code)] (flexgvt ema frf --reference POINT+DIR)")
        return np.array(force, int)

    def signals(self, references=None):
        """(force (n_in, n), response (n_out, n), inputs (n_in, 2), outputs (n_out, 2)) for the
        estimators; every channel that is not a reference is a response."""
        rows = self.reference_rows(references)
        if len(rows) == len(self.dofs):
            raise FileFormatError(f"{self.source}: every channel is a reference ({self.channel_names()}); the file "
                                  "holds no response channel")
        resp = np.setdiff1d(np.arange(len(self.dofs)), rows)
        return self.data[rows], self.data[resp], self.dofs[rows], self.dofs[resp]


def assemble(functions, where: str) -> TimeHistories:
    """Time-response functions (io.uff.Function, kind 'time response') -> TimeHistories; they must share
    one uniform time axis."""
    if not functions:
        raise FileFormatError(f"{where}: no time history (dataset 58, function type 1)")
    x = functions[0].x
    for f in functions[1:]:
        if f.x.shape != x.shape or not np.allclose(f.x, x, rtol=1e-9, atol=1e-12):
            raise FileFormatError(f"{where}: channel {f.response} has {len(f.x)} samples from {f.x[0]:g} s against "
                                  f"{len(x)} from {x[0]:g} s on the first channel; the channels must be simultaneous "
                                  "(one time axis): export them from one run")
    if len(x) < 2:
        raise FileFormatError(f"{where}: time histories of {len(x)} sample(s)")
    dt = np.diff(x)
    if np.any(dt <= 0) or not np.allclose(dt, dt[0], rtol=1e-4):
        raise FileFormatError(f"{where}: the time axis is not uniformly sampled (steps {dt.min():g} to "
                              f"{dt.max():g} s); FRF estimation needs a constant sample rate")
    data = np.array([np.real(f.data) for f in functions], float)
    dofs = np.array([f.response for f in functions], int)
    seen = {}
    for k, d in enumerate(map(tuple, dofs)):
        if d in seen:
            raise FileFormatError(f"{where}: two time histories for {d[0]}{DIRECTIONS.get(d[1], '?')} (functions "
                                  f"{seen[d] + 1} and {k + 1}); keep one channel per DOF")
        seen[d] = k
    fs = 1.0 / float(np.mean(dt))
    return TimeHistories(data, dofs, fs, float(x[0]), tuple(f.ordinate_label for f in functions),
                         tuple(getattr(f, "spec_type", 0) for f in functions), tuple(getattr(f, "name", "")
                                                                                     for f in functions), where)
