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
    assert result.exit_code == 2 and "no FRF" in result.output
