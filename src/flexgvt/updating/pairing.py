"""The pairing policy of the updating problem: which analytical mode each measured mode is
compared with at a design point, and the reference that keeps the pairing steady between points."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment

from ..correlation import pair
from ..modal import ModalSet
from .targets import Measured, Objective


class PairingPolicy:
    """Measured -> analytical pairing with the objective's mac_floor and max_frequency_ratio.

    reference: {configuration: (fit, shapes)}, per configuration without measured shapes the paired
    analytical shapes at the point where its frequencies fitted best so far, and that fit."""

    def __init__(self, objective: Objective):
        self.objective = objective
        self.reference: dict[str, tuple[float, np.ndarray]] = {}

    def reference_of(self, point, measured: dict[str, Measured]) -> dict:
        """{configuration: (-inf, paired analytical shapes)} of ``point`` (a Point), for the
        configurations without measured shapes: pairing against it reproduces the point's pairing."""
        out = {}
        for name, c in point.configurations.items():
            if c.phi is not None and measured[name].shapes is None:
                out[name] = (-np.inf, c.phi[:, np.maximum(c.paired, 0)])
        return out

    def pair(self, name: str, meas: Measured, f: np.ndarray, phi: np.ndarray, shapes_s: np.ndarray | None,
             M: sp.spmatrix, seen: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """Measured -> analytical pairing: by MAC with the measured shapes (frequency as tie-break,
        a floor below which a measured mode stays unpaired); without shapes, by MAC with a reference
        (so modes that cross stay paired), and at the first point by frequency (least squares on log
        frequency among the modes the sensors see, when ``seen`` is given). The reference is the
        paired analytical shapes of the design point where this configuration's frequencies fitted
        best so far: an optimiser's rejected trial steps do not move it, so the pairing at a point
        does not depend on the order in which points were tried."""
        elastic = f > 0
        fm = meas.frequencies_hz
        closeness = np.abs(np.log(np.where(f[None, :] > 0, f[None, :], 1e-300) / fm[:, None]))
        if shapes_s is not None:
            got = pair(ModalSet(fm, shapes=meas.shapes), ModalSet(f, shapes=shapes_s),
                       mac_floor=self.objective.mac_floor, max_frequency_ratio=self.objective.max_frequency_ratio)
            paired = np.full(len(fm), -1)
            paired[got.measured] = got.analytical
            mac = np.full(len(fm), np.nan)
            mac[got.measured] = got.mac
            return paired, mac, got.mac_matrix
        best, previous = self.reference.get(name, (np.inf, None))
        if previous is not None and previous.shape[0] == phi.shape[0]:
            weighted = M @ phi
            num = (previous.T @ weighted) ** 2
            den = np.einsum("ij,ij->j", previous, M @ previous)[:, None] * np.einsum("ij,ij->j", phi, weighted)[None, :]
            score = num / np.where(den > 0, den, 1.0)
            score[:, ~elastic] = -1.0
            rows, cols = linear_sum_assignment(-score)
            paired = np.full(len(fm), -1)
            paired[rows] = cols
        else:
            usable = elastic if seen is None else elastic & seen
            # Squared: the sum of |log| is the same for every assignment of a cluster lying on one
            # side of the measured frequencies, so the order would be left to round-off.
            cost = np.where(usable[None, :], closeness ** 2, 1e6)
            rows, cols = linear_sum_assignment(cost)
            paired = np.full(len(fm), -1)
            paired[rows] = cols
        ok = paired >= 0
        fit = float(np.mean(closeness[np.flatnonzero(ok), paired[ok]] ** 2)) if ok.all() else np.inf
        if previous is None or fit < best:
            self.reference[name] = (fit, phi[:, np.maximum(paired, 0)])
        return paired, np.full(len(fm), np.nan), None
