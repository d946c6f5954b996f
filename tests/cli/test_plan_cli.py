"""`flexgvt plan project.toml` as a user runs it on their own deck: the ranking, sensor and exciter
tables on the console (80 columns), the CSV tables, the JSON and the pre-test page (checked in
headless Chromium)."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from flexgvt.cli.main import app

runner = CliRunner()
DECK = Path(__file__).parents[1] / "data" / "bdf" / "free_strip.bdf"
PROJECT = """
[project]
name = "free strip pre-test"
[model]
bdf = "free_strip.bdf"
[model.options]
cbar_torsional_inertia = true
[[configurations]]
name = "clean"
from = "subcase_2"
[[configurations]]
name = "tip masses"
from = "subcase_2"
[[configurations.masses]]
node = 101
mass = "50 g"
[[configurations.masses]]
node = 141
mass = "50 g"
[plan]
n_modes = 5
stations = [[110, 132], [101, 141]]
stiffness = ["5 N/m", "20 N/m"]
length = ["2 m"]
sensors = 6
directions = "Z"
"""


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plan_cli")
    shutil.copy(DECK, folder / "free_strip.bdf")
    (folder / "project.toml").write_text(PROJECT)
    r = runner.invoke(app, ["plan", str(folder / "project.toml"), "--json", str(folder / "plan.json")])
    return folder, r


def test_plan_prints_the_ranking_sensors_and_driving_points(planned):
    folder, r = planned
    assert r.exit_code == 0, r.output
    out = r.output
    assert "clean: candidate suspensions, best first (4 tried)" in out
    assert "tip masses: candidate suspensions, best first (4 tried)" in out
    ranking = out[out.index("clean: candidate"):out.index("clean: tested on")]
    assert ranking.index("5 N/m, 2 m at nodes") < ranking.index("20 N/m, 2 m at nodes")
    assert "6 sensors (auto-MAC off-diagonal max" in out
    assert "driving points (smallest normalised residue over the targets" in out
    assert max(len(line) for line in out.splitlines() if not set(line) <= {"─", " "}) <= 80
    data = json.loads((folder / "plan.json").read_text())
    assert [c["configuration"] for c in data["configurations"]] == ["clean", "tip masses"]
    assert data["configurations"][0]["layouts"][0]["suspension"] == "5 N/m, 2 m at nodes 110, 132"


def test_plan_writes_tables_and_a_pretest_page(planned):
    folder, _ = planned
    out = folder / "results" / "pretest"
    names = {p.name for p in out.iterdir()}
    assert {"layouts_clean.csv", "sensors_clean.csv", "exciters_clean.csv", "targets_clean.csv",
            "layouts_tip_masses.csv", "plan.json", "pretest.html"} <= names
    text = (out / "pretest.html").read_text()
    for heading in ("Configuration: clean", "Configuration: tip masses", "Candidate suspensions, best first",
                    "Sensors and driving points", "driving points, best first"):
        assert heading in text


def test_pretest_page_renders_in_chromium(planned, tmp_path):
    from flexgvt.report.browser import check_page, chromium
    if chromium() is None:
        pytest.skip("chromium not installed: apt-get install chromium")
    folder, _ = planned
    page = folder / "results" / "pretest" / "pretest.html"
    shot = tmp_path / "pretest.png"
    check = check_page(page, tmp_path / "chromium", shot)
    assert check.errors == []
    # per configuration: the frequency map, the 3D sensor view (WebGL) and the auto-MAC
    assert len(check.plots) == 6 and check.undrawn == [] and sum(p[2] for p in check.plots) == 2
    import matplotlib.image
    img = matplotlib.image.imread(shot)
    assert float(img[..., :3].std()) > 0.05  # not a blank page
    orange = np.abs(img[..., :3] - np.array([0xE0, 0x7B, 0x00]) / 255).max(axis=-1) < 0.08
    assert orange.sum() > 100  # the suspension modes of the frequency map are drawn


def test_plan_errors_name_the_file_and_key(tmp_path):
    shutil.copy(DECK, tmp_path / "free_strip.bdf")
    (tmp_path / "project.toml").write_text(PROJECT.replace("sensors = 6", "sensors = 6\nexciter = 2"))
    r = runner.invoke(app, ["plan", str(tmp_path / "project.toml")])
    assert r.exit_code == 2
    assert "project.toml: plan.exciter: unknown key" in " ".join(r.output.split())
