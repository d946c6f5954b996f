"""Automatic modal identification on hard GVT data: PolyMAX candidates from the stabilisation diagram,
maximum-likelihood refinement, and a likelihood-ratio test deciding which poles are physical.

Criteria (`identify`):

1. Strong clusters: stable poles (frequency 1 %, damping 5 %, participation MAC 0.98 between
   consecutive orders) within tol_f of each other in at least min_fraction of the orders (as
   `Stabilisation.select()`).
2. Weak clusters: the remaining stable poles grouped by frequency (gaps under tol_f or half a line),
   present in at least min_orders distinct orders (a narrow band of orders is enough: heavily damped
   or weakly excited modes stabilise late or only briefly, and wander by a fraction of a line), whose
   participation vectors agree (MAC with the cluster's median pole >= min_mac across references) and
   whose damping stays under max_damping.
3. Poles within two lines of the band edges are left out (an edge pole models the out-of-band modes).
4. The strong set is refined (`refine`); then each weak cluster, most orders first, is tried as an
   extra mode: kept if the refinement is accepted, the new mode is significant and none of the others
   loses significance, and it is not a duplicate (within 3 standard deviations in frequency and
   damping of a kept mode).
5. Significance: the increase of the chi-square-scaled weighted cost when the mode's shape is set to
   zero (likelihood ratio / Wald statistic, 2 n_outputs degrees of freedom), above the chi-square
   quantile at probability 1 - alpha (alpha = 1e-6 by default). Modes below it are dropped (weakest
   first, refining again after each).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

import numpy as np
from scipy.stats import chi2

from ..errors import EMAError
from .._threads import serial_blas
from ..modal import mac_paired
from .clustering import group_by_gap, representative, split_by_order
from .modal_set import ModalSet, warn_flag
from .refine import SignificanceScreen, refine


@dataclass(frozen=True)
class Cluster:
    """Stable poles of one candidate mode: representative pole s [rad/s] and participation L, the
    poles' orders, and whether it is strong (present in min_fraction of the orders)."""

    s: complex
    L: np.ndarray
    orders: np.ndarray
    frequencies_hz: np.ndarray
    strong: bool
    mac: float  # median participation MAC with the representative


def _macs(pts, idx, b):
    """MAC of the participation vectors of poles idx with b."""
    return mac_paired(np.array([pts[i][1] for i in idx]), b)


def clusters(stab, min_fraction: float = 0.3, tol_f: float = 0.01, min_orders: int = 4,
             min_mac: float = 0.9, max_damping: float = 0.3) -> list[Cluster]:
    """Candidate modes of a stabilisation diagram (stab: a `flexgvt.ema.Stabilisation`): strong
    clusters (as `select()`) and weak ones (criterion 2 of the module docstring), sorted by
    frequency; poles within two lines of the band
    edges left out."""
    pts = [(s, L, k) for k, (ss, Ls, st) in enumerate(zip(stab.poles, stab.participations, stab.stable))
           for s, L, ok in zip(ss, Ls, st) if ok]
    if not pts:
        return []
    f = np.array([abs(s) / (2 * np.pi) for s, _, _ in pts])
    lo, hi = stab.band
    fb = stab.frequencies_hz[(stab.frequencies_hz >= lo) & (stab.frequencies_hz <= hi) & (stab.frequencies_hz > 0)]
    df = float(np.median(np.diff(fb))) if len(fb) > 1 else 0.0
    f_lo, f_hi = fb.min() + 2 * df, fb.max() - 2 * df
    need = max(2, int(np.ceil(min_fraction * len(stab.orders))))
    out, used = [], np.zeros(len(pts), bool)
    order = np.argsort(f)
    for c in group_by_gap(order, f, lambda fi: tol_f * fi):
        for sub in split_by_order(c, pts, f):
            if len({pts[i][2] for i in sub}) < need:
                continue
            best = representative(pts, list(sub), f, tol_f)
            used[sub] = True
            if f_lo <= f[best] <= f_hi:
                macs = _macs(pts, sub, pts[best][1])
                out.append(Cluster(pts[best][0], pts[best][1], np.array([pts[i][2] for i in sub]), f[sub], True,
                                   float(np.median(macs))))
    # Weak clusters from the poles left: looser grouping (a weak pole wanders by a fraction of a line).
    rest = [i for i in order if not used[i]]
    if rest:
        groups = group_by_gap(rest, f, lambda fi: max(tol_f * fi, 0.5 * df))
        for c in groups:
            if len({pts[i][2] for i in c}) < min_orders:
                continue
            best = representative(pts, c, f, 5 * tol_f)
            macs = _macs(pts, c, pts[best][1])
            z = -pts[best][0].real / abs(pts[best][0])
            if np.median(macs) >= min_mac and z <= max_damping and f_lo <= f[best] <= f_hi:
                out.append(Cluster(pts[best][0], pts[best][1], np.array([pts[i][2] for i in c]), f[c], False,
                                   float(np.median(macs))))
    out.sort(key=lambda c: abs(c.s))
    return out


