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
