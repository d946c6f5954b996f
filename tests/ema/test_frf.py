"""FRF estimators against a known system: bias as theory says, multi-input, stepped sine, impacts."""

import numpy as np
import pytest
from scipy import signal

from flexgvt.ema import estimate_frf, exponential_window, force_window, stepped_sine_frf
from flexgvt.errors import EMAError

FS = 256.0


def sdof(fn=8.0, zeta=0.05):
    """Receptance of a 1 kg SDOF as a discrete filter (bilinear) and its exact FRF."""
    wn = 2 * np.pi * fn
    b, a = signal.bilinear([1.0], [1.0, 2 * zeta * wn, wn * wn], fs=FS)
    return b, a


def true_frf(b, a, f):
    return signal.freqz(b, a, worN=f, fs=FS)[1]


def test_h1_and_h2_bias_as_theory_says():
    rng = np.random.default_rng(1)
    b, a = sdof()
    n = 2**18
    x = rng.standard_normal(n)
    y = signal.lfilter(b, a, x)
    nperseg = 1024
    # Noise on the response only: H1 unbiased, H2 biased upwards by (1 + Gnn/Gyy).
    ny = 0.3 * np.std(y) * rng.standard_normal(n)
    e1 = estimate_frf(x, y + ny, FS, "H1", nperseg=nperseg)
    e2 = estimate_frf(x, y + ny, FS, "H2", nperseg=nperseg)
    f = e1.frequencies_hz
    band = (f > 2) & (f < 40) & (np.abs(f - 8) > 1.5)  # away from the peak (leakage) and from DC
    H = true_frf(b, a, f)
    r1 = np.abs(e1.H[:, 0, 0]) / np.abs(H)
    r2 = np.abs(e2.H[:, 0, 0]) / np.abs(H)
    assert abs(np.median(r1[band]) - 1) < 0.03
    expected = 1 / e1.coherence[:, 0]  # H2/H1 = 1/coherence exactly
    np.testing.assert_allclose(np.abs(e2.H[:, 0, 0] / e1.H[:, 0, 0])[band], expected[band], rtol=1e-9)
    assert np.median(r2[band]) > 1.1
    # Noise on the force only: H2 unbiased, H1 biased downwards by Gxx / (Gxx + Gmm).
    nx = 0.5 * rng.standard_normal(n)
    e1 = estimate_frf(x + nx, y, FS, "H1", nperseg=nperseg)
    e2 = estimate_frf(x + nx, y, FS, "H2", nperseg=nperseg)
    r1 = np.abs(e1.H[:, 0, 0]) / np.abs(H)
    r2 = np.abs(e2.H[:, 0, 0]) / np.abs(H)
    assert abs(np.median(r1[band]) - 1 / (1 + 0.25)) < 0.03
    assert abs(np.median(r2[band]) - 1) < 0.03
    ev = estimate_frf(x + nx, y + ny, FS, "Hv", nperseg=nperseg)
    e1 = estimate_frf(x + nx, y + ny, FS, "H1", nperseg=nperseg)
    e2 = estimate_frf(x + nx, y + ny, FS, "H2", nperseg=nperseg)
    m1, m2, mv = (np.median(np.abs(e.H[:, 0, 0])[band] / np.abs(H)[band]) for e in (e1, e2, ev))
    assert m1 < mv < m2  # Hv lies between H1 and H2


def test_two_uncorrelated_inputs_recover_both_frfs():
    rng = np.random.default_rng(2)
    b1, a1 = sdof(8.0, 0.05)
    b2, a2 = sdof(20.0, 0.03)
    n = 2**17
    x = rng.standard_normal((2, n))
    y = np.vstack([signal.lfilter(b1, a1, x[0]) + signal.lfilter(b2, a2, x[1]),
                   signal.lfilter(b2, a2, x[0]) - 0.5 * signal.lfilter(b1, a1, x[1])])
    e = estimate_frf(x, y, FS, "H1", nperseg=1024)
    f = e.frequencies_hz
    band = (f > 2) & (f < 60)
    for o, i, (b, a, s) in ((0, 0, (b1, a1, 1)), (0, 1, (b2, a2, 1)), (1, 0, (b2, a2, 1)), (1, 1, (b1, a1, -0.5))):
        H = s * true_frf(b, a, f)
        err = np.abs(e.H[:, o, i] - H)[band] / np.abs(H)[band]
        assert np.median(err) < 0.03
    assert np.median(e.coherence[band]) > 0.95


def test_stepped_sine_gives_exact_complex_amplitudes():
    b, a = sdof()
    steps = []
    for fhz in np.arange(0.5, 10.01, 0.5):
        t = np.arange(int(10 * FS / fhz) + 1) / FS  # ten cycles
        H = true_frf(b, a, [fhz])[0]
        force = 2.0 * np.cos(2 * np.pi * fhz * t + 0.3)
        resp = 2.0 * np.abs(H) * np.cos(2 * np.pi * fhz * t + 0.3 + np.angle(H)) + 0.01
        steps.append((fhz, t, force, resp))
    f, H = stepped_sine_frf(steps)
    np.testing.assert_allclose(H[:, 0, 0], true_frf(b, a, f), rtol=1e-9)


def test_impact_averaging_with_force_and_exponential_windows():
    rng = np.random.default_rng(3)
    b, a = sdof(8.0, 0.02)
    n_rec, n = 5, 4096  # 16 s records
    fs = FS
    forces, responses = [], []
    for _ in range(n_rec):
        pulse = np.zeros(n)
        pulse[10:14] = np.hanning(4) * rng.uniform(50, 80)
        forces.append(pulse + 0.01 * rng.standard_normal(n))
        responses.append(signal.lfilter(b, a, pulse) + 1e-6 * rng.standard_normal(n))
    fw = force_window(n, fs, duration_s=0.1, taper_s=0.02)
    tau = 4.0
    ew = exponential_window(n, fs, tau)
    e = estimate_frf(np.concatenate(forces), np.concatenate(responses), fs, "H1", records=n_rec,
                     window=fw * ew, response_window=ew)
    f = e.frequencies_hz
    band = (f > 2) & (f < 40)
    # The exponential window r^n (r = exp(-1/(tau fs))) turns the system's H(z) into H(z/r): its
    # polynomial coefficients b_k, a_k become b_k r^k, a_k r^k (the added damping 1/tau per second).
    r = np.exp(-1 / (tau * fs))
    H_windowed = true_frf(b * r ** np.arange(len(b)), a * r ** np.arange(len(a)), f)
    err = np.abs(e.H[band, 0, 0] - H_windowed[band]) / np.abs(H_windowed[band])
    assert np.median(err) < 0.02
    assert e.n_averages == n_rec


def test_bad_time_data_gives_clear_errors():
    with pytest.raises(EMAError, match="NaN"):
        estimate_frf(np.array([1.0, np.nan, 2.0]), np.ones(3), FS)
    with pytest.raises(EMAError, match="simultaneous"):
        estimate_frf(np.ones(100), np.ones(90), FS)
    with pytest.raises(EMAError, match="one input"):
        estimate_frf(np.ones((2, 512)), np.ones((1, 512)), FS, "H2", nperseg=256)
    with pytest.raises(EMAError, match="fully correlated"):
        estimate_frf(np.tile(np.random.default_rng(0).standard_normal(512), (2, 1)), np.ones((1, 512)), FS,
                     nperseg=256)
