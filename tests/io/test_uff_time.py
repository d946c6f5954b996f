"""Time histories (58 type 1) through UFF to FRFs with the ema estimators."""

import numpy as np
import pytest

from flexgvt.ema import ModalModel, estimate_frf_from_time, synthesize_frfs, synthesize_time_data
from flexgvt.errors import FileFormatError
from flexgvt.io.uff import TimeHistories, read_time_histories, read_uff, write_uff

MODEL = ModalModel(np.array([3.0, 7.5, 12.0]), np.array([0.03, 0.02, 0.02]),
                   np.array([[1.0, 0.6, -0.4], [0.5, -0.8, 0.7], [0.3, 0.9, 0.6]]))
FS = 64.0


@pytest.fixture(scope="module")
def uff_pair(tmp_path_factory):
    """A force channel (point 100, +Z, N) and three displacement responses written as UFF 58 type 1."""
    _, force, resp = synthesize_time_data(MODEL, FS, 512.0, [0, 1, 2], [0], snr_db=20, seed=3)
    th = TimeHistories(np.vstack([force, resp]), np.array([[100, 3], [1, 3], [2, 3], [3, -2]]), FS,
                       units=("N", "m", "m", "m"), spec_types=(13, 8, 8, 8))
    return write_uff(tmp_path_factory.mktemp("th") / "time.uff", time_histories=th), th


def test_time_histories_round_trip(uff_pair):
    path, th = uff_pair
    back = read_time_histories(path)
    assert back.sample_rate_hz == pytest.approx(FS) and back.dofs.tolist() == th.dofs.tolist()
    assert back.units == ("N", "m", "m", "m") and back.spec_types == (13, 8, 8, 8)
    np.testing.assert_allclose(back.data, th.data, rtol=1e-10, atol=1e-12 * np.abs(th.data).max())
    force, resp, inputs, outputs = back.signals()
    assert inputs.tolist() == [[100, 3]] and outputs.tolist() == [[1, 3], [2, 3], [3, -2]]
    with pytest.raises(FileFormatError, match=r"no FRF .*4 time responses.*estimate FRFs"):
        _ = read_uff(path).frfs


@pytest.mark.parametrize("estimator", ["H1", "Hv"])
def test_frfs_estimated_from_uff_time_data_reproduce_the_synthetic_frf(uff_pair, estimator):
    path, _ = uff_pair
    frfs = estimate_frf_from_time(read_time_histories(path), estimator=estimator, nperseg=1024)
    assert frfs.outputs.tolist() == [[1, 3], [2, 3], [3, -2]] and frfs.inputs.tolist() == [[100, 3]]
    assert frfs.units == "m/N" and frfs.n_averages == 63 and frfs.estimator == estimator
    true = synthesize_frfs(MODEL, frfs.frequencies_hz, [0, 1, 2], [0]).H
    band = (frfs.frequencies_hz > 1.0) & (frfs.frequencies_hz < 20.0)
    # |H_est - H|^2 / variance is ~ exponential with mean 1 when the estimator's variance is right:
    # mean near 1 (0.5..2), 99th percentile below 10 (exponential: 4.6; the overlapped Hann blocks
    # are correlated, so the variance is somewhat optimistic, as estimate_frf says). Measured: 1.12, 7.2.
    e = np.abs(frfs.H - true)[band] ** 2 / frfs.variance[band]
    assert 0.5 < e.mean() < 2.0 and np.quantile(e, 0.99) < 10.0
    # The tolerance is not empty: a 10 % gain error on one channel is far outside it.
    wrong = frfs.H[:, 0] * 1.1
    assert (np.abs(wrong - true[:, 0])[band] ** 2 / frfs.variance[band][:, 0]).mean() > 5


def test_reference_named_by_dof_and_errors(uff_pair):
    _, th = uff_pair
    plain = TimeHistories(th.data, th.dofs, FS)
    with pytest.raises(FileFormatError, match="no channel is marked as a force.*references="):
        estimate_frf_from_time(plain)
    frfs = estimate_frf_from_time(plain, references=[(100, 3)], nperseg=512)
    assert frfs.inputs.tolist() == [[100, 3]] and frfs.H.shape == (257, 3, 1)
    with pytest.raises(FileFormatError, match=r"reference 7\+X is not among the channels"):
        plain.signals([(7, 1)])
    with pytest.raises(FileFormatError, match="every channel is a reference"):
        plain.signals(th.dofs)
