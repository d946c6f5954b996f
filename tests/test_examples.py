"""Every example in examples/ runs (with --out and --json, on the measured tables shipped in
flexgvt.data) and gives what its docstring says; a bad --data is one line and exit status 2."""

import importlib.util
import json
import runpy
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def _load(path: Path):
    spec = importlib.util.spec_from_file_location(path.parent.name + "_" + path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_example_is_tested():
    scripts = sorted(p.relative_to(EXAMPLES).as_posix() for p in EXAMPLES.rglob("*.py"))
    assert scripts == ["strip_366_gvt.py", "swept_wing/run.py", "xhale_lab/run.py"]


def test_xhale_lab(tmp_path):
    out = _load(EXAMPLES / "xhale_lab" / "run.py").main(["--out", str(tmp_path / "o"), "--json",
                                                          str(tmp_path / "x.json"), "--no-report"])
    saved = json.loads((tmp_path / "x.json").read_text())
    assert set(saved) == {"configurations", "rms_error_percent", "gross_mass", "prediction", "prediction_modes",
                          "prediction_uncertainty", "variables", "timings_s", "files"}
    # The pods' masses (three variables, by default) move mass outboard; the published gross mass
    # holds within 1 %.
    pods = {v["name"]: v for v in saved["variables"] if v["kind"] == "mass"}
    assert set(pods) == {"pod_centre", "pods_inner", "pods_outer"}
    assert abs(saved["gross_mass"]["updated_kg"] / 11.35 - 1) < 0.01
    # The project written reads its own copy of the shipped table.
    assert json.loads((tmp_path / "o" / "xhale_lab_gvt.json").read_text()) == __import__("flexgvt").data.load(
        "xhale_lab_gvt")
    assert 'modes = "xhale_lab_gvt.json"' in (tmp_path / "o" / "project.toml").read_text()
    for c, s in out["rms_error_percent"].items():
        # Updating on both layouts at once lowers the error in each; it ends within 1 % (rms) of the
        # original work's updated Nastran model.
        assert s["updated_hz"] < s["initial_hz"], c
        assert s["updated_hz"] < s["original_updated_hz"] + 1.0, c
    assert out["prediction"][0]["label"] == "1 OOP" and 0.85 < out["prediction"][0]["free_hz"] < 0.95
    # Every predicted frequency has its 95 % interval; every mode of a predicted configuration is
    # listed, the bungees' second torsion near 6.2 Hz (no free-free partner) too.
    assert all(r["free_low_hz"] < r["free_hz"] < r["free_high_hz"] for r in saved["prediction"])
    torsion = [m for m in saved["prediction_modes"]["bungee_outboard"] if 6.0 < m["frequency_hz"] < 6.4]
    assert len(torsion) == 1 and torsion[0]["free_mode"] is None and torsion[0]["mac"] is None
    assert torsion[0]["low_hz"] < torsion[0]["frequency_hz"] < torsion[0]["high_hz"]
    # The heavy bungees' own modes are listed with their labels and no free-free partner; with them
    # the first bending on the outboard bungees comes out lower than on massless bungees.
    heavy = saved["prediction_modes"]["bungee_outboard_heavy"]
    own = [m for m in heavy if "bungee" in m["label"]]
    assert {m["label"] for m in own} >= {"1 bungee surge", "1 bungee string"}
    assert all(m["free_mode"] is None for m in own)
    first = saved["prediction"][0]
    assert first["bungee_outboard_heavy_hz"] < first["bungee_outboard_hz"]


def test_xhale_lab_property_option(tmp_path):
    """--property NAME=VALUE changes an unpublished dimension of the case in the project the example
    writes (checked there, before any solve); a malformed one is refused by the parser."""
    import argparse

    example = _load(EXAMPLES / "xhale_lab" / "run.py")
    assert example._property("pendulum_length=6") == ("pendulum_length", 6.0)
    assert example._property("pod_inertia=0.01,0.002,0.006") == ("pod_inertia", [0.01, 0.002, 0.006])
    for bad in ("pendulum_length", "=6", "pendulum_length=six"):
        with pytest.raises(argparse.ArgumentTypeError, match="NAME=VALUE"):
            example._property(bad)
    with pytest.raises(__import__("flexgvt").errors.ModelError, match="unknown properties"):
        example.main(["--out", str(tmp_path / "o"), "--no-report", "--property", "chord=0.3"])


@pytest.fixture(scope="module")
def swept_wing_small(tmp_path_factory):
    """examples/swept_wing/run.py --small: (its returned tables, the JSON it wrote)."""
    tmp = tmp_path_factory.mktemp("swept_wing")
    out = _load(EXAMPLES / "swept_wing" / "run.py").main(["--out", str(tmp / "o"), "--json", str(tmp / "w.json"),
                                                           "--small"])
    return out, json.loads((tmp / "w.json").read_text())


def test_swept_wing(swept_wing_small):
    """Both stages run from the case (small settings), after the root spring's M_z is set on the
    laboratory GVT's first in-plane mode (Section 5.4.2); each lowers its stage's error (stage 1 on
    all five modes, stage 2 on the four its root spring moves: the model's third bending hardly
    follows it); stage 2 changes only the root spring; the tables carry the original work's columns.
    OOP 3 pairs with the model's third bending; stage 1 brings the first three modes within 0.5 %
    and all five within 2 % (the issue's figures; at these settings 0.3 %) with every variable inside
    Table 5.7's bounds; stage 2 brings IP 1 within 1 % and stiffens M_x, splitting the difference
    between OOP 1 (the GVT's +5.2 % from the shaker table) and OOP 2 (+1.8 %), which the root spring
    moves alike."""
    out, saved = swept_wing_small
    assert set(saved) == {"stage0", "stages", "summary"}
    assert list(saved["stages"]) == ["root_spring_adjustment", "shaker_table", "wind_tunnel"]
    assert saved["stage0"]["E_spar_ply"] == 45e9 and saved["stage0"]["rho_printed"] == 890.0
    adjust = out["stages"]["root_spring_adjustment"]
    (row,), (mz,) = adjust["frequencies"], adjust["variables"]
    assert row["measured_hz"] == 7.10 and row["initial_hz"] > 8.0 and row["updated_hz"] == pytest.approx(7.10, rel=1e-5)
    assert mz["name"] == "M_z" and mz["initial"] == 5000.0 and 0.5 < mz["final"] / 5000.0 < 0.75
    for name in ("shaker_table", "wind_tunnel"):
        stage = out["stages"][name]
        rows = stage["frequencies"]
        assert [r["label"] for r in rows] == ["OOP 1", "IP 1", "T 1", "OOP 2", "OOP 3"], name
        assert all(r["updated_hz"] is not None for r in rows), name
        rows = rows if name == "shaker_table" else rows[:4]
        rms = {k: sum(r[k] ** 2 for r in rows) for k in ("initial_error_percent", "updated_error_percent")}
        assert rms["updated_error_percent"] < 0.5 * rms["initial_error_percent"], name
    s1 = out["stages"]["shaker_table"]["variables"]
    assert len(s1) == 15 and all(r["lower"] <= r["final"] / r["initial"] + 1e-9 <= r["upper"] + 1e-9 for r in s1)
    assert {r["name"]: r["initial"] for r in s1}["M_z"] == pytest.approx(mz["final"], rel=1e-12)  # stage 1 starts there
    assert {r["name"]: r["original_final"] for r in s1}["E_skin"] == 5.84e9  # Table 5.7 beside flexgvt's
    assert [r["name"] for r in out["stages"]["wind_tunnel"]["variables"]] == ["K_x", "K_y", "K_z", "M_x", "M_y", "M_z"]
    st = out["stages"]["shaker_table"]["frequencies"]
    assert all(r["model_label"].startswith(lab) for r, lab in zip(st, ("1 OOP", "RB", "1 T", "2 OOP", "3 OOP")))
    assert max(abs(r["updated_error_percent"]) for r in st[:3]) < 0.5
    assert max(abs(r["updated_error_percent"]) for r in st) < 2.0
    assert not {r["name"]: r["at_bound"] for r in s1}["M_z"]
    assert saved["summary"]["shaker_table"]["worst_first3_percent"] < 0.5
    wt = out["stages"]["wind_tunnel"]["frequencies"]
    assert abs(wt[1]["updated_error_percent"]) < 1.0
    assert wt[0]["updated_error_percent"] < 0 < wt[3]["updated_error_percent"]
    assert {r["name"]: r["change_percent"] for r in out["stages"]["wind_tunnel"]["variables"]}["M_x"] > 10


def test_swept_wing_stage2_reach():
    """bench/swept_wing_stage2_reach.py --small (the docs' stage-2 study at the test's settings): from
    stage 1's model, stiffening M_x raises the third bending monotonically towards its rigid-root
    value, which stays more than 1 % below the tunnel's 35.5 Hz (no root spring reaches it), while the
    first and second bending pass the GVT; the printed frame's and the film's moduli beside the root
    spring fit the tunnel's shifts far better than the root spring alone."""
    out = _load(ROOT / "bench" / "swept_wing_stage2_reach.py").main(["--small"])
    oop3 = [r["errors_percent"][4] for r in out["scan"]]
    assert all(b >= a - 1e-9 for a, b in zip(oop3, oop3[1:])) and oop3[-1] < -1.0
    rigid = out["scan"][-1]["errors_percent"]
    assert rigid[0] > 0 and rigid[3] > 0  # OOP 1 and OOP 2 above the GVT on a rigid root
    assert out["best_scan"]["worst_without_ip1_percent"] > 1.0
    worst = {tuple(v["extra"]): v["worst_percent"] for v in out["variants"]}
    assert worst[("E_printed", "E_skin")] < 0.5 * worst[()]


# run.py --small's settings, set on a copy of the project file (each line must be there exactly once).
SMALL = {"n_wing = 20 ": "n_wing = 10 ", "max_iterations = 100 ": "max_iterations = 10 ", "starts = 4 ": "starts = 1 "}


def test_swept_wing_project(tmp_path, swept_wing_small):
    """examples/swept_wing/project.toml (at run.py's --small settings) runs the chapter-5 procedure with
    flexgvt run: the component tests as fixed inputs, then the shaker-table stage, then the root spring
    on the wind-tunnel GVT from stage 1's model; each stage in results.json and the report; its
    variables and frequencies are the Python example's."""
    import shutil

    from typer.testing import CliRunner

    from flexgvt.cli.main import app

    text = (EXAMPLES / "swept_wing" / "project.toml").read_text()
    for old, new in SMALL.items():
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    shutil.copytree(EXAMPLES / "swept_wing" / "data", tmp_path / "data")
    (tmp_path / "project.toml").write_text(text)
    got = CliRunner().invoke(app, ["run", str(tmp_path / "project.toml")], env={"COLUMNS": "120"})
    assert got.exit_code == 0, got.output
    for title in ("stage 1 of 4 ('component tests'): fixed inputs",
                  "stage 2 of 4 ('root-spring adjustment'): shaker_table_lab",
                  "stage 3 of 4 ('shaker table'): shaker_table", "stage 4 of 4 ('wind tunnel'): design variables"):
        assert title in got.output  # each stage's table on the console
    res = json.loads((tmp_path / "results" / "results.json").read_text())
    s0, sa, s1, s2 = res["stages"]
    assert [s["name"] for s in res["stages"]] == ["component tests", "root-spring adjustment", "shaker table",
                                                 "wind tunnel"]
    assert {r["name"]: r["value"] for r in s0["fixed_inputs"]}["E12_spar"] == 45e9 and s0["variables"] == []
    assert sa["configurations"] == ["shaker_table_lab"] and [r["name"] for r in sa["variables"]] == ["M_z"]
    assert {r["name"]: r["initial"] for r in s1["variables"]}["M_z"] == pytest.approx(sa["variables"][0]["final"],
                                                                                     rel=1e-12)
    assert s1["configurations"] == ["shaker_table"] and len(s1["variables"]) == 15
    assert [(r["name"], r["lower"], r["upper"]) for r in s2["variables"]] == [
        (n, 0.25, 4.0) for n in ("K_x", "K_y", "K_z", "M_x", "M_y", "M_z")]
    # Stage 2 starts from stage 1's answer and holds the four rigid components (unidentifiable = "fix").
    final1 = {r["name"]: r["final"] for r in s1["variables"]}
    assert all(r["initial"] == pytest.approx(final1[r["name"]], rel=1e-12) for r in s2["variables"])
    assert [r["name"] for r in s2["variables"] if r["fixed"]] == ["K_x", "K_y", "K_z", "M_y"]
    assert [(r["name"], r["final"]) for r in res["updating"]["variables"]] == [
        (r["name"], r["final"]) for r in s2["variables"]]  # `updating`: the final stage's
    # The same numbers as the Python example (run.py --small), to well inside the optimiser's steps
    # (measured: the variables to 1.6e-8, the frequencies to 2.1e-9).
    example = swept_wing_small[1]["stages"]
    for mine, theirs in ((sa, example["root_spring_adjustment"]), (s1, example["shaker_table"]),
                         (s2, example["wind_tunnel"])):
        assert [r["final"] for r in mine["variables"]] == pytest.approx([r["final"] for r in theirs["variables"]],
                                                                        rel=1e-6)
        rows = next(iter(mine["frequencies"].values()))
        for key in ("initial_hz", "updated_hz"):
            assert [r[key] for r in rows] == pytest.approx([r[key] for r in theirs["frequencies"]], rel=1e-8)
    html = (tmp_path / "results" / "report.html").read_text()
    assert all(f"Stage {k} of 4: {n}" in html for k, n in ((1, "component tests"), (2, "root-spring adjustment"),
                                                          (3, "shaker table"), (4, "wind tunnel")))
    # The summary gives every stage; the final-stage sections say whose they are.
    assert "stage 3: shaker table</th><td>15 variables on shaker_table: objective" in html
    assert "Design variables (stage 4: wind tunnel)" in html


def test_strip_366_gvt(tmp_path):
    out = _load(EXAMPLES / "strip_366_gvt.py").main(["--out", str(tmp_path / "o"), "--json", str(tmp_path / "s.json"),
                                                     "--max-iterations", "10"])
    saved = json.loads((tmp_path / "s.json").read_text())
    assert set(saved["configurations"]) == {"outboard", "inboard"} and Path(saved["figure"]).is_file()
    # The unpublished inboard attachment: the torsion modes put it 1.5-1.65 m from the ends.
    assert 1.45 <= out["inboard_attachment_m"] <= 1.65
    for name, s in out["summary"].items():
        assert s["updated_median_percent"] < s["initial_median_percent"] + 0.5, name
    assert out["summary"]["outboard"]["updated_median_percent"] < out["summary"]["outboard"]["initial_median_percent"]
    assert saved["objective"]["final"] < 0.7 * saved["objective"]["initial"]
    # The same modes in both layouts: the measured 2nd bending is 5 % lower outboard, the model's is
    # not, so one layout errs by at least 2.5 %; the 8th bending agrees in both.
    floors = {r["label"]: r["floor_percent"] for r in saved["layout_consistency"]}
    assert floors["2 OOP"] > 2.0 and floors["8 OOP"] < 0.5


@pytest.mark.parametrize("script", ["strip_366_gvt.py", "xhale_lab/run.py"])
def test_bad_data_is_one_line(script, tmp_path, monkeypatch, capsys):
    """A --data that is missing, not JSON or not in the shipped table's form: one line on stderr and
    exit status 2, before any computation (nothing written to --out)."""
    bad = {"missing.json": None, "broken.json": '{"outboard": [1.2, ', "binary.json": b"\x89PNG\r\n\x1a\n\x00",
           "wrong.json": '{"outboard": {"undamped_hz": "1.2"}, "labels": ["1 OOP"]}'}
    for name, content in bad.items():
        path = tmp_path / name
        if isinstance(content, bytes):
            path.write_bytes(content)
        elif content is not None:
            path.write_text(content)
        monkeypatch.setattr(sys, "argv", [script, "--data", str(path), "--out", str(tmp_path / "o")])
        with pytest.raises(SystemExit) as exit_:
            runpy.run_path(str(EXAMPLES / script), run_name="__main__")
        err = capsys.readouterr().err
        assert exit_.value.code == 2 and err.startswith(f"error: {path}") and err.count("\n") == 1, (name, err)
        assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("script, table",
                         [("strip_366_gvt.py", "strip_366_gvt"), ("xhale_lab/run.py", "xhale_lab_gvt")])
def test_own_table(script, table, tmp_path):
    """--data takes a table of the shipped one's form; a frequency that is not a finite positive
    number is refused with the file named."""
    import flexgvt as fg
    from flexgvt.errors import FileFormatError
    measured_tables = _load(EXAMPLES / script).measured_tables
    shipped = fg.data.load(table)
    assert measured_tables(None) == shipped
    path = tmp_path / "mine.json"
    path.write_text(json.dumps(shipped))
    assert measured_tables(path) == shipped
    key = "undamped_hz" if table == "strip_366_gvt" else "measured_hz"
    for bad in (float("nan"), -1.0, True, "1.2"):
        shipped["inboard"][key][3] = bad
        path.write_text(json.dumps(shipped))
        with pytest.raises(FileFormatError, match=f"mine.json: 'inboard' must hold '?{key}"):
            measured_tables(path)
