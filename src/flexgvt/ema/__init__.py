"""Experimental modal analysis: FRF estimation, PolyMAX with stabilisation and automatic pole selection, LSFD,
maximum-likelihood refinement with uncertainty (refine, identify), averaging of repeated tests,
synthetic GVT data. free-decay identification, CMIF. Figures of these are in flexgvt.report.plots."""

from .free_decay import FreeDecay, free_decay, free_decay_from_peaks
from .indicators import cmif, frac, mif, mpc, mpd, resynthesize, synthesize_from_modes
from .polymax import ModalSet, Stabilisation, identify, lsfd, polymax
from .refine import RefineInfo, frf_variance_from_coherence, mode_significance, refine
from .selection import Cluster, clusters, select_ml
from .repeated import average_tests
from .wideband import identify_wide_band, wide_band_bands
from .synthetic import ModalModel, modal_model_from_modes, synthesize_frfs, synthesize_time_data
from .frf import (FRFEstimate, estimate_frf, estimate_frf_from_time, exponential_window,
                  exponential_window_damping, force_window, hann,
                  spectra, stepped_sine_frf)

__all__ = ["RefineInfo", "frf_variance_from_coherence", "mode_significance", "refine", "Cluster", "clusters",
           "identify", "select_ml", "average_tests", "cmif", "frac", "mif", "mpc", "mpd", "resynthesize",
           "synthesize_from_modes", "FreeDecay", "free_decay",
           "free_decay_from_peaks", "ModalSet", "Stabilisation", "lsfd", "polymax", "identify_wide_band",
           "wide_band_bands", "ModalModel", "modal_model_from_modes", "synthesize_frfs", "synthesize_time_data",
           "FRFEstimate", "estimate_frf", "estimate_frf_from_time",
           "exponential_window", "exponential_window_damping", "force_window", "hann",
           "spectra", "stepped_sine_frf"]
