"""Free-decay identification against known damped oscillators (suspension characterisation)."""

import numpy as np
import pytest

from flexgvt.ema import free_decay, free_decay_from_peaks
from flexgvt.errors import EMAError


def decay(fn, zeta, t, amp=1.0, phase=0.4):
    wn = 2 * np.pi * fn
    wd = wn * np.sqrt(1 - zeta**2)
    return amp * np.exp(-zeta * wn * t) * np.cos(wd * t + phase)


@pytest.mark.parametrize("fn, zeta", [(0.40, 0.07), (0.41, 0.11), (1.07, 0.045), (0.28, 0.047)])
def test_time_record_of_a_suspension_block(fn, zeta):
    """docs/method.md section 2's suspension tests: 0.28-1.07 Hz, 4.5-11 % damping; DC accelerometer at
    50 Hz for 20 s with 2 % noise."""
    rng = np.random.default_rng(int(fn * 100))
    t = np.arange(0, 20, 0.02)
    x = decay(fn, zeta, t) + 0.02 * rng.standard_normal(len(t)) + 0.1
    r = free_decay(t, x)
    assert abs(r.frequency_hz / fn - 1) < 2e-3
    assert abs(r.damping_ratio / zeta - 1) < 0.05
    assert abs(r.frequency_hz - fn) < 4 * r.frequency_std_hz + 1e-6
    assert abs(r.damping_ratio - zeta) < 4 * r.damping_std


def test_stopwatch_peak_times():
    """Peaks of a 0.40 Hz, 7 % damped pendulum timed by hand (0.05 s reaction scatter) and their
    amplitudes read off a scale (1 % scatter)."""
    rng = np.random.default_rng(3)
    fn, zeta = 0.40, 0.07
    wn = 2 * np.pi * fn
    wd = wn * np.sqrt(1 - zeta**2)
    tk = np.arange(8) * 2 * np.pi / wd
    peaks = tk + 0.05 * rng.standard_normal(8)
    amps = np.exp(-zeta * wn * tk) * (1 + 0.01 * rng.standard_normal(8))
    r = free_decay_from_peaks(peaks, amps)
    assert abs(r.damped_frequency_hz / (wd / (2 * np.pi)) - 1) < 0.01
    assert abs(r.damping_ratio / zeta - 1) < 0.1
    assert abs(r.damped_frequency_hz - wd / (2 * np.pi)) < 4 * r.damped_frequency_std_hz
    only_times = free_decay_from_peaks(peaks)
    assert np.isnan(only_times.damping_ratio) and abs(only_times.frequency_hz / (wd / (2 * np.pi)) - 1) < 0.01


def test_bad_records():
    with pytest.raises(EMAError, match="NaN"):
        free_decay(np.arange(100.0), np.r_[np.ones(99), np.nan])
    with pytest.raises(EMAError, match="at least 3"):
        free_decay_from_peaks([1.0, 2.0])
    with pytest.raises(EMAError, match="do not decay"):
        free_decay_from_peaks([0, 2.5, 5, 7.5], [1, 1.1, 1.2, 1.3])