def _subset(ms: ModalSet, keep) -> ModalSet:
    keep = np.asarray(keep, int)
    pick = lambda a: None if a is None else np.asarray(a)[keep]  # noqa: E731
    return replace(ms, frequencies_hz=ms.frequencies_hz[keep], damping_ratio=ms.damping_ratio[keep],
                   shapes=ms.shapes[keep], participation=ms.participation[keep], residues=ms.residues[keep],
                   frequency_std_hz=pick(ms.frequency_std_hz), damping_std=pick(ms.damping_std))


def _start(stab, poles, parts):
    """The refinement's start: poles s [rad/s] by |s| with their participations. `refine` takes only the
    frequencies, damping ratios and participations of a modal set (it fits shapes and residuals itself),
    so no LSFD here: the shapes and residues are left empty."""
    o = np.argsort(np.abs(poles))
    s, L = np.asarray(poles)[o], np.asarray(parts)[o]
    n_i = stab.H.shape[2]
    return ModalSet(np.abs(s) / (2 * np.pi), -s.real / np.abs(s), np.zeros((len(s), 0), complex), L,
                    np.zeros((len(s), 0, n_i), complex), stab.outputs, stab.inputs)


def _pole(ms):
    wn = 2 * np.pi * ms.frequencies_hz
    return -ms.damping_ratio * wn + 1j * wn * np.sqrt(1 - ms.damping_ratio ** 2)


