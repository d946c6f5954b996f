"""The pairing policy of the updating problem: which analytical mode each measured mode is
compared with at a design point, and the reference that keeps the pairing steady between points."""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment

from ..correlation import Unpaired, label_families, pair, pair_by_frequency
from ..correlation.pairing import explain_unpaired, label_matrix
from ..modal import ModalSet
from .targets import Measured, Objective


class PairingPolicy:
    """Measured -> analytical pairing with the objective's mac_floor and max_frequency_ratio.

    reference: {configuration: (fit, shapes)}, per configuration without measured shapes the paired
    analytical shapes at the point where its frequencies fitted best so far, and that fit."""

    def __init__(self, objective: Objective):
        self.objective = objective
        self.reference: dict[str, tuple[float, np.ndarray]] = {}
        self.moves = 0  # times a point's better fit replaced a reference (cached points may pair otherwise)

    def reference_of(self, point, measured: dict[str, Measured]) -> dict:
        """{configuration: (-inf, paired analytical shapes)} of ``point`` (a Point), for the
        configurations without measured shapes: pairing against it reproduces the point's pairing."""
        out = {}
        for name, c in point.configurations.items():
            if c.phi is not None and measured[name].shapes is None:
                out[name] = (-np.inf, c.phi[:, np.maximum(c.paired, 0)])
        return out

    def pair(self, name: str, meas: Measured, f: np.ndarray, phi: np.ndarray, shapes_s: np.ndarray | None,
             M: sp.spmatrix, seen: np.ndarray | None = None,
             labels: Callable[[], tuple[str, ...]] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """Measured -> analytical pairing: by MAC with the measured shapes (frequency as tie-break,
        a floor below which a measured mode stays unpaired, analytical modes the sensors do not see
        (``seen``) left out); without shapes, by MAC with a reference (so modes that cross stay
        paired), and at the first point by frequency (flexgvt.correlation.pair_by_frequency: least
        squares on log frequency among the modes the sensors see, within max_frequency_ratio and of
        the measured mode's family when its label names one; ``labels`` gives the analytical modes'
        labels). The reference is the paired analytical shapes of the design point where this
        configuration's frequencies fitted best so far (zero for a mode left unpaired, which stays
        unpaired): an optimiser's rejected trial steps do not move it, so the pairing at a point
        does not depend on the order in which points were tried."""
        elastic = f > 0
        fm = meas.frequencies_hz
        closeness = np.abs(np.log(np.where(f[None, :] > 0, f[None, :], 1e-300) / fm[:, None]))
        if shapes_s is not None:
            got = pair(ModalSet(fm, shapes=meas.shapes), ModalSet(f, shapes=shapes_s), seen=seen,
                       mac_floor=self.objective.mac_floor, max_frequency_ratio=self.objective.max_frequency_ratio)
            paired = np.full(len(fm), -1)
            paired[got.measured] = got.analytical
            mac = np.full(len(fm), np.nan)
            mac[got.measured] = got.mac
            return paired, mac, got.mac_matrix
        best, previous = self.reference.get(name, (np.inf, None))
        paired = np.full(len(fm), -1)
        if previous is not None and previous.shape[0] == phi.shape[0]:
            weighted = M @ phi
            num = (previous.T @ weighted) ** 2
            norms = np.einsum("ij,ij->j", previous, M @ previous)
            den = norms[:, None] * np.einsum("ij,ij->j", phi, weighted)[None, :]
            score = num / np.where(den > 0, den, 1.0)
            score[:, ~elastic] = -1.0
            live = np.flatnonzero(norms > 0)  # a zero reference column: unpaired where it was made
            rows, cols = linear_sum_assignment(-score[live])
            paired[live[rows]] = cols
        else:
            mlabels = meas.labels if any(label_families(x) for x in meas.labels) and labels is not None else ()
            got = pair_by_frequency(fm, f, measured_labels=mlabels, analytical_labels=labels() if mlabels else (),
                                    max_frequency_ratio=self.objective.max_frequency_ratio, seen=seen)
            paired[got.measured] = got.analytical
        ok = paired >= 0
        fit = float(np.mean(closeness[np.flatnonzero(ok), paired[ok]] ** 2)) if ok.any() else np.inf
        if previous is None or fit < best:
            self.reference[name] = (fit, phi[:, np.maximum(paired, 0)] * ok[None, :])
            self.moves += 1
        return paired, np.full(len(fm), np.nan), None

    def explain(self, meas: Measured, p) -> tuple[Unpaired, ...]:
        """Why each measured mode left unpaired at the configuration point ``p`` is (its own
        frequencies, MAC matrix, labels and what its sensors see)."""
        f = p.frequencies_hz
        fm = meas.frequencies_hz
        if not np.any(p.paired < 0):
            return ()
        o = self.objective
        usable = f > 0
        in_range = np.ones((len(fm), len(f)), bool) if o.max_frequency_ratio is None else \
            np.abs(np.log(np.where(f[None, :] > 0, f[None, :], 1e-300) / fm[:, None])) <= np.log(o.max_frequency_ratio)
        labels = tuple(p.labels) if p.state is not None or p._labels is not None else ()
        kw = dict(usable=usable, in_range=in_range, seen=p.seen, measured_labels=meas.labels,
                  analytical_labels=labels, max_frequency_ratio=o.max_frequency_ratio, configuration=p.name)
        if p.mac_matrix is not None:
            zero = np.linalg.norm(meas.shapes, axis=1)
            zero = zero <= 1e-12 * max(zero.max(initial=0.0), 1e-300)
            return tuple(explain_unpaired(i, fm, f, p.paired, macm=p.mac_matrix, mac_floor=o.mac_floor,
                                          measured_zero=bool(zero[i]), **kw) for i in np.flatnonzero(p.paired < 0))
        kw["label_ok"] = label_matrix(meas.labels, labels, len(fm), len(f))
        out = []
        for i in np.flatnonzero(p.paired < 0):
            u = explain_unpaired(i, fm, f, p.paired, **kw)
            if u.reason == "taken":
                u = replace(u, text="left unpaired as at the initial model (modes are paired by frequency there and "
                            "followed by MAC from then on): " + u.text)
            out.append(u)
        return tuple(out)
