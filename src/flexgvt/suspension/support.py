"""The support-structure system of docs/method.md section 2: two equal masses m joined by the structure
(k_st, c_st), each hung on a support (k_sup, c_sup). The true structural frequency and damping
from the suspended ones, as a quick check before the full model is built."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from ..errors import ModelError


@dataclass(frozen=True)
class SupportCorrection:
    """True structural frequency [Hz] and damping ratio from the suspended (measured) ones."""

    frequency_hz: float
    damping_ratio: float
    frequency_shift_percent: float  # (measured - true) / true
    damping_shift_percent: float


def support_correction(measured_hz: float, measured_damping: float, support_hz: float,
                       support_damping: float) -> SupportCorrection:
    """w_st^2 = w_m^2 - w_sup^2; z_st w_st = z_m w_m - z_sup w_sup (docs/method.md section 2).

    measured_*: the suspended elastic mode; support_*: the suspension mode alone (k_sup/m,
    c_sup/(2 m w_sup)), e.g. from a block test (SuspensionPoint.frequency_hz, .damping_ratio)."""
    vals = np.array([measured_hz, measured_damping, support_hz, support_damping], float)
    if not np.all(np.isfinite(vals)) or measured_hz <= 0 or support_hz < 0 or measured_damping < 0 or \
            support_damping < 0:
        raise ModelError("support_correction: frequencies > 0 (support >= 0) and damping ratios >= 0")
    if support_hz >= measured_hz:
        raise ModelError(f"support_correction: the support mode ({support_hz} Hz) is not below the measured mode "
                         f"({measured_hz} Hz); this two-mass model does not apply")
    wm, ws = 2 * np.pi * measured_hz, 2 * np.pi * support_hz
    wst = np.sqrt(wm**2 - ws**2)
    zst = (measured_damping * wm - support_damping * ws) / wst
    f = wst / (2 * np.pi)
    return SupportCorrection(float(f), float(zst), float(100 * (measured_hz - f) / f),
                             float(100 * (measured_damping - zst) / zst) if zst != 0 else float("inf"))


def two_mass_model(m: float, k_sup: float, c_sup: float, k_st: float, c_st: float) -> list[tuple[float, float]]:
    """Complex eigenvalues s (rad/s) of the 2-DOF support-structure model, as (frequency_hz,
    damping_ratio) of its two modes in ascending frequency: (support mode, structural mode)."""
    M = np.diag([m, m])
    C = np.array([[c_sup + c_st / 2, -c_st / 2], [-c_st / 2, c_sup + c_st / 2]])
    K = np.array([[k_sup + k_st / 2, -k_st / 2], [-k_st / 2, k_sup + k_st / 2]])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    s = sla.eigvals(A)
    s = s[s.imag >= 0] if np.sum(s.imag > 0) == 2 else s[np.argsort(np.abs(s))][::2]
    wn = np.abs(s)
    order = np.argsort(wn)
    return [(float(wn[k] / (2 * np.pi)), float(-s[k].real / wn[k])) for k in order]
