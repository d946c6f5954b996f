"""Synthetic GVT data: FRFs and time histories from modal parameters or from a flexgvt modal
result, at chosen test points and references, with noise at a chosen SNR (seeded)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import EMAError
from ..modal import FRFs

_QUANTITY_POWER = {"receptance": 0, "mobility": 1, "accelerance": 2}


@dataclass(frozen=True)
class ModalModel:
    """frequencies_hz (n,), damping_ratio (n,), shapes (n, n_dof) real, mass-normalised at the test DOFs."""

    frequencies_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray


def modal_model_from_modes(modes, points) -> tuple[ModalModel, np.ndarray]:
    """Project a flexgvt Modes result (shapes (n_modes, n_nodes, 6), mass-normalised) onto test DOFs.

    points: iterable of (node_id, direction vector) -> (ModalModel, dofs (n, 2) as (node id, index)).
    Damping: the modes' damping ratios (zero without dampers)."""
    node_ids = np.asarray(modes.node_ids)
    cols, dofs = [], []
    for k, (node, direction) in enumerate(points):
        rows = np.flatnonzero(node_ids == node)
        if not len(rows):
            raise EMAError(f"test point {k}: node {node} is not in the modal result")
        d = np.asarray(direction, float)
        d = d / np.linalg.norm(d)
        cols.append(modes.shapes[:, rows[0], :3] @ d)
        dofs.append((int(node), k))
    return ModalModel(np.asarray(modes.frequencies_hz, float), np.asarray(modes.damping_ratio, float),
                      np.column_stack(cols)), np.array(dofs)


def synthesize_frfs(model: ModalModel, frequencies_hz, outputs, inputs, quantity: str = "receptance",
                    snr_db: float | None = None, seed: int = 0, noise: str = "relative") -> FRFs:
    """FRFs H (n_freq, n_out, n_in) of a viscously (proportionally) damped modal model.

    outputs/inputs: indices into the model's DOFs. quantity: receptance, mobility or accelerance.
    snr_db: complex Gaussian noise at this signal-to-noise ratio; noise='relative' scales it with the
    FRF's magnitude at each line (a measurement's noise floor follows its signal), 'uniform' uses
    each FRF's mean power (then weak high-frequency modes drown).
    """
    if quantity not in _QUANTITY_POWER:
        raise EMAError(f"quantity '{quantity}' must be one of {sorted(_QUANTITY_POWER)}")
    w = 2 * np.pi * np.asarray(frequencies_hz, float)
    wn = 2 * np.pi * model.frequencies_hz
    z = model.damping_ratio
    phi_o = model.shapes[:, outputs]  # (n_modes, n_out)
    phi_i = model.shapes[:, inputs]
    denom = wn[None, :] ** 2 - w[:, None] ** 2 + 2j * z[None, :] * wn[None, :] * w[:, None]
    H = np.einsum("mo,mi,fm->foi", phi_o, phi_i, 1.0 / denom)
    H = H * (1j * w[:, None, None]) ** _QUANTITY_POWER[quantity]
    if snr_db is not None:
        rng = np.random.default_rng(seed)
        if noise not in ("relative", "uniform"):
            raise EMAError("noise must be 'relative' or 'uniform'")
        power = np.abs(H) ** 2 if noise == "relative" else np.mean(np.abs(H) ** 2, axis=0, keepdims=True)
        sigma = np.sqrt(power / 10 ** (snr_db / 10) / 2)
        H = H + sigma * (rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape))
    idx = np.arange(model.shapes.shape[1])
    outs = np.column_stack([idx[outputs], np.full(len(outputs), 3)])
    ins = np.column_stack([idx[inputs], np.full(len(inputs), 3)])
    return FRFs(np.asarray(frequencies_hz, float), H, outs, ins, quantity)


def synthesize_time_data(model: ModalModel, fs: float, duration_s: float, outputs, inputs,
                         excitation: str = "random", snr_db: float | None = None, seed: int = 0):
    """Force (n_in, n_t) and response (n_out, n_t) time histories (receptance, frequency-domain
    synthesis: the response is the inverse FFT of H times the force's FFT). excitation: 'random' (white
    noise on each input, uncorrelated) or 'impact' (a 4-sample hammer pulse on each input in turn,
    the record split in equal parts). Returns (t, force, response)."""
    rng = np.random.default_rng(seed)
    n = int(round(duration_s * fs))
    t = np.arange(n) / fs
    n_in = len(inputs)
    force = np.zeros((n_in, n))
    if excitation == "random":
        force = rng.standard_normal((n_in, n))
    elif excitation == "impact":
        part = n // n_in
        for k in range(n_in):
            force[k, k * part + 10:k * part + 14] = np.hanning(4) * 100.0
    else:
        raise EMAError("excitation must be 'random' or 'impact'")
    # Frequency-domain synthesis: exact at the record's FFT lines (the record is treated as
    # periodic, so make it long enough for the slowest mode to decay or use random excitation).
    f = np.fft.rfftfreq(n, 1 / fs)
    H = synthesize_frfs(model, f, outputs, inputs).H  # (n_f, n_out, n_in)
    response = np.fft.irfft(np.einsum("foi,if->of", H, np.fft.rfft(force, axis=1)), n=n, axis=1)
    if snr_db is not None:
        p = np.mean(response**2, axis=1, keepdims=True)
        response = response + np.sqrt(p / 10 ** (snr_db / 10)) * rng.standard_normal(response.shape)
    return t, force, response
