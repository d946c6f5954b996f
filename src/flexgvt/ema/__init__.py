"""Experimental modal analysis: FRF estimation (more to come: PolyMAX, LSFD, stabilisation, CMIF, free decay)."""

from .frf import (FRFEstimate, estimate_frf, exponential_window, exponential_window_damping, force_window, hann,
                  spectra, stepped_sine_frf)

__all__ = ["FRFEstimate", "estimate_frf", "exponential_window", "exponential_window_damping", "force_window", "hann",
           "spectra", "stepped_sine_frf"]