@serial_blas  # as refine
def select_ml(stab, variance=None, alpha: float = 1e-6, min_fraction: float = 0.3,
              tol_f: float = 0.01, min_orders: int = 4, min_mac: float = 0.9, max_damping: float = 0.3,
              max_trials: int = 6, return_info: bool = False) -> ModalSet:
    """Physical modes of a stabilisation diagram (stab: a `flexgvt.ema.Stabilisation`) by the criteria of this
    module, refined by maximum
    likelihood with frequency_std_hz and damping_std. variance: as `refine` (default: estimated
    from the fit residual). Returns a ModalSet whose ``info`` holds the candidate clusters
    ('candidates'), the kept ones ('kept'), the refinement diagnostics ('refine', a RefineInfo), the
    likelihood-ratio 'threshold' and the trial 'log'; return_info=True (deprecated) returns
    (ModalSet, that dict) as before."""
    cands = clusters(stab, min_fraction, tol_f, min_orders, min_mac, max_damping)
    strong = [c for c in cands if c.strong]
    weak = sorted([c for c in cands if not c.strong], key=lambda c: -len(set(c.orders)))
    if not strong and not weak:
        raise EMAError("no stable pole cluster in the diagram: raise max_order or widen the frequency band")
    n_o = stab.H.shape[1]
    threshold = float(chi2.isf(alpha, 2 * n_o))
    from ..modal import FRFs

    frfs = FRFs(stab.frequencies_hz, stab.H, stab.outputs, stab.inputs)
    band = stab.band

    def fit(poles, parts, start_var):
        ms0 = _start(stab, poles, parts)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            ms = refine(frfs, ms0, variance=start_var, frequency_band=band)
        return ms, ms.info["refine"], [str(w.message) for w in caught]

    base = strong if strong else weak[:1]
    poles = [c.s for c in base]
    parts = [c.L for c in base]
    kept = list(base)
    ms, info, notes = fit(poles, parts, variance)
    # Drop insignificant modes, weakest first.
    while len(kept) > 1 and info.significance.min() < threshold:
        j = int(np.argmin(info.significance))
        del kept[j]
        ms = _subset(ms, [k for k in range(len(kept) + 1) if k != j])
        ms, info, notes = fit(_pole(ms), ms.participation, variance)
    log = []
    base_var = info.variance
    added = False
    tried = 0
    screen = None
    for i, c in enumerate(weak):
        if c in kept or tried >= max_trials:
            continue
        sd_f = ms.frequency_std_hz
        f_c = abs(c.s) / (2 * np.pi)
        if np.any(np.abs(ms.frequencies_hz - f_c) <= np.maximum(tol_f * f_c, 3 * sd_f)):
            log.append((round(f_c, 3), "near a kept mode"))
            continue  # already a kept mode there
        trial_s = np.r_[_pole(ms), c.s]
        trial_L = np.vstack([ms.participation / np.linalg.norm(ms.participation, axis=1, keepdims=True), c.L])
        # Screen at the candidate's PolyMAX pole (one linear solve): a pole that does not pass the test
        # there is not tried (a real mode's statistic is orders of magnitude above the threshold).
        # The kept set's weighted Gram is shared by every candidate, and the candidates left are
        # screened against it together (SignificanceScreen.many) until a candidate is kept.
        if screen is None:
            screen = SignificanceScreen(frfs, trial_s[:-1], trial_L[:-1], base_var, band)
            statistic = dict(zip(range(i, len(weak)), screen.many([w.s for w in weak[i:]], [w.L for w in weak[i:]])))
        if statistic[i] < threshold:
            continue
        tried += 1
        try:
            ms_t, info_t, notes_t = fit(trial_s, trial_L, base_var)
        except EMAError:
            continue
        log.append((round(f_c, 3), len(set(c.orders)), round(c.mac, 3), info_t.accepted,
                    np.round(np.sort(info_t.significance)[:3], 0)))
        if not info_t.accepted or info_t.significance.min() < threshold:
            continue
        # The new mode must not duplicate a kept one.
        new = int(np.argmin(np.abs(ms_t.frequencies_hz - abs(trial_s[-1]) / (2 * np.pi))))
        others = [k for k in range(len(ms_t.frequencies_hz)) if k != new]
        dup = any(abs(ms_t.frequencies_hz[k] - ms_t.frequencies_hz[new]) < 3 * np.hypot(
            ms_t.frequency_std_hz[k], ms_t.frequency_std_hz[new])
            and abs(ms_t.damping_ratio[k] - ms_t.damping_ratio[new])
            < 3 * np.hypot(ms_t.damping_std[k], ms_t.damping_std[new]) for k in others)
        if dup:
            continue
        ms, info, notes, kept = ms_t, info_t, notes_t, kept + [c]
        screen = None
        added = True
    if added and variance is None:  # final fit with the noise re-estimated from the final model
        ms, info, notes = fit(_pole(ms), ms.participation, None)
    for n in notes:
        warnings.warn(n, stacklevel=2)
    details = {"candidates": cands, "kept": kept, "refine": info, "threshold": threshold, "log": log}
    ms = ms.with_info(**details)
    if return_info:
        warn_flag("select_ml", "return_info", "result.info (candidates, kept, refine, threshold, log)")
        return ms, details
    return ms
