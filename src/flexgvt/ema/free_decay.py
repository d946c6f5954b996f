"""Free-decay identification: frequency and damping, with standard uncertainties, from a time
record of a hand- or hammer-excited body, or from the times (and amplitudes) of successive peaks
such as a stopwatch gives. Used to characterise suspension points (docs/method.md section 2)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.signal import hilbert

from ..errors import EMAError


@dataclass(frozen=True)
class FreeDecay:
    """natural frequency_hz and damped_frequency_hz [Hz], damping_ratio [-], each with a standard
    uncertainty (*_std), from n_cycles of decay."""

    frequency_hz: float
    damped_frequency_hz: float
    damping_ratio: float
    frequency_std_hz: float
    damped_frequency_std_hz: float
    damping_std: float
    n_cycles: float


def _finish(wd, sigma, cov, n_cycles) -> FreeDecay:
    """Natural frequency and damping from (omega_d, sigma) with first-order uncertainty propagation."""
    wn = np.hypot(wd, sigma)
    zeta = sigma / wn
    # d(wn)/d(wd, sigma) and d(zeta)/d(wd, sigma)
    J_wn = np.array([wd / wn, sigma / wn])
    J_z = np.array([-sigma * wd / wn**3, wd * wd / wn**3])
    var_wn = J_wn @ cov @ J_wn
    var_z = J_z @ cov @ J_z
    return FreeDecay(wn / (2 * np.pi), wd / (2 * np.pi), zeta, np.sqrt(var_wn) / (2 * np.pi),
                     np.sqrt(cov[0, 0]) / (2 * np.pi), np.sqrt(var_z), n_cycles)


def free_decay(t, x) -> FreeDecay:
    """Fit x(t) = A exp(-sigma t) cos(omega_d t + phi) + c by nonlinear least squares.

    Starting values from the spectrum peak and the slope of the log Hilbert envelope; the
    uncertainty is the least-squares covariance scaled by the residual variance. t [s], x any unit.
    """
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    if t.shape != x.shape or t.ndim != 1 or len(t) < 16:
        raise EMAError("free_decay needs two 1-D arrays t and x of equal length (at least 16 samples)")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x))):
        raise EMAError("free_decay: the record contains NaN or infinite samples")
    dt = np.diff(t)
    if np.any(dt <= 0):
        raise EMAError("free_decay: times must increase")
    xc = x - x.mean()
    n = len(x)
    spec = np.abs(np.fft.rfft(xc * np.hanning(n), 8 * n))
    freqs = np.fft.rfftfreq(8 * n, dt.mean())
    k = np.argmax(spec[1:]) + 1
    wd0 = 2 * np.pi * freqs[k]
    env = np.abs(hilbert(xc))
    core = slice(n // 10, n - n // 10)
    sigma0 = max(-np.polyfit(t[core], np.log(np.maximum(env[core], 1e-300)), 1)[0], 1e-6 * wd0)
    A0 = env[core][0] * np.exp(sigma0 * t[core][0])
    phi0 = np.angle(hilbert(xc)[n // 10]) - wd0 * t[n // 10]
    p0 = np.array([A0, sigma0, wd0, phi0, x.mean()])

    def resid(p):
        A, s, w, ph, c = p
        return A * np.exp(-s * t) * np.cos(w * t + ph) + c - x

    fit = least_squares(resid, p0, x_scale="jac", method="lm")
    if not fit.success:
        raise EMAError(f"free_decay: the damped-sinusoid fit did not converge ({fit.message}); trim the record to "
                       "the clean decay of one mode")
    dof = max(n - 5, 1)
    s2 = np.sum(fit.fun**2) / dof
    cov = np.linalg.pinv(fit.jac.T @ fit.jac) * s2
    A, sigma, wd, _, _ = fit.x
    if sigma <= 0 or wd <= 0:
        raise EMAError("free_decay: the record does not decay as one damped mode (growing or not oscillating)")
    cov_ws = cov[np.ix_([2, 1], [2, 1])]
    return _finish(wd, sigma, cov_ws, wd * (t[-1] - t[0]) / (2 * np.pi))


def free_decay_from_peaks(peak_times, amplitudes=None) -> FreeDecay:
    """Frequency (and damping, given the peak amplitudes) from successive peaks one period apart.

    The period is the slope of a straight-line fit of the peak times against their count, so
    independent timing errors (a stopwatch's reaction time) average out; the decay rate is the
    slope of log(amplitude) against time. Without amplitudes the damping is reported as NaN with
    the damped frequency taken as the natural one.
    """
    tk = np.asarray(peak_times, float)
    if tk.ndim != 1 or len(tk) < 3 or not np.all(np.isfinite(tk)) or np.any(np.diff(tk) <= 0):
        raise EMAError("free_decay_from_peaks needs at least 3 increasing, finite peak times")
    k = np.arange(len(tk))
    (T, t0), cov_T = np.polyfit(k, tk, 1, cov=True) if len(tk) > 3 else (np.polyfit(k, tk, 1), np.zeros((2, 2)))
    wd = 2 * np.pi / T
    var_wd = (2 * np.pi / T**2) ** 2 * cov_T[0, 0]
    if amplitudes is None:
        return FreeDecay(wd / (2 * np.pi), wd / (2 * np.pi), float("nan"), np.sqrt(var_wd) / (2 * np.pi),
                         np.sqrt(var_wd) / (2 * np.pi), float("nan"), float(len(tk) - 1))
    a = np.asarray(amplitudes, float)
    if a.shape != tk.shape or np.any(a <= 0) or not np.all(np.isfinite(a)):
        raise EMAError("amplitudes must be positive, finite and one per peak time")
    (slope, _), cov_a = np.polyfit(tk, np.log(a), 1, cov=True) if len(tk) > 3 else (np.polyfit(tk, np.log(a), 1),
                                                                                   np.zeros((2, 2)))
    sigma = -slope
    if sigma <= 0:
        raise EMAError("the peak amplitudes do not decay")
    cov = np.diag([var_wd, cov_a[0, 0]])
    return _finish(wd, sigma, cov, float(len(tk) - 1))
