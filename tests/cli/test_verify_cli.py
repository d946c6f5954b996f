"""`flexgvt verify wingbox` as a user runs it: the console tables and the files of --out, on the
coarsest wingbox mesh (0.5 m: one element per rib bay, whose skins cannot wrinkle, so no onset is
found; the post-buckled protocol at 0.25 m is tests/updating/test_verify_wingbox.py's)."""

import csv
import json

import numpy as np
from typer.testing import CliRunner

from flexgvt.cli.main import app

runner = CliRunner()


def _rows(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_verify_wingbox_prints_the_protocol_tables_and_writes_its_files(tmp_path):
    out, js = tmp_path / "fig", tmp_path / "v.json"
    result = runner.invoke(app, ["verify", "wingbox", "--seed", "1", "--element-size", "0.5", "--tolerance", "1e-3",
                                 "--out", str(out), "--json", str(js)])
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())  # the 80-column tables wrap their titles
    data = json.loads(js.read_text())
    assert json.loads((out / "verification.json").read_text()) == data
    names = ["rho", "E", "t_ribs", "t_skins", "t_spars"]
    assert data["case"] == "wingbox" and data["seed"] == 1 and data["variables"] == names
    e = {k: np.asarray(v) for k, v in data["variable_errors_percent"].items()}
    assert np.abs(e["initial"]).max() > 2.0 and np.abs(e["multi"]).max() < 0.5
    assert max(abs(x) for x in data["prediction"]["multi_error_percent"]) < 0.2

    # The design-variable errors: each variable's row with its initial error as the JSON has it.
    assert "design variables: error against the reference [%]" in text
    rows = {line.split("│")[1].strip(): line for line in result.output.splitlines() if line.count("│") >= 5}
    for k, name in enumerate(names):
        assert f"{e['initial'][k]:+.3f}" in rows[name], (name, rows.get(name))
    # The frequency errors of every configuration, each said seen or unseen, with its reference Hz.
    for title in ("'unloaded' (seen by both models)", "'minus_1g' (seen by the multi-configuration model only)",
                  "'plus_2_5g' (seen by the multi-configuration model only)", "'combined' (unseen by both models)"):
        assert f"{title}: reference frequencies [Hz] and the models' errors [%]" in text, title
    for name, row in data["configurations"].items():
        assert len(row["reference_hz"]) == 8
        assert all(f"{f:.4f}" in result.output for f in row["reference_hz"]), name
    # The unseen prediction's static tip, the reference's onsets (none on this mesh), the files.
    assert "static deflections: the reference's [m or rad] and the models' errors [%] (the unseen 'combined' is " \
           "a prediction)" in text
    (tip,) = data["prediction"]["static"]
    assert f"{tip['reference']:.5g}" in result.output and abs(tip["multi_error_percent"]) < 0.2
    assert "buckling onset along the reference's load path" in text and text.count("none found") == 3
    assert f"files in {out}/" in text

    onsets = _rows(out / "onsets.csv")
    assert [(r["configuration"], r["buckled"], r["load_factor"]) for r in onsets] == [
        ("minus_1g", "False", ""), ("plus_2_5g", "False", ""), ("combined", "False", "")]
    assert data["onsets"] == {"minus_1g": None, "plus_2_5g": None, "combined": None}
    static = _rows(out / "static.csv")
    assert [(r["configuration"], r["unseen"]) for r in static] == [("minus_1g", "False"), ("plus_2_5g", "False"),
                                                                   ("combined", "True")]
    assert int(static[-1]["node"]) == tip["node"] and float(static[-1]["reference"]) == float(f"{tip['reference']:.9g}")
    assert float(static[-1]["multi_error_percent"]) == float(f"{tip['multi_error_percent']:.6g}")
    freqs = _rows(out / "frequencies.csv")
    assert len(freqs) == 4 * 8 and [r["configuration"] for r in freqs[::8]] == list(data["configurations"])
    assert [r["variable"] for r in _rows(out / "variables.csv")] == names
    for figure in ("errors.png", "mac.png"):
        assert (out / figure).stat().st_size > 10_000


def test_verify_refuses_a_tolerance_before_solving_anything():
    result = runner.invoke(app, ["verify", "wingbox", "--tolerance", "0"])
    assert result.exit_code == 2 and "tolerance = 0.0 must be finite and > 0" in result.output
