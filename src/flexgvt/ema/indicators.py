"""Mode indicator functions (CMIF, MIF), mode complexity (MPC, MPD), FRF synthesis from identified
modes and its correlation with the measured FRFs (FRAC)."""

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


def mif(H: np.ndarray) -> np.ndarray:
    """Real mode indicator function per reference, (n_freq, n_in): sum_o |Re H_oi| |H_oi| / sum_o |H_oi|^2,
    between 0 and 1. Near 1 off resonance, it dips towards 0 at each normal mode a reference excites
    (the response is then in quadrature with the force). For receptance and accelerance FRFs; for
    mobility (velocity) the response is in phase at resonance: use 1 - mif."""
    H = np.asarray(H)
    if H.ndim == 2:
        H = H[:, :, None]
    mag = np.abs(H)
    den = np.sum(mag**2, axis=1)
    return np.sum(np.abs(H.real) * mag, axis=1) / np.where(den > 0, den, 1.0)


def mpc(shapes: np.ndarray) -> np.ndarray:
    """Modal phase collinearity of each shape (rows of (n_modes, n_dofs), or one (n_dofs,) shape):
    ((l1 - l2) / (l1 + l2))^2 with l1 >= l2 the eigenvalues of [[Re.Re, Re.Im], [Re.Im, Im.Im]].
    1 for a real (normal) mode whatever its phase, 0 when the real and imaginary parts are orthogonal
    with equal norms (a travelling wave)."""
    S = np.atleast_2d(np.asarray(shapes))
    re, im = S.real, S.imag
    sxx, syy, sxy = np.sum(re * re, axis=1), np.sum(im * im, axis=1), np.sum(re * im, axis=1)
    tr = sxx + syy
    det = sxx * syy - sxy**2
    gap2 = np.maximum(tr**2 - 4 * det, 0.0)  # (l1 - l2)^2
    return gap2 / np.where(tr > 0, tr**2, 1.0)


def mpd(shapes: np.ndarray) -> np.ndarray:
    """Mean phase deviation [deg] of each shape (rows of (n_modes, n_dofs)): the amplitude-weighted
    mean angle between each component and the shape's best straight line in the complex plane
    (Reynders et al. 2012; the line from the SVD of [Re, Im]). 0 for a real mode, 45 for [1, i]."""
    S = np.atleast_2d(np.asarray(shapes, dtype=complex))
    out = np.zeros(len(S))
    for k, phi in enumerate(S):
        w = np.abs(phi)
        if not np.any(w > 0):
            continue
        _, _, vt = np.linalg.svd(np.column_stack([phi.real, phi.imag]), full_matrices=False)
        v12, v22 = vt[1, 0], vt[1, 1]  # the least-significant direction: the line's normal
        cos = np.abs(phi.real * v22 - phi.imag * v12) / (np.hypot(v12, v22) * np.where(w > 0, w, 1.0))
        out[k] = np.degrees(np.sum(w * np.arccos(np.clip(cos, 0.0, 1.0))) / np.sum(w))
    return out


def frac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Frequency response assurance criterion of FRFs a and b (n_freq, ...), per FRF over the frequency
    axis: |sum a conj(b)|^2 / (sum |a|^2 sum |b|^2); 1 when b is a scaled copy of a, 0 where a curve is zero."""
    a, b = np.asarray(a), np.asarray(b)
    num = np.abs(np.sum(a * b.conj(), axis=0)) ** 2
    den = np.sum(np.abs(a) ** 2, axis=0) * np.sum(np.abs(b) ** 2, axis=0)
    return num / np.where(den > 0, den, 1.0)


def resynthesize(frequencies_hz, H: np.ndarray, modal_frequencies_hz, damping_ratio,
                 residuals: bool = True) -> np.ndarray:
    """FRFs (n_freq, n_out, n_in) synthesised from identified modes (frequencies [Hz], damping ratios)
    with their residues fitted to the measured H by least squares (one problem, every FRF a right-hand
    side, as flexgvt.ema.lsfd), and with ``residuals`` a lower (-R/w^2: the modes below the band) and an
    upper (constant: those above) residual term per FRF, as a test system's synthesis. Lines at 0 Hz
    are left at 0."""
    f = np.asarray(frequencies_hz, float)
    H = np.asarray(H)
    wn = 2 * np.pi * np.asarray(modal_frequencies_hz, float)
    z = np.asarray(damping_ratio, float)
    s = -z * wn + 1j * wn * np.sqrt(np.clip(1 - z**2, 0.0, None))
    pos = f > 0
    w = 2 * np.pi * f[pos]
    iw = 1j * w[:, None]
    P, Pc = 1 / (iw - s[None, :]), 1 / (iw - s.conj()[None, :])
    cols = [P + Pc, 1j * P - 1j * Pc]  # real and imaginary parts of each residue
    if residuals:
        cols += [(-1 / w**2)[:, None].astype(complex), np.ones((len(w), 1), complex)]
    A = np.hstack(cols)
    B = H[pos].reshape(len(w), -1)
    x, *_ = np.linalg.lstsq(np.vstack([A.real, A.imag]), np.vstack([B.real, B.imag]), rcond=None)
    out = np.zeros(H.shape, complex)
    out[pos] = (A @ x).reshape((len(w),) + H.shape[1:])
    return out
