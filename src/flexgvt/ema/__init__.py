"""Experimental modal analysis: FRF estimation and synthetic GVT data (PolyMAX, LSFD, stabilisation, CMIF and
free-decay identification are not written yet)."""

from .synthetic import ModalModel, modal_model_from_modes, synthesize_frfs, synthesize_time_data
from .frf import (FRFEstimate, estimate_frf, exponential_window, exponential_window_damping, force_window, hann,
                  spectra, stepped_sine_frf)

__all__ = ["ModalModel", "modal_model_from_modes", "synthesize_frfs", "synthesize_time_data", "FRFEstimate", "estimate_frf", "exponential_window", "exponential_window_damping", "force_window", "hann",
           "spectra", "stepped_sine_frf"]
