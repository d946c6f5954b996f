"""FRF estimation from time data: H1, H2, Hv with coherence, averaged over blocks or impacts;
Hann, force and exponential windows; stepped-sine FRFs (one complex amplitude per step).

Shapes: force (n_inputs, n_samples) or (n_samples,), response (n_outputs, n_samples); H is
(n_freq, n_outputs, n_inputs) like every FRF in flexgvt.
"""

from __future__ import annotations

import numpy as np

from ..errors import EMAError
from ..modal import FRFs


def FRFEstimate(frequencies_hz, H, coherence, n_averages: int, estimator: str, variance=None) -> FRFs:  # noqa: N802
    """An estimate as the one FRFs type (the former FRFEstimate's positional order): frequencies_hz
    (n_freq,); H (n_freq, n_out, n_in); coherence (n_freq, n_out); n_averages; estimator ('H1',
    'H2', 'Hv'); variance (n_freq, n_out, n_in) E|H_est - H|^2 per line [H units squared]."""
    return FRFs(frequencies_hz, H, coherence=coherence, variance=variance, n_averages=n_averages,
                estimator=estimator)


def hann(n: int) -> np.ndarray:
    """Periodic Hann window (random excitation)."""
    return 0.5 - 0.5 * np.cos(2 * np.pi * np.arange(n) / n)


def force_window(n: int, fs: float, duration_s: float, taper_s: float = 0.0) -> np.ndarray:
    """Rectangular window over the impact (first duration_s seconds) with an optional cosine taper:
    removes the noise the force channel records after the hammer has left [fs in Hz]."""
    t = np.arange(n) / fs
    w = (t <= duration_s).astype(float)
    if taper_s > 0:
        edge = (t > duration_s) & (t <= duration_s + taper_s)
        w[edge] = 0.5 * (1 + np.cos(np.pi * (t[edge] - duration_s) / taper_s))
    return w


def exponential_window(n: int, fs: float, tau_s: float) -> np.ndarray:
    """exp(-t/tau) on the response of an impact test so it decays within the record."""
    return np.exp(-np.arange(n) / fs / tau_s)


def exponential_window_damping(frequency_hz, tau_s: float):
    """Damping ratio the exponential window adds to a mode, to subtract from identified values:
    sigma_added = 1/tau, so zeta_added = 1 / (tau * omega)."""
    return 1.0 / (tau_s * 2 * np.pi * np.asarray(frequency_hz, float))


