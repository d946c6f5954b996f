"""The run's confidence bounds and full mode lists (flexgvt.workflow.add_bounds, [prediction.uncertainty]):
a small X-HALE-like project (2 elements a section, the lab table's frequencies, three variables)."""

import copy
import json
import re

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.updating import UncertaintySettings
from flexgvt.workflow import example_project, load_project, run
from flexgvt.workflow.bounds import add_bounds
from flexgvt.workflow.project import ProjectError

VARIABLES = """
[[variables]]
name = "E_wing"
kind = "beam"
targets = ["wing_*"]
attribute = "E"
bounds = [0.75, 1.25]

[[variables]]
name = "G_wing"
kind = "beam"
targets = ["wing_*"]
attribute = "G"
bounds = [0.75, 1.25]

[[variables]]
name = "k_suspension"
kind = "cord"
targets = [0, 1]
attribute = "stiffness"
configurations = ["outboard"]
bounds = [0.8, 1.2]
"""


def _project(folder, uncertainty: str = "") -> str:
    lab = fg.data.load("xhale_lab_gvt")
    (folder / "lab.json").write_text(json.dumps(lab))
    text = example_project("xhale", modes={c: ("lab.json", c, lab["labels"]) for c in ("outboard", "inboard")})
    # the case's own cords (the template's name the nodes of the default mesh)
    text = re.sub(r"\[\[configurations\.cords\]\].*?carries = [^\n]*\n", "", text, flags=re.S)
    text = text.replace('case = "xhale"', 'case = "xhale"\n[model.options]\nn_per_section = 2', 1)
    text = re.sub(r"\[\[variables\]\].*?\n\n(?=\[\[variables\]\]|\n)", "", text, flags=re.S)
    text = text.replace("\n[objective]", VARIABLES + "\n[objective]", 1)
    text = text.replace("n_modes = 10", "n_modes = 6").replace("max_iterations = 60", "max_iterations = 15")
    text = text.replace("report = true", "report = false").replace("bdf = true", "bdf = false")
    text = text.replace("uff = true", "uff = false")
    (folder / "project.toml").write_text(text + uncertainty)
    return folder / "project.toml"


