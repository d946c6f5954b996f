"""A GVT-like synthetic case (issue 22): two references, 24 uniaxial channels, 0.05 Hz lines to 10 Hz;
two suspension modes at 0.22/0.29 Hz with 8/6 % damping (the second weakly excited: the references
sit near its node line), a pair of light modes 0.04 Hz apart at 2.00/2.04 Hz (closer than the line
spacing) and six more modes to 7.8 Hz."""

import numpy as np

from flexgvt.ema import ModalModel, estimate_frf, synthesize_frfs, synthesize_time_data

FN = np.array([0.22, 0.29, 0.95, 1.60, 2.00, 2.04, 3.30, 4.70, 6.20, 7.80])
ZETA = np.array([0.08, 0.06, 0.02, 0.015, 0.008, 0.01, 0.012, 0.015, 0.02, 0.01])
REFS = [3, 17]
N_OUT = 24
MAX_ORDER = 50


def model(seed: int) -> ModalModel:
    rng = np.random.default_rng(100 + seed)
    x = np.linspace(-1, 1, N_OUT)
    shapes = rng.standard_normal((len(FN), N_OUT))
    shapes[0] = 1 + 0.1 * rng.standard_normal(N_OUT)  # plunge on the suspension
    shapes[1] = x + 0.1 * rng.standard_normal(N_OUT)  # roll about the middle
    shapes[1, REFS] *= 0.2  # references near its node line: weakly excited
    return ModalModel(FN, ZETA, shapes)


def frfs(seed: int, snr_db: float):
    """FRFs with complex noise relative to each line's magnitude (variance |H|^2 / 10^(snr/10))."""
    f = np.arange(1, 201) * 0.05
    return synthesize_frfs(model(seed), f, list(range(N_OUT)), REFS, snr_db=snr_db, seed=seed)


def time_frfs(seed: int, snr_db: float = 40.0, records: int = 16):
    """H1 from time data: periodic random excitation of both references, one 20 s record per block
    (rectangular window, leakage-free), response noise at snr_db of each channel's power; the
    FRFEstimate carries the per-line variances of the averaging."""
    m = model(seed)
    fs, T = 25.6, 20.0
    force, resp = [], []
    for k in range(records):
        _, fo, y = synthesize_time_data(m, fs, T, list(range(N_OUT)), REFS, snr_db=snr_db, seed=1000 * seed + k)
        force.append(fo)
        resp.append(y)
    return estimate_frf(np.hstack(force), np.hstack(resp), fs, nperseg=int(fs * T), overlap=0.0, window="rect")


def match(found_hz, tol: float = 0.02):
    """Index of the identified mode nearest each true mode (-1 if none within tol), spurious indices."""
    found_hz = np.asarray(found_hz)
    idx = np.array([int(np.argmin(np.abs(found_hz / f - 1))) if len(found_hz) and
                    np.min(np.abs(found_hz / f - 1)) < tol else -1 for f in FN])
    spurious = [j for j in range(len(found_hz)) if j not in idx]
    return idx, spurious
