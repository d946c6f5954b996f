"""A suspension point characterised as its own one-DOF system (docs/method.md section 2).

Hang a rigid block of the mass the point carries on the same string, spring, adapters and
pulley, excite it, identify its damped frequency and damping ratio, then

    w_n = w_d / sqrt(1 - z^2),   K = M w_n^2,   C = 2 z w_n M.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError


@dataclass(frozen=True)
class SuspensionPoint:
    """An identified suspension point: block mass [kg], undamped and damped frequencies [Hz],
    damping ratio, stiffness K [N/m] and viscous damping C [N s/m], each with its standard
    deviation over repeated tests (0 for one test; propagated from the fit's uncertainty where a
    record was fitted) and the number of tests."""

    mass: float
    frequency_hz: float
    damped_frequency_hz: float
    damping_ratio: float
    stiffness: float
    damping: float
    frequency_std_hz: float = 0.0
    damping_ratio_std: float = 0.0
    stiffness_std: float = 0.0
    damping_std: float = 0.0
    n_tests: int = 1
    source: str = "frequency and damping"

    def to_dict(self) -> dict:
        """The point's values as a JSON-ready dictionary."""
        return {k: (float(v) if isinstance(v, (float, np.floating)) else v) for k, v in vars(self).items()}

    def as_dict(self) -> dict:
        """Deprecated: to_dict()."""
        warnings.warn("SuspensionPoint.as_dict() is deprecated; use SuspensionPoint.to_dict()", DeprecationWarning,
                      stacklevel=2)
        return self.to_dict()


def _values(mass, frequency_hz, damping_ratio):
    """K, C, wn from damped frequency [Hz], damping ratio and mass (vectorised)."""
    zeta = np.asarray(damping_ratio, float)
    wd = 2 * np.pi * np.asarray(frequency_hz, float)
    wn = wd / np.sqrt(1 - zeta**2)
    return mass * wn**2, 2 * zeta * wn * mass, wn


