"""`flexgvt suspension identify|plan` as a user runs them."""

import json

from typer.testing import CliRunner

from flexgvt.cli.main import app

runner = CliRunner()


def test_identify_repeated_block_tests_writes_json_and_figure(tmp_path):
    out = tmp_path / "p.json"
    r = runner.invoke(app, ["suspension", "identify", "--mass", "0.8", "--frequency", "0.40", "--frequency", "0.41",
                            "--damping", "0.07", "--damping", "0.11", "--json", str(out), "--out", str(tmp_path)])
    assert r.exit_code == 0, r.output
    data = json.loads(out.read_text())
    assert data["n_tests"] == 2 and 5.0 < data["stiffness"] < 5.5 and data["stiffness_std"] > 0
    assert (tmp_path / "suspension_point.png").stat().st_size > 5_000
    bad = runner.invoke(app, ["suspension", "identify", "--mass", "0.8", "--frequency", "0.4"])
    assert bad.exit_code == 2 and "--damping" in bad.output


def test_plan_ranks_layouts_and_flags_the_stiff_one(tmp_path):
    out = tmp_path / "plan.json"
    r = runner.invoke(app, ["suspension", "plan", "strip_366", "--stiffness", "5", "--stiffness", "40",
                            "--station", "1.52", "--json", str(out), "--out", str(tmp_path)])
    assert r.exit_code == 0, r.output
    layouts = json.loads(out.read_text())["layouts"]
    assert [x["layout"] for x in layouts] == ["5 N/m at y = +-1.52 m", "40 N/m at y = +-1.52 m"]
    assert any("RB plunge" in p for p in layouts[1]["problems"])
    assert (tmp_path / "hung_shapes.png").stat().st_size > 10_000
