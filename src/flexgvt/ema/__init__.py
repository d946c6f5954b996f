"""Experimental modal analysis: FRF estimation, PolyMAX with stabilisation and automatic pole selection, LSFD,
synthetic GVT data. (Not written yet: CMIF, free-decay identification, figures, `flexgvt ema` command.)"""

from .polymax import ModalSet, Stabilisation, lsfd, polymax
from .synthetic import ModalModel, modal_model_from_modes, synthesize_frfs, synthesize_time_data
from .frf import (FRFEstimate, estimate_frf, exponential_window, exponential_window_damping, force_window, hann,
                  spectra, stepped_sine_frf)

__all__ = ["ModalSet", "Stabilisation", "lsfd", "polymax", "ModalModel", "modal_model_from_modes", "synthesize_frfs", "synthesize_time_data", "FRFEstimate", "estimate_frf", "exponential_window", "exponential_window_damping", "force_window", "hann",
           "spectra", "stepped_sine_frf"]
