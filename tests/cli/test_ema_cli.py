"""`flexgvt ema identify` on a synthetic GVT written as UFF, as a test engineer would run it."""

import json

import numpy as np
from typer.testing import CliRunner

import flexgvt as fg
from flexgvt.cli.main import app
from flexgvt.ema import ModalModel, cmif, synthesize_frfs
from flexgvt.io.uff import write_uff

runner = CliRunner()


def test_identify_writes_modes_table_and_figures(tmp_path):
    rng = np.random.default_rng(4)
    model = ModalModel(np.array([1.2, 3.4, 7.9]), np.array([0.02, 0.015, 0.01]), rng.standard_normal((3, 6)))
    frfs = synthesize_frfs(model, np.linspace(0.05, 12, 2400), list(range(6)), [0], snr_db=40, seed=2)
    uff = write_uff(tmp_path / "gvt.uff", frfs=frfs)
    out = tmp_path / "out"
    result = runner.invoke(app, ["ema", "identify", str(uff), "--band", "0.5", "--band", "10", "--out", str(out),
                                 "--json", str(tmp_path / "m.json")])
    assert result.exit_code == 0, result.output
    found = json.loads((tmp_path / "m.json").read_text())
    np.testing.assert_allclose(found["frequencies_hz"], [1.2, 3.4, 7.9], rtol=2e-3)
    back = fg.io.read_uff(out / "modes.uff").modes
    np.testing.assert_allclose(back.frequencies_hz, found["frequencies_hz"], rtol=1e-5)  # UFF 55 holds E13.5
    for name in ("stabilisation.png", "cmif.png", "frf_fit.png", "modes.csv"):
        assert (out / name).stat().st_size > 100
    # CMIF of a single-reference FRF matrix is |H| itself.
    np.testing.assert_allclose(cmif(frfs.H)[:, 0], np.linalg.norm(frfs.H[:, :, 0], axis=1))


def test_identify_reports_a_file_without_frfs(tmp_path):
    from pathlib import Path

    geometry_only = Path(__file__).parents[1] / "data" / "uff" / "mesh_Oros-modal_uff15_uff2412.uff"
    result = runner.invoke(app, ["ema", "identify", str(geometry_only), "--out", str(tmp_path)])
    assert result.exit_code == 2 and "no FRF" in " ".join(result.output.split())  # rich wraps long paths


def test_identify_wide_band_from_the_command_line(tmp_path):
    rng = np.random.default_rng(5)
    f = np.array([0.3, 0.5, 2.0, 9.0, 40.0])
    model = ModalModel(f, np.array([0.08, 0.06, 0.01, 0.01, 0.01]), rng.standard_normal((5, 8)))
    frfs = synthesize_frfs(model, np.linspace(0.01, 60, 6000), list(range(8)), [0, 1], snr_db=40, seed=3)
    uff = write_uff(tmp_path / "wide.uff", frfs=frfs)
    out = tmp_path / "out"
    result = runner.invoke(app, ["ema", "identify", str(uff), "--wide", "--band", "0.1", "--band", "60",
                                 "--out", str(out), "--json", str(tmp_path / "w.json")])
    assert result.exit_code == 0, result.output
    got = json.loads((tmp_path / "w.json").read_text())["frequencies_hz"]
    # The command gives what the library gives on the file (accuracy itself: tests/ema/test_wideband.py).
    # (refined by maximum likelihood by default, --no-refine for the PolyMAX + LSFD values)
    read = fg.io.read_uff(uff).frfs
    direct = fg.ema.identify_wide_band(read, frequency_band=(0.1, 60.0), max_order=40)
    np.testing.assert_allclose(got, fg.ema.refine(read, direct, frequency_band=(0.1, 60.0)).frequencies_hz, rtol=1e-12)
    raw = runner.invoke(app, ["ema", "identify", str(uff), "--wide", "--no-refine", "--band", "0.1", "--band", "60",
                              "--out", str(out), "--json", str(tmp_path / "raw.json")])
    assert raw.exit_code == 0, raw.output
    np.testing.assert_allclose(json.loads((tmp_path / "raw.json").read_text())["frequencies_hz"],
                               direct.frequencies_hz, rtol=1e-12)
    np.testing.assert_allclose(got, f, rtol=5e-3)  # all five found, none spurious
    bad = runner.invoke(app, ["ema", "identify", str(uff), "--wide", "--poles", "2.0", "--out", str(out)])
    assert bad.exit_code == 2 and "--poles" in bad.output


def test_identify_repeated_tests_reports_mean_and_spread(tmp_path):
    """Three files of one configuration: averaged with their spread in the table, JSON and UFF 55."""
    rng = np.random.default_rng(4)
    model = ModalModel(np.array([1.2, 3.4, 7.9]), np.array([0.02, 0.015, 0.01]), rng.standard_normal((3, 6)))
    files = []
    for seed in (1, 2, 3):
        frfs = synthesize_frfs(model, np.linspace(0.05, 12, 600), list(range(6)), [0, 3], snr_db=30, seed=seed)
        files.append(str(write_uff(tmp_path / f"gvt{seed}.uff", frfs=frfs)))
    out = tmp_path / "out"
    result = runner.invoke(app, ["ema", "identify", *files, "--band", "0.5", "--band", "10", "--out", str(out),
                                 "--json", str(tmp_path / "m.json")])
    assert result.exit_code == 0, result.output
    assert "3 tests averaged" in result.output and "spread" in result.output
    found = json.loads((tmp_path / "m.json").read_text())
    np.testing.assert_allclose(found["frequencies_hz"], [1.2, 3.4, 7.9], rtol=2e-3)
    assert all(s > 0 for s in found["frequency_std_hz"]) and found["tests"]["n_tests"] == [3, 3, 3]
    back = fg.io.read_uff(out / "modes.uff").modes
    np.testing.assert_allclose(back.frequency_std_hz, found["frequency_std_hz"], rtol=1e-4)
    single = tmp_path / "one.json"
    result = runner.invoke(app, ["ema", "identify", files[0], "--band", "0.5", "--band", "10", "--out", str(out),
                                 "--json", str(single)])
    assert result.exit_code == 0 and all(s > 0 for s in json.loads(single.read_text())["damping_std"])


