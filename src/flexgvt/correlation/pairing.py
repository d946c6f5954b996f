"""One-to-one pairing of measured and analytical modes: MAC first, frequency as tie-break, a MAC
floor below which a measured mode stays unpaired and is reported."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..errors import ModelError
from .mac import _pair_shapes, mac_of

TIE_BREAK = 0.01  # weight of the frequency closeness |ln(f_a / f_m)| (capped at 1) against MAC


@dataclass(frozen=True)
class Pairing:
    """measured, analytical: paired indices (n_pairs,); mac and frequency_error ((f_a - f_m) / f_m)
    of each pair; unpaired: measured modes whose best available MAC is below the floor;
    mac_matrix: the full (n_measured, n_analytical) MAC."""

    measured: np.ndarray
    analytical: np.ndarray
    mac: np.ndarray
    frequency_error: np.ndarray
    unpaired: tuple[int, ...]
    mac_matrix: np.ndarray
    measured_hz: np.ndarray
    analytical_hz: np.ndarray
    labels: tuple[str, ...] = ()

    def table(self) -> list[dict]:
        """Rows for a report: every measured mode, paired or not."""
        rows = []
        lookup = dict(zip(self.measured.tolist(), range(len(self.measured))))
        for i, fm in enumerate(self.measured_hz):
            k = lookup.get(i)
            if k is None:
                rows.append({"measured_mode": i + 1, "measured_hz": float(fm), "analytical_mode": None,
                             "analytical_hz": None, "error_percent": None,
                             "mac": float(self.mac_matrix[i].max(initial=0.0)), "label": "unpaired"})
                continue
            j = int(self.analytical[k])
            rows.append({"measured_mode": i + 1, "measured_hz": float(fm), "analytical_mode": j + 1,
                         "analytical_hz": float(self.analytical_hz[j]),
                         "error_percent": 100 * float(self.frequency_error[k]), "mac": float(self.mac[k]),
                         "label": self.labels[j] if j < len(self.labels) else ""})
        return rows

    def report(self) -> str:
        if not self.unpaired:
            return f"{len(self.measured)} measured modes paired"
        return (f"{len(self.measured)} paired; measured mode(s) {[i + 1 for i in self.unpaired]} left unpaired: no "
                "analytical mode reaches the MAC floor (a mode the model lacks, or too few analytical modes)")


def pair(measured, modes, sensors=None, mac_floor: float = 0.5, exclude_rigid: bool = True,
         max_frequency_ratio: float | None = 2.0) -> Pairing:
    """Pair measured modes (ModalSet or (n, n_rows) array with frequencies given by ``measured``'s
    frequencies_hz) with analytical ones (fem Modes, reduced to the sensors).

    The assignment maximises the sum of MAC - 0.01 min(|ln(f_a / f_m)|, 1) (scipy's
    linear_sum_assignment): MAC decides, frequency only breaks near-ties. exclude_rigid leaves out
    analytical modes at 0 Hz (rigid-body modes of a free model); a suspended model's pendulum and
    plunge modes have frequencies and pair with measured suspension modes like any other.
    max_frequency_ratio: an analytical mode more than this factor away in frequency never pairs
    (a few sensors can see a far mode's tiny motion with a high MAC; None: no limit)."""
    A, B, _ = _pair_shapes(measured, modes, sensors)
    fm = np.asarray(getattr(measured, "frequencies_hz", np.full(len(A), np.nan)), float)
    fa = np.asarray(getattr(modes, "frequencies_hz", np.full(len(B), np.nan)), float)
    if not 0.0 <= mac_floor <= 1.0:
        raise ModelError(f"pair: mac_floor={mac_floor} must lie in [0, 1]")
    macm = mac_of(A, B)
    usable = np.ones(len(B), bool)
    if exclude_rigid and np.isfinite(fa).all():
        usable &= fa > 0
    closeness = np.abs(np.log(np.where(fa[None, :] > 0, fa[None, :], 1.0)
                              / np.where(fm[:, None] > 0, fm[:, None], 1.0)))
    closeness = np.where(np.isfinite(closeness), np.minimum(closeness, 1.0), 1.0)
    allowed = np.broadcast_to(usable[None, :], macm.shape).copy()
    if max_frequency_ratio is not None:
        if not max_frequency_ratio > 1.0:
            raise ModelError(f"pair: max_frequency_ratio={max_frequency_ratio} must be > 1")
        ratio = np.where((fa[None, :] > 0) & (fm[:, None] > 0),
                         np.abs(np.log(np.where(fa[None, :] > 0, fa[None, :], 1.0)
                                       / np.where(fm[:, None] > 0, fm[:, None], 1.0))),
                         0.0)
        allowed &= ~(np.nan_to_num(ratio, nan=0.0) > np.log(max_frequency_ratio))
    score = np.where(allowed, macm - TIE_BREAK * closeness, -1.0)
    rows, cols = linear_sum_assignment(-score) if len(A) and usable.any() else (np.zeros(0, int), np.zeros(0, int))
    keep = macm[rows, cols] >= mac_floor
    keep &= allowed[rows, cols]
    r, c = rows[keep], cols[keep]
    unpaired = tuple(sorted(set(range(len(A))) - set(r.tolist())))
    err = (fa[c] - fm[r]) / np.where(fm[r] != 0, fm[r], np.nan)
    labels = tuple(getattr(modes, "labels", ()) or ())
    return Pairing(r, c, macm[r, c], err, unpaired, macm, fm, fa, labels)