def identify_block(mass: float, frequency_hz: ArrayLike | None = None, damping_ratio: ArrayLike | None = None, *,
                   decay: tuple | list | None = None, peak_times: ArrayLike | None = None,
                   peak_amplitudes: ArrayLike | None = None, frf: tuple | None = None) -> SuspensionPoint:
    """Stiffness and damping of a suspension point from a block test.

    mass: the block's mass [kg] (the mass the point carries in the GVT). Give one of:
    frequency_hz (damped) and damping_ratio, scalars or one value per repeated test (the mean and
    the sample standard deviation are reported); decay=(t, x): a free-decay record (or a list of
    them: repeated tests); peak_times (and peak_amplitudes): successive peaks of the decay, e.g.
    a timer; frf=(frequencies_hz, H): the block's measured FRF (one input, one output).
    """
    if not (np.isfinite(mass) and mass > 0):
        raise ModelError(f"identify_block: the block mass must be a positive number of kg, got {mass!r}")
    given = [frequency_hz is not None, decay is not None, peak_times is not None, frf is not None]
    if sum(given) != 1:
        raise ModelError("identify_block: give exactly one of frequency_hz (+ damping_ratio), decay=(t, x), "
                         "peak_times (+ peak_amplitudes) or frf=(frequencies_hz, H)")
    fit_std = (0.0, 0.0)
    if frequency_hz is not None:
        if damping_ratio is None:
            raise ModelError("identify_block: give damping_ratio with frequency_hz (0 if it was not measured)")
        try:
            f = np.atleast_1d(np.asarray(frequency_hz, float))
            z = np.asarray(damping_ratio, float)
        except (TypeError, ValueError):
            raise ModelError("identify_block: frequency_hz and damping_ratio must be numbers or lists of numbers, "
                             f"got {frequency_hz!r}, {damping_ratio!r}") from None
        if f.ndim != 1 or f.size == 0 or z.ndim > 1 or (z.ndim == 1 and z.shape != f.shape):
            raise ModelError(f"identify_block: {f.size} frequencies and {z.size} damping ratios; give one damping "
                             "ratio per frequency (repeated tests), or one damping ratio for all")
        z = np.broadcast_to(z, f.shape)
        source = "frequency and damping"
    else:
        from ..ema.free_decay import free_decay, free_decay_from_peaks
        if decay is not None:
            records = [decay] if len(decay) == 2 and np.ndim(decay[0]) == 1 else list(decay)
            fits = [free_decay(t, x) for t, x in records]
            source = "free decay"
        elif peak_times is not None:
            fits = [free_decay_from_peaks(peak_times, peak_amplitudes)]
            source = "peak times"
        else:
            fits = [_fit_frf(*frf)]
            source = "FRF"
        f = np.array([r.damped_frequency_hz for r in fits])
        z = np.array([0.0 if np.isnan(r.damping_ratio) else r.damping_ratio for r in fits])
        if len(fits) == 1:
            fit_std = (fits[0].frequency_std_hz, 0.0 if np.isnan(fits[0].damping_std) else fits[0].damping_std)
    if np.any(~np.isfinite(f)) or np.any(f <= 0) or np.any(~np.isfinite(z)) or np.any((z < 0) | (z >= 1)):
        raise ModelError(f"identify_block: frequencies must be > 0 and damping ratios in [0, 1), got {f}, {z}")
    K, C, wn = _values(mass, f, z)
    n = len(f)

    def std(a):
        return float(np.std(a, ddof=1)) if n > 1 else 0.0

    fn = wn / (2 * np.pi)
    f_std = std(fn) if n > 1 else fit_std[0]
    z_std = std(z) if n > 1 else fit_std[1]
    # One fitted record: its uncertainty carried to K and C to first order.
    k_std = std(K) if n > 1 else float(2 * mass * wn[0] * 2 * np.pi * f_std)
    c_std = std(C) if n > 1 else float(np.hypot(2 * mass * wn[0] * z_std, 2 * mass * z[0] * 2 * np.pi * f_std))
    return SuspensionPoint(float(mass), float(fn.mean()), float(f.mean()), float(z.mean()), float(K.mean()),
                           float(C.mean()), f_std, z_std, k_std, c_std, n, source)


def _fit_frf(frequencies_hz, H):
    """Natural frequency and damping of the dominant mode of a single FRF (PolyMAX, low order)."""
    from ..ema.free_decay import FreeDecay
    from ..ema.polymax import polymax
    from ..io.uff import FRFs
    f = np.asarray(frequencies_hz, float)
    h = np.asarray(H, complex).reshape(len(f), 1, 1)
    if not np.all(np.isfinite(h)) or len(f) < 8:
        raise ModelError("identify_block: the FRF needs at least 8 finite lines")
    stab = polymax(FRFs(f, h, np.array([[1, 3]]), np.array([[1, 3]]), "accelerance"), max_order=8)
    modes = stab.select()
    if len(modes.frequencies_hz) == 0:
        raise ModelError("identify_block: no stable mode in the block's FRF; check the band and the coherence")
    k = int(np.argmax(np.abs(modes.residues[:, 0, 0]))) if modes.residues.size else 0
    fn, z = float(modes.frequencies_hz[k]), float(modes.damping_ratio[k])
    return FreeDecay(fn, fn * np.sqrt(1 - z * z), z, 0.0, 0.0, 0.0, 0.0)


def modulus_from_tip_load(force: float, length: float, deflection: float, second_moment: float) -> float:
    """Equivalent modulus [Pa] of a cantilevered spar from a tip-load test: E = F L^3 / (3 delta I)
    (force [N], length [m], tip deflection [m], second moment of area [m^4])."""
    vals = np.array([force, length, deflection, second_moment], float)
    if not np.all(np.isfinite(vals)) or np.any(vals[1:] <= 0) or force == 0:
        raise ModelError("modulus_from_tip_load: force non-zero, length, deflection and I positive and finite")
    return float(abs(force) * length**3 / (3 * deflection * second_moment))
