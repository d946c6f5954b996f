"""The identified-modes container (ModalSet, flexgvt.modal's one type for every set of modes) and
the FRF-array check shared by PolyMAX, LSFD, refinement and selection: the bottom of ema, so that
polymax, refine and selection import it and not each other in a circle."""

from __future__ import annotations

import numpy as np

from ..errors import EMAError
from ..modal import FRFs, ModalSet

__all__ = ["ModalSet", "as_frfs", "checked_frfs", "warn_flag"]


def as_frfs(frfs) -> FRFs:
    """The FRFs every EMA function takes: FRFs as they are; a tuple (frequencies_hz, H) as FRFs without
    DOF labels."""
    if isinstance(frfs, FRFs):
        return frfs
    if isinstance(frfs, tuple) and len(frfs) == 2:
        return FRFs(*frfs)
    if hasattr(frfs, "frequencies_hz") and hasattr(frfs, "H"):  # a look-alike (e.g. a user's own container)
        return FRFs(frfs.frequencies_hz, frfs.H, getattr(frfs, "outputs", None), getattr(frfs, "inputs", None),
                    variance=getattr(frfs, "variance", None))
    raise EMAError(f"expected FRFs (flexgvt.modal.FRFs, e.g. read_uff(path).frfs or estimate_frf(...)) or a tuple "
                   f"(frequencies_hz, H), got {type(frfs).__name__}")


def warn_flag(function: str, flag: str, instead: str) -> None:
    """DeprecationWarning for a flag that changed a function's return type (one result object now)."""
    import warnings

    warnings.warn(f"{function}({flag}=True) is deprecated: {function} returns one ModalSet; read {instead}",
                  DeprecationWarning, stacklevel=3)


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
