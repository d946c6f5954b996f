"""Experimental modal analysis: FRF estimation, PolyMAX with stabilisation and automatic pole selection, LSFD,
synthetic GVT data. free-decay identification. CMIF and report figures (flexgvt.ema.plots)."""

from .free_decay import FreeDecay, free_decay, free_decay_from_peaks
from .indicators import cmif, synthesize_from_modes
from .polymax import ModalSet, Stabilisation, lsfd, polymax
from .wideband import identify_wide_band, wide_band_bands
from .synthetic import ModalModel, modal_model_from_modes, synthesize_frfs, synthesize_time_data
from .frf import (FRFEstimate, estimate_frf, exponential_window, exponential_window_damping, force_window, hann,
                  spectra, stepped_sine_frf)

__all__ = ["cmif", "synthesize_from_modes", "FreeDecay", "free_decay", "free_decay_from_peaks", "ModalSet", "Stabilisation", "lsfd", "polymax", "identify_wide_band", "wide_band_bands", "ModalModel", "modal_model_from_modes", "synthesize_frfs", "synthesize_time_data", "FRFEstimate", "estimate_frf", "exponential_window", "exponential_window_damping", "force_window", "hann",
           "spectra", "stepped_sine_frf"]