@pytest.fixture(scope="module")
def linear(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bounds")
    return run(load_project(_project(folder)))


def test_rows_json_and_mode_lists_carry_the_bounds(linear):
    res = linear
    pred = res.predictions["updated"]
    assert pred.uncertainty["method"] == "linear" and pred.uncertainty["confidence"] == 0.95
    assert pred.uncertainty["sigma_source"].startswith("residual")  # the lab table has no scatter
    assert "initial" not in res.to_dict()["prediction_uncertainty"] or \
        res.to_dict()["prediction_uncertainty"]["initial"] is None
    values = [k[:-3] for k in pred.rows[0] if k.endswith("_hz") and not k.endswith(("_low_hz", "_high_hz"))
              and k != "reference_hz"]
    assert "free" in values and "bungee_outboard" in values
    for r in pred.rows:
        for v in values:
            f, lo, hi = r.get(f"{v}_hz"), r.get(f"{v}_low_hz"), r.get(f"{v}_high_hz")
            if f is None:
                assert lo is None and hi is None
            else:
                assert lo < f < hi, (r["label"], v)
    # Every mode of each predicted configuration, paired or not, with its bounds.
    for name, modes in pred.modes.items():
        paired = {m["free_mode"] for m in modes if m["free_mode"] is not None}
        assert paired == {r["free_mode"] for r in pred.rows if r.get(f"{name}_hz") is not None}, name
        for m in modes:
            assert m["low_hz"] < m["frequency_hz"] < m["high_hz"]
            assert (m["mac"] is None) == (m["free_mode"] is None)
    saved = json.loads((res.project.output / "results.json").read_text())
    assert saved["prediction_modes"]["updated"].keys() == pred.modes.keys()
    assert saved["prediction"]["updated"][0]["free_low_hz"] == pred.rows[0]["free_low_hz"]
    csv = (res.project.output / "prediction-updated.csv").read_text().splitlines()[0]
    assert "free_low_hz" in csv and "bungee_inboard_high_hz" in csv


def test_the_report_shows_interval_columns_and_mode_lists(linear, tmp_path):
    from flexgvt.report.project import build_report_content
    content = build_report_content(linear)
    assert "free_95%_hz" in content.prediction[0] and "free_low_hz" not in content.prediction[0]
    lo, hi = map(float, content.prediction[0]["free_95%_hz"].split("\u2013"))
    assert lo < content.prediction[0]["free_hz"] < hi
    assert set(content.prediction_modes) == set(linear.predictions["updated"].modes)
    html = fg.report.write_report(content, tmp_path, figures=False, tables=False).read_text()
    assert "bungee_outboard: every mode" in html and "free 95% [Hz]" in html


def test_interval_is_wider_at_a_higher_level(linear):
    res = linear
    pred = copy.deepcopy(res.predictions["updated"])
    add_bounds(res.project, res.update, pred, res.identified, UncertaintySettings(confidence=0.99))
    before = res.predictions["updated"].rows
    assert all(a["free_low_hz"] < b["free_low_hz"] and a["free_high_hz"] > b["free_high_hz"]
               for a, b in zip(pred.rows, before))
    assert pred.uncertainty["confidence"] == 0.99


def test_mcmc_on_the_same_residuals(linear):
    """The sampling route (a short chain: the machinery, not converged statistics)."""
    pytest.importorskip("emcee")
    res = linear
    pred = copy.deepcopy(res.predictions["updated"])
    add_bounds(res.project, res.update, pred, res.identified,
               UncertaintySettings(method="mcmc", walkers=8, steps=4, burn=2, thin=1, samples=4, seed=1))
    assert pred.uncertainty["method"] == "mcmc"
    for r, lin in zip(pred.rows, res.predictions["updated"].rows):
        assert r["free_low_hz"] < r["free_high_hz"]
        # samples near the answer: inside the linear interval widened by half its width
        width = lin["free_high_hz"] - lin["free_low_hz"]
        assert lin["free_low_hz"] - width / 2 < r["free_low_hz"] and r["free_high_hz"] < lin["free_high_hz"] + width / 2


def test_the_settings_key(tmp_path):
    path = _project(tmp_path, '\n[prediction]\n')  # a second [prediction] would be a TOML error: edit in place
    text = path.read_text().replace("\n[prediction]\n", "")
    path.write_text(text.replace("n_modes = 6\n", 'n_modes = 6\nuncertainty = "none"\n', 1))
    assert load_project(path).spec.prediction.uncertainty == UncertaintySettings(method="none")
    path.write_text(text.replace("n_modes = 6\n", 'n_modes = 6\nuncertainty = "bayes"\n', 1))
    with pytest.raises(ProjectError, match="uncertainty"):
        load_project(path)
    path.write_text(text + '\n[prediction.uncertainty]\nconfidence = 1.5\n')
    with pytest.raises(ProjectError, match="confidence"):
        load_project(path)
    path.write_text(text + '\n[prediction.uncertainty]\nmethod = "mcmc"\nwalkers = 8\nsteps = 6\nburn = 2\n')
    assert load_project(path).spec.prediction.uncertainty == UncertaintySettings("mcmc", walkers=8, steps=6, burn=2)
    path.write_text(text + '\n[prediction.uncertainty]\nsteps = 6\nburn = 6\n')
    with pytest.raises(ProjectError, match="burn"):
        load_project(path)
    assert np.isclose(load_project(_project(tmp_path)).spec.prediction.uncertainty.confidence, 0.95)


def test_mcmc_without_emcee_is_refused_before_the_run(tmp_path, monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "emcee", None)  # import emcee then raises ImportError
    path = _project(tmp_path, '\n[prediction.uncertainty]\nmethod = "mcmc"\n')
    with pytest.raises(ProjectError, match="emcee"):
        run(load_project(path))
    assert not (tmp_path / "results" / "store" / "updating.sqlite").exists()
