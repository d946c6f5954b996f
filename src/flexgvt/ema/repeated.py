"""Repeated tests of one configuration: modes paired across tests and averaged with their spread."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import EMAError
from ..modal import mac_rows
from .modal_set import ModalSet, warn_flag


def average_tests(modal_sets, tol_f: float = 0.05, min_mac: float = 0.8, min_tests: int | None = None,
                  return_table: bool = False) -> ModalSet:
    """Average the modes of repeated tests (ModalSets of the same outputs) with their spread.

    Modes are paired with those of the test holding the most modes: in each other test, the mode
    within tol_f (relative frequency) with the highest shape MAC, at least min_mac, each used once.
    A mode kept must be found in min_tests tests (default: more than half of them).
    Returns a ModalSet: mean frequency [Hz] and damping, shapes averaged after phase alignment;
    frequency_std_hz and damping_std are the sample standard deviations over the tests (the
    spread, as a GVT report gives it), or the single test's own standard deviations when a mode is
    found once. ``result.info['tests']``: {"frequencies_hz", "damping_ratio"} each (n_modes, n_tests)
    with NaN where a test missed the mode, "n_tests" (n_modes,); return_table=True (deprecated)
    returns (ModalSet, that table) as before.
    """
    sets = list(modal_sets)
    if not sets:
        raise EMAError("average_tests: no modal set given")
    n_out = {np.asarray(s.shapes).shape[1] for s in sets if len(s.frequencies_hz)}
    if len(n_out) > 1:
        raise EMAError(f"average_tests: the tests have different numbers of outputs {sorted(n_out)}; average tests "
                       "of one configuration measured at the same points")
    n_t = len(sets)
    need = min_tests if min_tests is not None else n_t // 2 + 1
    ref_k = int(np.argmax([len(s.frequencies_hz) for s in sets]))
    ref = sets[ref_k]
    n_m = len(ref.frequencies_hz)
    F = np.full((n_m, n_t), np.nan)
    Z = np.full((n_m, n_t), np.nan)
    FS = np.full((n_m, n_t), np.nan)
    ZS = np.full((n_m, n_t), np.nan)
    shapes = [[None] * n_t for _ in range(n_m)]
    idx = [[None] * n_t for _ in range(n_m)]
    for t, s in enumerate(sets):
        f = np.asarray(s.frequencies_hz, float)
        used = set()
        pairs = []
        macs = mac_rows(np.asarray(s.shapes), np.asarray(ref.shapes)) if len(f) and n_m else None
        for m in range(n_m):
            for j in range(len(f)):
                if abs(f[j] / ref.frequencies_hz[m] - 1) <= tol_f:
                    mac = float(macs[j, m])
                    if mac >= min_mac:
                        pairs.append((mac, m, j))
        for _mac, m, j in sorted(pairs, reverse=True):
            if idx[m][t] is not None or j in used:
                continue
            idx[m][t] = j
            used.add(j)
            F[m, t], Z[m, t] = f[j], s.damping_ratio[j]
            if s.frequency_std_hz is not None:
                FS[m, t] = s.frequency_std_hz[j]
            if s.damping_std is not None:
                ZS[m, t] = s.damping_std[j]
            phi = np.asarray(s.shapes[j], complex)
            a = np.vdot(phi, ref.shapes[m])  # align phase and scale to the reference shape
            shapes[m][t] = phi * a / max(abs(a), 1e-300) / np.linalg.norm(phi)
    count = np.sum(np.isfinite(F), axis=1)
    keep = np.flatnonzero(count >= need)
    if len(keep) < n_m:
        warnings.warn(f"average_tests: {n_m - len(keep)} mode(s) found in fewer than {need} of {n_t} tests left out "
                      f"({', '.join(f'{ref.frequencies_hz[m]:.4g} Hz' for m in range(n_m) if m not in keep)})",
                      stacklevel=2)
    fm = np.array([np.nanmean(F[m]) for m in keep])
    zm = np.array([np.nanmean(Z[m]) for m in keep])

    def spread(A, own, m):
        vals = A[m][np.isfinite(A[m])]
        if len(vals) >= 2:
            return float(np.std(vals, ddof=1))
        o = own[m][np.isfinite(own[m])]
        return float(o[0]) if len(o) else np.nan

    fs = np.array([spread(F, FS, m) for m in keep])
    zs = np.array([spread(Z, ZS, m) for m in keep])
    sh = []
    for m in keep:
        mean = np.mean([p for p in shapes[m] if p is not None], axis=0)
        sh.append(mean / mean[np.argmax(np.abs(mean))])
    sh = np.array(sh).reshape(len(keep), -1)
    part = (np.asarray(ref.participation)[keep] if ref.participation is not None
            and len(np.asarray(ref.participation)) == n_m else np.zeros((len(keep), 0)))
    res = (np.asarray(ref.residues)[keep] if ref.residues is not None and len(np.asarray(ref.residues)) == n_m
           else np.zeros((len(keep), 0, 0)))
    table = {"frequencies_hz": F[keep], "damping_ratio": Z[keep], "n_tests": count[keep]}
    out = ModalSet(fm, zm, sh, part, res, ref.outputs, ref.inputs, frequency_std_hz=fs, damping_std=zs,
                   info={"tests": table})
    if return_table:
        warn_flag("average_tests", "return_table", "result.info['tests']")
        return out, table
    return out
