"""Mode indicators and quality measures: MIF, MPC, MPD, FRAC and the FRFs re-synthesised from identified
modes, checked against values worked out by hand."""

import numpy as np
import pytest

from flexgvt.ema import ModalModel, frac, mif, mpc, mpd, resynthesize, synthesize_frfs


def test_mpc_is_one_for_real_modes_and_known_for_complex_ones():
    real = np.array([[1.0, -2.0, 3.0], [0.5, 0.0, -1.0]])
    assert mpc(real) == pytest.approx([1.0, 1.0])
    assert mpc(real * np.exp(0.7j)) == pytest.approx([1.0, 1.0])  # a real mode at any phase
    # [1, i]: Re.Re = Im.Im = 1, Re.Im = 0 -> equal eigenvalues -> 0
    # [1, 1 + i]: [[2, 1], [1, 1]] -> l = (3 +- sqrt 5)/2 -> ((l1 - l2)/(l1 + l2))^2 = 5/9
    assert mpc(np.array([[1.0, 1j], [1.0, 1 + 1j]])) == pytest.approx([0.0, 5 / 9])
    assert mpc(np.array([1.0, 1j, 0.0])).shape == (1,)


def test_mpd_is_zero_for_real_modes_and_the_phase_spread_otherwise():
    assert mpd(np.array([[1.0, -2.0, 3.0]]) * np.exp(0.3j)) == pytest.approx([0.0], abs=1e-6)
    # [1, i]: any line is 45 deg from both; [1, e^{i 30 deg}]: the best line bisects, 15 deg from each
    spread = np.array([[1.0, 1j], [1.0, np.exp(1j * np.radians(30))]])
    assert mpd(spread) == pytest.approx([45.0, 15.0])


def _single_dof(f, fn=2.0, z=0.02):
    w, wn = 2 * np.pi * f, 2 * np.pi * fn
    return 1 / (wn**2 - w**2 + 2j * z * wn * w)


def test_mif_dips_to_zero_at_a_normal_mode_and_is_one_far_from_it():
    f = np.array([0.2, 2.0, 20.0])
    H = np.stack([_single_dof(f) * a for a in (1.0, -0.5, 2.0)], axis=1)[:, :, None]  # (3, 3, 1)
    m = mif(H)
    assert m.shape == (3, 1)
    assert m[1, 0] == pytest.approx(0.0, abs=1e-12)  # at 2 Hz: H purely imaginary
    assert m[0, 0] > 0.99 and m[2, 0] > 0.99


def test_frac_is_one_for_a_scaled_copy_and_lower_for_a_shifted_mode():
    f = np.linspace(0.5, 4.0, 400)
    a = _single_dof(f)
    assert frac(a, 3.0 * a) == pytest.approx(1.0)
    assert frac(a, _single_dof(f, fn=2.2)) < 0.3


def test_resynthesize_reproduces_the_frfs_of_known_modes():
    rng = np.random.default_rng(3)
    model = ModalModel(np.array([1.3, 2.9, 4.4]), np.array([0.01, 0.02, 0.015]), rng.normal(size=(3, 6)))
    frfs = synthesize_frfs(model, np.linspace(0.0, 6.0, 601), np.arange(6), [0, 4])
    Hs = resynthesize(frfs.frequencies_hz, frfs.H, model.frequencies_hz, model.damping_ratio)
    err = np.abs(Hs[1:] - frfs.H[1:]).max() / np.abs(frfs.H).max()
    assert err < 1e-8
    assert frac(frfs.H[1:], Hs[1:]) == pytest.approx(np.ones((6, 2)))
    assert np.all(Hs[0] == 0)  # the 0 Hz line is left out


def test_resynthesize_takes_modes_outside_the_band_into_its_residual_terms():
    """A strong mode below the band (0.4 Hz) seen from 1-6 Hz: the lower residual term takes it; without
    residual terms the in-band modes alone explain less of the FRFs."""
    rng = np.random.default_rng(5)
    shapes = rng.normal(size=(3, 5)) * [[5.0], [1.0], [1.0]]
    model = ModalModel(np.array([0.4, 2.1, 3.7]), np.array([0.02, 0.02, 0.02]), shapes)
    frfs = synthesize_frfs(model, np.linspace(1.0, 6.0, 501), np.arange(5), [0])
    with_res = frac(frfs.H, resynthesize(frfs.frequencies_hz, frfs.H, [2.1, 3.7], [0.02, 0.02]))
    without = frac(frfs.H, resynthesize(frfs.frequencies_hz, frfs.H, [2.1, 3.7], [0.02, 0.02], residuals=False))
    assert np.all(with_res > 0.998) and np.all(without < 0.5)
