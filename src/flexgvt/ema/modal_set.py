"""The identified-modes container (ModalSet) and the FRF-array check shared by PolyMAX, LSFD,
refinement and selection: the bottom of ema, so that polymax, refine and selection import it
and not each other in a circle."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import EMAError


@dataclass(frozen=True)
class ModalSet:
    """Identified modes: frequencies_hz, damping_ratio (n_modes,); shapes (n_modes, n_outputs)
    complex (normalised to a unit largest component); participation (n_modes, n_inputs);
    residues (n_modes, n_outputs, n_inputs); outputs/inputs as in the FRFs; frequency_std_hz and
    damping_std (n_modes,) standard deviations where known (maximum-likelihood refinement, averaging
    of repeated tests), else None."""

    frequencies_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    participation: np.ndarray
    residues: np.ndarray
    outputs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    inputs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    frequency_std_hz: np.ndarray | None = None  # (n_modes,) standard deviation [Hz], e.g. from refine()
    damping_std: np.ndarray | None = None  # (n_modes,) standard deviation of the damping ratio


def checked_frfs(freq, H, frequency_band=None, where: str = ""):
    """(frequencies_hz, H, in-band mask, (f_lo, f_hi)) of FRF arrays, checked: H (n_freq, n_out, n_in) on the
    frequency axis, finite; the band (default: the whole axis above 0) keeps lines above 0 Hz."""
    prefix = f"{where}: " if where else ""
    freq = np.asarray(freq, float)
    H = np.asarray(H)
    if H.ndim != 3 or H.shape[0] != len(freq):
        raise EMAError(f"{prefix}H must have shape (n_freq, n_outputs, n_inputs) matching {len(freq)} frequencies, "
                       f"got {H.shape}")
    if not np.all(np.isfinite(H)):
        raise EMAError(f"{prefix}the FRFs contain NaN or infinite values; remove the bad channels first")
    if not np.all(np.isfinite(freq)) or not np.any(freq > 0):
        raise EMAError(f"{prefix}the frequency axis must be finite with lines above 0 Hz")
    lo, hi = frequency_band if frequency_band is not None else (freq[freq > 0].min(), freq.max())
    keep = (freq >= lo) & (freq <= hi) & (freq > 0)
    if not np.any(keep):
        raise EMAError(f"{prefix}no frequency line in the band {lo:g}-{hi:g} Hz (the FRFs span "
                       f"{freq.min():g}-{freq.max():g} Hz)")
    big = float(np.abs(H[keep]).max())
    if big > 1e150:  # its square overflows the fits' products
        raise EMAError(f"{prefix}an FRF value of magnitude {big:.3g} (a corrupt value?) is too large to fit; "
                       "check the file or remove the channel")
    return freq, H, keep, (lo, hi)
