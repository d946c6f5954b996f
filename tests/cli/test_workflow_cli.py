"""`flexgvt init` and `flexgvt run` as a user runs them."""

import json
import tomllib

from typer.testing import CliRunner

from flexgvt.cli.main import app
from flexgvt.workflow import example_project, load_project

runner = CliRunner()


def test_init_writes_a_commented_project_that_validates(tmp_path):
    result = runner.invoke(app, ["init", str(tmp_path)])
    assert result.exit_code == 0, result.output
    text = (tmp_path / "project.toml").read_text()
    assert text == example_project()
    spec = tomllib.loads(text)
    assert len(spec["variables"]) == 30 and {c["name"] for c in spec["configurations"]} == {"outboard", "inboard"}
    assert text.count("#") > 40  # every key explained
    # Without data it stops on the first missing file, naming it.
    result = runner.invoke(app, ["run", str(tmp_path / "project.toml")])
    assert result.exit_code == 2 and "data/outboard.uff' not found" in result.output.replace("\n", "")
    again = runner.invoke(app, ["init", str(tmp_path)])
    assert again.exit_code == 2 and "--force" in again.output


def test_init_with_data_then_run(tmp_path):
    result = runner.invoke(app, ["init", str(tmp_path), "--data"])
    assert result.exit_code == 0, result.output
    project = load_project(tmp_path / "project.toml")
    assert [c.name for c in project.spec.configurations] == ["outboard", "inboard"]
    out = tmp_path / "r.json"
    result = runner.invoke(app, ["run", str(tmp_path / "project.toml"), "--no-report", "--json", str(out)])
    assert result.exit_code == 0, result.output
    data = json.loads(out.read_text())
    assert set(data) == {"project", "timings_s", "resumed", "identified", "updating", "checks", "prediction",
                         "prediction_modes", "prediction_uncertainty", "files"}
    rows = data["prediction"]["updated"]
    assert all("reference_hz" in r for r in rows[:7]) and max(abs(r["error_percent"]) for r in rows[:7]) < 2.0
    assert "free-flying prediction, updated model" in result.output
    second = runner.invoke(app, ["run", str(tmp_path / "project.toml"), "--no-report", "--json", str(out)])
    assert second.exit_code == 0 and "from the store" in second.output
    assert "updating" in json.loads(out.read_text())["resumed"]


def test_run_a_broken_project_names_the_key(tmp_path):
    (tmp_path / "project.toml").write_text(example_project().replace('max_order = 60', 'max_orders = 60', 1))
    result = runner.invoke(app, ["run", str(tmp_path / "project.toml")])
    assert result.exit_code == 2
    assert "configurations[0].test.max_orders: unknown key" in result.output.replace("\n", "")
