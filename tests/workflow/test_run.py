"""`run(project)` end to end on the 3.66 m strip: synthetic FRFs of a stiffer 'as-built' strip in the
outboard layout -> PolyMAX -> updating -> the inboard layout checked -> prediction, outputs, resume."""

import json

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.io.uff import TestGeometry, write_uff
from flexgvt.workflow import load_project, run
from flexgvt.workflow.synthetic import synthetic_gvt

PROJECT = """
[project]
name = "3.66 m strip"
[model]
case = "strip_366"
[[configurations]]
name = "outboard"
from = "outboard"
[configurations.test]
frfs = "outboard.uff"
points = "case"
band_hz = [0.2, 20.0]
max_order = 40
[[configurations]]
name = "inboard"
from = "inboard"
role = "check"
[configurations.test]
frfs = "inboard.uff"
points = "case"
band_hz = [0.2, 20.0]
max_order = 40
[[variables]]
name = "E"
kind = "beam"
targets = ["strip"]
attribute = "E"
bounds = [0.8, 1.2]
[objective]
mac = 1.0
[prediction]
n_modes = 6
[outputs]
report = %s
"""

TRUE_E_FACTOR = 1.05


@pytest.fixture(scope="module")
def project_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("strip_project")
    truth = fg.cases.strip_366()
    g = truth.model.beams[0]
    truth.model.set_beam_group(0, material=fg.Material("as built", E=g.material.E * TRUE_E_FACTOR, nu=0.33,
                                                       rho=g.material.rho))
    for name in ("outboard", "inboard"):
        gvt = synthetic_gvt(truth.model, truth.configurations[name], truth.sensors, ["S12LE", "S03TE"],
                            f_max_hz=20.0, df_hz=0.05, snr_db=40.0, seed=3)
        pts = np.array(sorted(gvt.point_xyz))
        write_uff(folder / f"{name}.uff", frfs=gvt.frfs,
                  geometry=TestGeometry(pts, np.array([gvt.point_xyz[p] for p in pts])))
    (folder / "project.toml").write_text(PROJECT % "false")
    return folder


def test_run_updates_checks_predicts_and_resumes(project_dir):
    project = load_project(project_dir / "project.toml")
    res = run(project)
    up = res.update
    # E recovered from the identified modes (frequencies and MAC) to well within the noise.
    assert up.x[0] == pytest.approx(TRUE_E_FACTOR, abs=0.01)
    rows = [r for r in up.tables["outboard"] if r["updated_hz"] is not None and r["initial_hz"] is not None]
    assert len(rows) >= 6
    assert sum(abs(r["updated_error_percent"]) for r in rows) < 0.5 * sum(abs(r["initial_error_percent"]) for r in rows)
    # The unseen inboard layout gets better too.
    err = {k: np.mean([abs(r["error_percent"]) for r in v["inboard"] if r["error_percent"] is not None])
           for k, v in res.checks.items()}
    assert err["updated"] < err["initial"]
    # Free-free prediction: the free strip's first bending mode (published 1.23 Hz).
    pred = res.predictions["updated"].rows
    assert pred[0]["label"] == "1 OOP" and pred[0]["free_hz"] == pytest.approx(1.23 * np.sqrt(TRUE_E_FACTOR), rel=0.03)
    out = project.output
    for name in ("updated.bdf", "identified-outboard.uff", "predicted-free-free-updated.uff", "results.json",
                 "prediction-updated.csv", "store/updating.sqlite"):
        assert (out / name).is_file(), name
    # The updated deck read back gives the updated model's free-free frequencies.
    deck = fg.io.read_bdf(out / "updated.bdf")
    modes = fg.solve_modes(fg.solve_static(deck.model, deck.configurations[next(iter(deck.configurations))]), 10)
    elastic = modes.frequencies_hz[modes.frequencies_hz > 0][:3]
    assert np.allclose(elastic, [r["free_hz"] for r in pred[:3]], rtol=1e-4)
    # A second run reads the identification and the finished optimisation back.
    again = run(project)
    assert "updating" in again.resumed and "identification outboard" in again.resumed
    assert again.update.x[0] == pytest.approx(up.x[0], rel=1e-9)
    data = json.loads((out / "results.json").read_text())
    assert data["prediction"]["updated"][0]["free_hz"] == pytest.approx(pred[0]["free_hz"])