def _time_file(tmp_path):
    """A force channel (point 100, +Z) and three displacement responses as UFF 58 type 1."""
    from flexgvt.ema import synthesize_time_data
    from flexgvt.io.uff import TimeHistories

    model = ModalModel(np.array([3.0, 7.5, 12.0]), np.array([0.03, 0.02, 0.02]),
                       np.array([[1.0, 0.6, -0.4], [0.5, -0.8, 0.7], [0.3, 0.9, 0.6]]))
    _, force, resp = synthesize_time_data(model, 64.0, 512.0, [0, 1, 2], [0], snr_db=20, seed=3)
    th = TimeHistories(np.vstack([force, resp]), np.array([[100, 3], [1, 3], [2, 3], [3, -2]]), 64.0,
                       units=("N", "m", "m", "m"), spec_types=(13, 8, 8, 8))
    return model, write_uff(tmp_path / "time.uff", time_histories=th)


def test_frf_from_time_histories_reproduces_the_synthetic_frf(tmp_path):
    from flexgvt.ema import estimate_frf_from_time

    model, path = _time_file(tmp_path)
    out = tmp_path / "frfs.uff"
    result = runner.invoke(app, ["ema", "frf", str(path), "--reference", "100+Z", "--nperseg", "1024",
                                 "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "100+Z" in result.output and "63 averages" in result.output
    frfs = fg.io.read_uff(out).frfs
    assert frfs.outputs.tolist() == [[1, 3], [2, 3], [3, -2]] and frfs.inputs.tolist() == [[100, 3]]
    true = synthesize_frfs(model, frfs.frequencies_hz, [0, 1, 2], [0]).H
    # The file holds no variance: the estimator's own (same blocks) gives the tolerance, as tests/io does.
    variance = estimate_frf_from_time(fg.io.uff.read_time_histories(path), nperseg=1024).variance
    band = (frfs.frequencies_hz > 1.0) & (frfs.frequencies_hz < 20.0)
    e = np.abs(frfs.H - true)[band] ** 2 / variance[band]
    assert 0.5 < e.mean() < 2.0 and np.quantile(e, 0.99) < 10.0
    wrong = np.abs(frfs.H * 1.1 - true)[band] ** 2 / variance[band]  # a 10 % gain error fails it
    assert wrong.mean() > 2.0


def test_frf_reference_text_is_checked(tmp_path):
    from flexgvt.workflow.identification import parse_dof

    assert parse_dof("100+Z") == (100, 3) and parse_dof("7-ry") == (7, -5) and parse_dof("12:3") == (12, 3)
    _, path = _time_file(tmp_path)
    result = runner.invoke(app, ["ema", "frf", str(path), "--reference", "100Q", "--out", str(tmp_path / "f.uff")])
    assert result.exit_code == 2 and "100+Z" in result.output and "Traceback" not in result.output
    result = runner.invoke(app, ["ema", "frf", str(path), "--reference", "5+X", "--out", str(tmp_path / "f.uff")])
    assert result.exit_code == 2 and "5" in result.output and "Traceback" not in result.output


def test_drop_incomplete_names_the_dropped_channel(tmp_path):
    rng = np.random.default_rng(4)
    model = ModalModel(np.array([1.2, 3.4, 7.9]), np.array([0.02, 0.015, 0.01]), rng.standard_normal((3, 6)))
    frfs = synthesize_frfs(model, np.linspace(0.05, 12, 1200), list(range(6)), [0, 1], snr_db=40, seed=2)
    uff = write_uff(tmp_path / "gvt.uff", frfs=frfs)
    lines = uff.read_text().split("\n")
    marks = [i for i, ln in enumerate(lines) if ln.strip() == "-1"]
    blocks = [(marks[k], marks[k + 1]) for k in range(0, len(marks) - 1, 2)]
    a, b = blocks[-1]  # the last FRF: the last response to the second reference
    uff.write_text("\n".join(lines[:a] + lines[b + 1:]))
    out = tmp_path / "out"
    result = runner.invoke(app, ["ema", "identify", str(uff), "--band", "0.5", "--band", "10", "--out", str(out),
                                 "--no-refine"])
    assert result.exit_code == 2 and "--drop-incomplete" in " ".join(result.output.split())
    result = runner.invoke(app, ["ema", "identify", str(uff), "--band", "0.5", "--band", "10", "--out", str(out),
                                 "--no-refine", "--drop-incomplete", "--json", str(tmp_path / "m.json")])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    dropped = f"response {int(frfs.outputs[-1][0])}+{'XYZ'[int(frfs.outputs[-1][1]) - 1]}"
    assert "dropped" in text and dropped in text
    found = json.loads((tmp_path / "m.json").read_text())
    np.testing.assert_allclose(found["frequencies_hz"], [1.2, 3.4, 7.9], rtol=2e-3)
    assert found["dropped_channels"] == {str(uff): [f"{dropped}: no FRF for reference {int(frfs.inputs[1][0])}+Z"]}


def test_version():
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0 and result.output.strip() == f"flexgvt {fg.__version__}"

