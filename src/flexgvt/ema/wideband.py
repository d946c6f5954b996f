"""Modes over a wide band (0.1 Hz suspension modes to 100 Hz elastic modes): PolyMAX in sub-bands,
their physical poles merged, then one LSFD over the whole band.

One z-domain polynomial over decades of frequency cannot resolve the lowest modes: their poles
crowd at z = 1 (the sampling time is set by the highest frequency), so a single fit misses them
whatever the model order. Each sub-band gets its own sampling time instead.
"""

from __future__ import annotations

import numpy as np

from ..errors import EMAError
from .polymax import ModalSet, lsfd, polymax


def wide_band_bands(f_lo: float, f_hi: float, ratio: float = 4.0, overlap: float = 0.15) -> list[tuple[float, float]]:
    """Geometric sub-bands from f_lo to f_hi [Hz], each spanning about ``ratio`` and overlapping its
    neighbour by ``overlap`` (a mode near an edge lies well inside one of them)."""
    if not (0 < f_lo < f_hi) or ratio <= 1:
        raise EMAError("wide-band identification needs 0 < f_lo < f_hi and a band ratio above 1")
    n = max(1, int(np.ceil(np.log(f_hi / f_lo) / np.log(ratio))))
    edges = np.geomspace(f_lo, f_hi, n + 1)
    return [(max(f_lo, edges[k] / (1 + overlap)), min(f_hi, edges[k + 1] * (1 + overlap))) for k in range(n)]


def identify_wide_band(frfs, frequency_band=None, bands=None, max_order: int = 40, weighting: str = "unit",
                       min_fraction: float = 0.3, tol_f: float = 0.01) -> ModalSet:
    """Modes of ``frfs`` over ``frequency_band`` (default: the whole axis above 0) from PolyMAX fitted
    band by band (``bands``: list of (f_lo, f_hi) [Hz]; default wide_band_bands of the band).

    Each sub-band's automatic selection gives poles and participation factors; a mode found in two
    overlapping bands is kept from the band where it lies farther from the edges; the shapes come
    from one LSFD with residuals over the whole band, weighted by 1/|H| so that the weak
    high-frequency modes of FRFs spanning decades are fitted on their own lines. Model orders are capped per band by its
    number of lines.
    """
    freq = np.asarray(frfs.frequencies_hz, float)
    H = np.asarray(frfs.H)
    lo, hi = frequency_band if frequency_band is not None else (freq[freq > 0].min(), freq.max())
    bands = wide_band_bands(lo, hi) if bands is None else [tuple(map(float, b)) for b in bands]
    n_i = H.shape[2]
    found = []  # (s, L, centrality in its band, band index)
    for ib, (b_lo, b_hi) in enumerate(bands):
        lines = int(np.sum((freq >= b_lo) & (freq <= b_hi) & (freq > 0)))
        order = min(int(max_order), lines // (2 * n_i) - 1)
        if order < 2:
            raise EMAError(f"band {b_lo:g}-{b_hi:g} Hz has only {lines} frequency lines; widen it or measure "
                           "with a finer resolution")
        try:
            sel = polymax((freq, H), max_order=order, frequency_band=(b_lo, b_hi), weighting=weighting) \
                .select(min_fraction=min_fraction, tol_f=tol_f)
        except EMAError:
            continue  # no physical pole in this band
        wn = 2 * np.pi * sel.frequencies_hz
        s = -sel.damping_ratio * wn + 1j * wn * np.sqrt(np.clip(1 - sel.damping_ratio ** 2, 0, None))
        centre = np.log(np.sqrt(b_lo * b_hi))
        half = 0.5 * np.log(b_hi / b_lo)
        for k in range(len(s)):
            centrality = 1 - abs(np.log(sel.frequencies_hz[k]) - centre) / half
            found.append((s[k], sel.participation[k], centrality, ib))
    if not found:
        raise EMAError("no physical pole in any sub-band: raise max_order or check the FRFs")
    # Duplicates from overlapping bands: the same mode within tol_f found in another band (two
    # poles of one band are two modes, however close).
    found.sort(key=lambda p: -p[2])
    kept = []
    for s, L, c, ib in found:
        if all(jb == ib or abs(abs(s) / abs(t) - 1) > tol_f for t, _, _, jb in kept):
            kept.append((s, L, c, ib))
    kept.sort(key=lambda p: abs(p[0]))
    s = np.array([p[0] for p in kept])
    L = np.array([p[1] for p in kept])
    band = (freq >= lo) & (freq <= hi)
    return lsfd(freq[band], H[band], s, L, frfs.outputs, frfs.inputs, weighting="inverse")
