"""One FRFs type from both producers: the UFF reader and the estimators."""

import numpy as np

import flexgvt as fg
from flexgvt.io.uff import write_uff
from flexgvt.modal import FRFs


def test_frfs_from_the_uff_reader_and_from_the_estimator(tmp_path):
    rng = np.random.default_rng(0)
    fs, n = 64.0, 64 * 64
    force = rng.standard_normal(n)
    h = np.exp(-np.arange(32) / 6.0) * np.sin(np.arange(32) / 2.0)  # a decaying impulse response
    response = np.convolve(force, h)[:n] + 0.01 * rng.standard_normal(n)
    est = fg.ema.estimate_frf(force, response[None, :], fs, nperseg=256)
    assert isinstance(est, FRFs) and est.estimator == "H1" and est.n_averages > 1
    assert est.coherence.shape == est.H.shape[:2] and est.variance.shape == est.H.shape
    assert est.outputs.shape == (0, 2)  # an estimate from time data has no DOF labels until given
    old = fg.ema.FRFEstimate(est.frequencies_hz, est.H, est.coherence, est.n_averages, "H1", est.variance)
    assert isinstance(old, FRFs) and old.variance is est.variance
    labelled = FRFs(est.frequencies_hz[1:], est.H[1:], [(2, 3)], [(1, 3)], "m/N")
    read = fg.io.read_uff(write_uff(tmp_path / "h.uff", frfs=labelled)).frfs
    assert isinstance(read, FRFs) and read.coherence is None and read.variance is None
    assert read.outputs.tolist() == [[2, 3]] and read.inputs.tolist() == [[1, 3]]
    np.testing.assert_allclose(read.H, labelled.H, rtol=1e-10)
    # Both go to PolyMAX alike.
    for frfs in (est, read):
        stab = fg.ema.polymax(frfs, max_order=6)
        assert len(stab.orders) == 6
