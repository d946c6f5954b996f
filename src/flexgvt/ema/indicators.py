"""Mode indicator functions and FRF synthesis from identified modes."""

from __future__ import annotations

import numpy as np


def cmif(H: np.ndarray) -> np.ndarray:
    """Complex mode indicator function: singular values of H(w) per line, (n_freq, min(n_out, n_in)),
    descending. Peaks of the first curve mark modes; peaks in the second at the same frequency mark
    repeated or close modes (count them to choose the number of references)."""
    return np.linalg.svd(np.asarray(H), compute_uv=False)


def synthesize_from_modes(modes, frequencies_hz) -> np.ndarray:
    """FRFs (n_freq, n_out, n_in) rebuilt from a ModalSet's poles and residues (no residual terms)."""
    w = 2 * np.pi * np.asarray(frequencies_hz, float)
    wn = 2 * np.pi * modes.frequencies_hz
    z = modes.damping_ratio
    s = -z * wn + 1j * wn * np.sqrt(1 - z**2)
    iw = 1j * w[:, None]
    P = 1 / (iw - s[None, :])
    Pc = 1 / (iw - s.conj()[None, :])
    R = modes.residues
    return np.einsum("fm,moi->foi", P, R) + np.einsum("fm,moi->foi", Pc, R.conj())