def _as_2d(a, name):
    a = np.asarray(a, float)
    a = a[None, :] if a.ndim == 1 else a
    if a.ndim != 2:
        raise EMAError(f"{name} must have shape (n_channels, n_samples), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise EMAError(f"{name} contains NaN or infinite samples; remove the bad channel or record")
    return a


def _blocks(x: np.ndarray, nperseg: int, overlap: float) -> np.ndarray:
    step = max(int(round(nperseg * (1 - overlap))), 1)
    n = 1 + (x.shape[-1] - nperseg) // step
    if n < 1:
        raise EMAError(f"records of {x.shape[-1]} samples are shorter than one block of {nperseg}")
    idx = np.arange(nperseg)[None, :] + step * np.arange(n)[:, None]
    return x[:, idx]  # (channels, blocks, nperseg)


def spectra(force, response, fs: float, nperseg: int | None = None, overlap: float = 0.5, window="hann",
            response_window=None, records: int | None = None):
    """Averaged auto and cross spectra Gff (f, i, i), Gyf (f, o, i), Gyy (f, o).

    records: the signals hold this many separate records end to end (impact tests: one per
    hit; each is one block, no overlap); otherwise blocks of nperseg with overlap.
    window: 'hann', 'rect', or an array applied to the force (and to the response unless
    response_window is given, e.g. exponential for impacts).
    """
    f = _as_2d(force, "force")
    y = _as_2d(response, "response")
    if f.shape[1] != y.shape[1]:
        raise EMAError(f"force and response have {f.shape[1]} and {y.shape[1]} samples; they must be simultaneous")
    if records:
        nperseg = f.shape[1] // records
        fb = f[:, :records * nperseg].reshape(f.shape[0], records, nperseg)
        yb = y[:, :records * nperseg].reshape(y.shape[0], records, nperseg)
    else:
        nperseg = nperseg or f.shape[1]
        fb, yb = _blocks(f, nperseg, overlap), _blocks(y, nperseg, overlap)
    if isinstance(window, str):
        window = {"hann": hann(nperseg), "rect": np.ones(nperseg)}.get(window)
        if window is None:
            raise EMAError("window must be 'hann', 'rect' or an array")
    wy = window if response_window is None else response_window
    F = np.fft.rfft(fb * window, axis=-1)
    Y = np.fft.rfft(yb * wy, axis=-1)
    Gff = np.einsum("ibk,jbk->kij", F, F.conj()) / fb.shape[1]
    Gyf = np.einsum("obk,ibk->koi", Y, F.conj()) / fb.shape[1]
    Gyy = np.einsum("obk,obk->ko", Y, Y.conj()).real / fb.shape[1]
    return np.fft.rfftfreq(nperseg, 1 / fs), Gff, Gyf, Gyy, fb.shape[1]


def estimate_frf(force, response, fs: float, estimator: str = "H1", **kwargs) -> FRFs:
    """H1 (noise on the response), H2 (noise on the force, single input) or Hv (total least
    squares, single input) as FRFs with coherence (n_freq, n_out) (multiple coherence for several
    inputs), n_averages, estimator and variance (n_freq, n_out, n_in): E|H_est - H|^2 per line
    from the averaging [H units squared], the weights of flexgvt.ema.refine (noise on the
    response, independent blocks: overlapped windowed blocks are correlated and make it somewhat
    optimistic). kwargs go to :func:`spectra`."""
    if estimator not in ("H1", "H2", "Hv"):
        raise EMAError(f"estimator '{estimator}' must be 'H1', 'H2' or 'Hv'")
    freq, Gff, Gyf, Gyy, nav = spectra(force, response, fs, **kwargs)
    n_in = Gff.shape[1]
    if estimator != "H1" and n_in != 1:
        raise EMAError(f"{estimator} is defined here for one input; use H1 for {n_in} references")
    ok = np.abs(np.einsum("kii->k", Gff)) > 0
    Gff_safe = np.where(ok[:, None, None], Gff, np.eye(n_in))
    # H1 Gff = Gyf  ->  Gff^T H1^T = Gyf^T
    try:
        H1 = np.linalg.solve(np.swapaxes(Gff_safe, 1, 2), np.swapaxes(Gyf, 1, 2)).swapaxes(1, 2)
    except np.linalg.LinAlgError:
        raise EMAError("the force spectral matrix is singular: the references are fully correlated; excite "
                       "with uncorrelated signals (independent random generators) or use one reference") from None
    # Multiple (or ordinary) coherence: |H1 Gff H1^H| / Gyy per output.
    explained = np.einsum("koi,kij,koj->ko", H1, Gff_safe, H1.conj()).real
    coherence = np.clip(explained / np.where(Gyy > 0, Gyy, 1.0), 0.0, 1.0)
    # Variance of H1 by regression over the blocks: Var(H_oi) = G_nn,o [Gff^-1]_ii / (n - n_in), with
    # G_nn,o = Gyy_o (1 - coh_o) the response's uncorrelated (noise) spectrum (Bendat & Piersol).
    Gnn = np.maximum(Gyy - explained, 0.0)
    Ginv = np.linalg.inv(Gff_safe)
    diag = np.einsum("kii->ki", Ginv).real
    dof = max(nav - n_in, 1)
    variance = Gnn[:, :, None] * diag[:, None, :] / dof
    tiny = 1e-12 * np.maximum(np.max(np.abs(H1) ** 2, axis=0, keepdims=True), 1e-300)
    variance = np.maximum(variance, tiny)
    if estimator == "H1":
        H = H1
    else:
        gff = Gff[:, 0, 0].real[:, None]
        gyf = Gyf[:, :, 0]
        if estimator == "H2":
            H = (Gyy / np.where(np.abs(gyf.conj()) > 0, gyf.conj(), 1.0))[:, :, None]
        else:
            # Hv: the smallest-eigenvalue vector of [[Gff, Gfy], [Gyf, Gyy]] per output (total least squares).
            d = gff - Gyy
            root = np.sqrt(d * d + 4 * np.abs(gyf) ** 2)
            H = ((Gyy - gff + root) / (2 * np.where(np.abs(gyf.conj()) > 0, gyf.conj(), 1.0)))[:, :, None]
    return FRFs(freq, H, coherence=coherence, variance=variance, n_averages=nav, estimator=estimator)


def stepped_sine_frf(steps) -> tuple[np.ndarray, np.ndarray]:
    """FRF of a stepped-sine test: steps is an iterable of (frequency_hz, t, force, response) with
    force (n_t,) and response (n_out, n_t) sampled at times t [s] over whole cycles of one step.
    Each signal's complex amplitude at the step frequency is a least-squares fit of
    a cos + b sin + c; returns (frequencies_hz (n_steps,), H (n_steps, n_out, 1))."""
    freqs, rows = [], []
    for fhz, t, force, response in steps:
        t = np.asarray(t, float)
        basis = np.column_stack([np.cos(2 * np.pi * fhz * t), np.sin(2 * np.pi * fhz * t), np.ones_like(t)])
        y = np.vstack([np.asarray(force, float)[None, :], np.atleast_2d(np.asarray(response, float))])
        if not np.all(np.isfinite(y)):
            raise EMAError(f"stepped sine step at {fhz} Hz contains NaN samples")
        coef, *_ = np.linalg.lstsq(basis, y.T, rcond=None)
        amp = coef[0] - 1j * coef[1]  # a cos + b sin = Re((a - i b) e^{i w t})
        if abs(amp[0]) == 0:
            raise EMAError(f"no force at the step frequency {fhz} Hz")
        freqs.append(fhz)
        rows.append(amp[1:] / amp[0])
    return np.array(freqs), np.array(rows)[:, :, None]


def estimate_frf_from_time(histories, references=None, estimator: str = "H1", **kwargs) -> FRFs:
    """FRFs from simultaneous time histories (flexgvt.io.uff.TimeHistories, e.g. read_time_histories(path)):
    the reference (force) channels are ``references`` [(point, direction code)] or those the file marks
    as forces; every other channel is a response. kwargs go to :func:`estimate_frf` (nperseg, overlap,
    window, records...). The FRFs carry the channels' DOF labels and 'response unit/force unit'."""
    force, response, inputs, outputs = histories.signals(references)
    est = estimate_frf(force, response, histories.sample_rate_hz, estimator, **kwargs)
    units = getattr(histories, "units", ())
    dofs = [tuple(d) for d in np.asarray(histories.dofs).tolist()]
    label = ""
    if units and len(units) == len(dofs):
        label = f"{units[dofs.index(tuple(outputs[0]))]}/{units[dofs.index(tuple(inputs[0]))]}"
    return FRFs(est.frequencies_hz, est.H, outputs, inputs, label, est.coherence, est.variance, est.n_averages,
                est.estimator)
