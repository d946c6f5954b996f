"""Wide-band identification: suspension modes at 0.25-0.9 Hz (8 % damping) and elastic modes to
80 Hz (1 %, a pair 1 % apart) in one 0.1-100 Hz measurement, which a single PolyMAX fit cannot
resolve (its lowest poles crowd at z = 1)."""

import numpy as np
import pytest

from flexgvt.errors import EMAError
from flexgvt.ema import identify_wide_band, polymax, wide_band_bands
from flexgvt.ema.synthetic import ModalModel, synthesize_frfs


def _system():
    rng = np.random.default_rng(3)
    f = np.geomspace(0.25, 80.0, 20)
    f[8] = f[7] * 1.01  # a pair 1 % apart
    z = np.where(f < 1.0, 0.08, 0.01)
    x = np.linspace(0.0, 1.0, 30)
    shapes = np.array([np.sin((k + 1) * np.pi * x + 0.2 * k) + 0.3 * rng.normal(size=30) for k in range(20)])
    model = ModalModel(f, z, shapes)
    freq = np.linspace(0.01, 100.0, 10000)
    return model, synthesize_frfs(model, freq, np.arange(30), [3, 17], quantity="receptance", snr_db=30.0, seed=1)


def _mac(a, b):
    return abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)


def test_wide_band_finds_every_mode_from_0_25_to_80_hz():
    model, frfs = _system()
    single = polymax(frfs, max_order=80, frequency_band=(0.1, 100.0)).select()
    assert len(single.frequencies_hz) < 15  # the one-fit limitation this function exists for
    modes = identify_wide_band(frfs, frequency_band=(0.1, 100.0))
    assert len(modes.frequencies_hz) == 20  # none missed, none spurious
    for k, (f, z) in enumerate(zip(model.frequencies_hz, model.damping_ratio)):
        j = int(np.argmin(np.abs(modes.frequencies_hz - f)))
        assert abs(modes.frequencies_hz[j] / f - 1) < 0.002
        assert abs(modes.damping_ratio[j] / z - 1) < 0.10
        assert _mac(model.shapes[k], modes.shapes[j]) > 0.999  # 1/|H|-weighted LSFD (unit weights: 0.990 at 80 Hz)


def test_bands_cover_the_range_with_overlap_and_bad_input():
    bands = wide_band_bands(0.1, 100.0)
    assert bands[0][0] == pytest.approx(0.1) and bands[-1][1] == pytest.approx(100.0)
    assert all(b[0] < a[1] for a, b in zip(bands, bands[1:]))  # neighbours overlap
    with pytest.raises(EMAError, match="f_lo < f_hi"):
        wide_band_bands(10.0, 1.0)
    _, frfs = _system()
    with pytest.raises(EMAError, match="frequency lines"):
        identify_wide_band(frfs, bands=[(0.1, 0.12)])


def test_lsfd_weighting_is_checked():
    model, frfs = _system()
    from flexgvt.ema.polymax import lsfd
    with pytest.raises(EMAError, match="weighting"):
        lsfd(frfs.frequencies_hz, frfs.H, np.array([-1 + 10j]), weighting="log")
