"""[configurations.test] from real test-system exports: FRFs estimated from time histories (test.time),
incomplete channels dropped (drop_incomplete), files that hold something else named for what they hold."""

import warnings
from pathlib import Path

import numpy as np
import pytest

from flexgvt.ema import ModalModel, synthesize_frfs, synthesize_time_data
from flexgvt.errors import FlexGVTWarning
from flexgvt.io.uff import TimeHistories, write_uff
from flexgvt.workflow import identify_all, identify_configuration, load_project
from flexgvt.workflow.identification import read_modes
from flexgvt.workflow.projectbase import ProjectError

DATA = Path(__file__).parents[1] / "data" / "uff"
MODEL = ModalModel(np.array([3.0, 7.5, 12.0]), np.array([0.03, 0.02, 0.02]),
                   np.array([[1.0, 0.6, -0.4], [0.5, -0.8, 0.7], [0.3, 0.9, 0.6]]))

PROJECT = """
[model]
case = "strip_366"
[[configurations]]
name = "outboard"
from = "outboard"
role = "check"
[configurations.test]
%s
band_hz = [1.0, 20.0]
max_order = 24
"""


def _project(tmp_path, test: str):
    (tmp_path / "project.toml").write_text(PROJECT % test)
    return tmp_path / "project.toml"


@pytest.fixture
def time_file(tmp_path):
    """A force at point 100 +Z and displacements at nodes 1-3 +Z of the strip (points = nodes)."""
    _, force, resp = synthesize_time_data(MODEL, 64.0, 256.0, [0, 1, 2], [0], snr_db=30, seed=3)
    th = TimeHistories(np.vstack([force, resp]), np.array([[100, 3], [1, 3], [2, 3], [3, 3]]), 64.0,
                       units=("N", "m", "m", "m"), spec_types=(13, 8, 8, 8))
    return write_uff(tmp_path / "time.uff", time_histories=th)


def test_frfs_estimated_from_time_histories_are_identified(tmp_path, time_file):
    path = _project(tmp_path, 'time = "time.uff"\nreferences = ["100+Z"]\nestimator = "H1"\nnperseg = 1024')
    item = identify_configuration(load_project(path), "outboard")
    assert item.frfs.estimator == "H1" and item.frfs.n_averages == 31 and item.source == "time.uff"
    np.testing.assert_allclose(np.sort(item.frequencies_hz), MODEL.frequencies_hz, rtol=5e-3)


@pytest.mark.parametrize("test, match", [
    ('time = "time.uff"\nreferences = ["100Q"]', r"test\.references: '100Q' is not a test point.*100\+Z"),
    ('time = "time.uff"\nreferences = ["5+X"]', r"test\.time: 'time\.uff': .*5"),
    ('time = "time.uff"\nestimator = "H3"', r"estimator"),
    ('time = "time.uff"\nwindow = "flat"', r"window"),
    ('frfs = "time.uff"\nnperseg = 512', r"'nperseg' apply to FRFs estimated from time histories"),
    ('frfs = "time.uff"', r"no FRF .* 'time\.uff' holds .*time response.*give it as test\.time"),
])
def test_time_keys_are_checked(tmp_path, time_file, test, match):
    with pytest.raises(ProjectError, match=match):
        load_project(_project(tmp_path, test))


def _frf_file_missing_one_channel(tmp_path):
    frfs = synthesize_frfs(MODEL, np.linspace(0.05, 20, 800), [0, 1, 2], [0, 1], snr_db=40, seed=2)
    frfs = type(frfs)(frfs.frequencies_hz, frfs.H, np.array([[1, 3], [2, 3], [3, 3]]),
                      np.array([[100, 3], [101, 3]]), "m/N")
    path = write_uff(tmp_path / "gvt.uff", frfs=frfs)
    lines = path.read_text().split("\n")
    marks = [i for i, ln in enumerate(lines) if ln.strip() == "-1"]
    a, b = marks[-2], marks[-1]  # the last FRF: node 3 to reference 101
    path.write_text("\n".join(lines[:a] + lines[b + 1:]))
    return path


def test_drop_incomplete_from_a_project_reports_the_dropped_channel(tmp_path):
    _frf_file_missing_one_channel(tmp_path)
    with pytest.raises(ProjectError, match=r"incomplete.*3\+Z / 101\+Z.*drop_incomplete = true"):
        load_project(_project(tmp_path, 'frfs = "gvt.uff"'))
    project = load_project(_project(tmp_path, 'frfs = "gvt.uff"\ndrop_incomplete = true'))
    lines = []
    (tmp_path / "store").mkdir()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = identify_all(project, tmp_path / "store", progress=lines.append)["outboard"]
    assert found.info["dropped"] == ("response 3+Z: no FRF for reference 101+Z",)
    assert found.frfs.H.shape[1:] == (2, 2)
    assert any(issubclass(w.category, FlexGVTWarning) and "3+Z" in str(w.message) for w in caught)
    assert any("dropped response 3+Z" in ln for ln in lines)
    # read back from the store, the dropped channel is still reported
    again = []
    assert identify_all(project, tmp_path / "store", progress=again.append)["outboard"].info["dropped"]
    assert any("dropped response 3+Z" in ln and "store" in ln for ln in again)
    with pytest.raises(ProjectError, match=r"'drop_incomplete' applies to FRFs"):
        load_project(_project(tmp_path, 'modes = "m.json"\ndrop_incomplete = true'))


def test_files_that_hold_something_else_say_what_they_hold(tmp_path):
    (tmp_path / "geo.uff").write_bytes((DATA / "TestLab 161 164 18 15 82.uff").read_bytes())
    with pytest.raises(ProjectError, match=r"no FRF .*'geo\.uff' holds .*36 points; 36 coordinate systems.*"
                                           r"test geometry and coordinate systems only, no measurements"):
        load_project(_project(tmp_path, 'frfs = "geo.uff"'))
    with pytest.raises(ProjectError, match=r"no modes \(dataset 55 or 2414\).*36 points.*no measurements"):
        load_project(_project(tmp_path, 'modes = "geo.uff"'))
    with pytest.raises(ProjectError, match=r"no time history .*'geo\.uff'.*no measurements"):
        load_project(_project(tmp_path, 'time = "geo.uff"'))


def test_read_modes_accepts_nx_2414_modes():
    modes = read_modes(DATA / "NX simulation output.uff", "nx")
    assert len(modes.frequencies_hz) == 176 and modes.shapes.shape[0] == 176
    assert np.all(np.abs(modes.dofs[:, 1]) <= 3)
