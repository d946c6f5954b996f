"""Console output a test engineer can paste: tables within 80 columns with every number in full,
units that show (in tables and in help), per-iteration lines only with --verbose, Ctrl-C's message,
and `flexgvt show model` on a deck and on a project."""

import io
import json
import re
import warnings
from pathlib import Path

import pytest
from rich.console import Console
from typer.testing import CliRunner

import flexgvt as fg
from flexgvt.cli.main import app
from flexgvt.cli.tables import split_columns, tables
from flexgvt.cli.workflow import prediction_rows, print_prediction

runner = CliRunner()
DECK = Path(__file__).parents[1] / "data" / "bdf" / "all_cards.bdf"
NARROW = {"COLUMNS": "80"}


def _lines_fit(text: str, width: int = 80) -> None:
    too_long = [line for line in text.splitlines() if len(line) > width]
    assert not too_long, too_long
    assert "…" not in text  # nothing cut off


def _prediction_rows(n: int = 10) -> list[dict]:
    """The layout of a two-layout project's prediction rows with two proposed suspensions and a reference."""
    rows = []
    for k in range(n):
        f = 0.8912345 * (k + 1) ** 1.3
        row = {"free_mode": k + 7, "label": f"{k + 1} OOP/T", "free_hz": f}
        for name in ("outboard", "inboard", "bungee_outboard", "bungee_inboard"):
            row[f"{name}_hz"] = f * 1.0123
            row[f"{name}_shift_percent"] = 1.23
            row[f"{name}_mac"] = 0.99
        row.update(reference_hz=f * 0.99, reference_label="x", error_percent=-1.0101)
        rows.append(row)
    return rows


def test_prediction_table_fits_80_columns_with_every_number_in_full():
    rows = _prediction_rows()
    out = io.StringIO()
    print_prediction(Console(file=out, width=80), "free-flying prediction, updated model", rows)
    text = out.getvalue()
    _lines_fit(text)
    n = int(re.search(r"\(part 1 of (\d)\)", text).group(1))
    assert n >= 2 and f"(part {n} of {n})" in text
    _, cells = prediction_rows(rows)
    for row in cells:
        for cell in row:
            assert cell in text  # e.g. "0.8912", "15.7512": whole, on one line
    assert text.count(" 10 OOP/T ") == n  # mode and label repeated in each part
    for unit in ("[Hz]", "[%]"):
        assert unit in text
    # The same rows on a wide console: one table.
    wide = io.StringIO()
    print_prediction(Console(file=wide, width=200), "p", rows)
    assert "part" not in wide.getvalue()


def test_split_keeps_key_columns_and_packs_the_rest():
    assert split_columns([4, 10, 30, 30, 30], key=2, width=80) == [[0, 1, 2], [0, 1, 3], [0, 1, 4]]
    assert split_columns([4, 10, 8, 8], key=2, width=80) == [[0, 1, 2, 3]]
    assert split_columns([100], key=1, width=80) == [[0]]


def test_units_are_never_read_as_markup():
    out = io.StringIO()
    for t in tables("mass [kg] at [m]", ["mass [kg]", "offset [m]", "[bold]x[/bold]"], [[1.5, "(0, 0, 1)", "a"]]):
        Console(file=out, width=80).print(t)
    text = out.getvalue()
    assert "mass [kg] at [m]" in text and "[kg]" in text and "[m]" in text and "[bold]x[/bold]" in text
    help_text = runner.invoke(app, ["suspension", "identify", "--help"], env=NARROW).output
    assert "block mass [kg]" in help_text and "time [s]" in help_text and "times [s]" in help_text
    table = runner.invoke(app, ["suspension", "identify", "--mass", "1", "--peaks", "0,1,2,3"], env=NARROW).output
    assert "block mass [kg]" in table and "K [N/m]" in table and "C [N s/m]" in table
    run_help = runner.invoke(app, ["run", "--help"], env=NARROW).output
    assert "--fresh / --continue" in run_help and "--verbose" in run_help


def test_solve_table_in_a_pipe_fits_80_columns_with_full_frequencies(tmp_path):
    out = runner.invoke(app, ["solve", "hale_wing", "--modes", "8", "--json", str(tmp_path / "r.json")], env=NARROW)
    assert out.exit_code == 0, out.output
    _lines_fit(out.output)
    data = json.loads((tmp_path / "r.json").read_text())
    for cfg in data["configurations"].values():
        for f in cfg["frequencies_hz"]:
            assert f"{f:.4f}" in out.output


def test_show_model_on_a_deck_lists_groups_masses_springs_and_labelled_configurations():
    out = runner.invoke(app, ["show", "model", str(DECK)], env=NARROW)
    assert out.exit_code == 0, out.output
    _lines_fit(out.output)
    text = out.output
    for expected in ("PBARL_12", "PBEAM 20", "CONM2 100", "CONM1 102", "CELAS1 200", "CBUSH 221", "gravity",
                     "tip loads", "SUBCASE 2", "(0, 100, 0) N", "(0, 0, 5) N m", "[kg]", "[N/m]", "[m^2]"):
        assert expected in text, expected
    assert re.search(r"mass 17\.34\d* kg", text)


PROJECT = """
[model]
bdf = "strip.bdf"
[[configurations]]
name = "with shaker"
from = "unloaded"
[[configurations.masses]]
node = {tip}
mass = "12 g"
name = "shaker"
[configurations.test]
modes = "modes.json"
[[variables]]
name = "E2"
kind = "beam"
targets = ["PBEAML_2"]
attribute = "E"
bounds = [0.8, 1.2]
[optimiser]
tolerance = 1e-4
[prediction]
free_free = false
[outputs]
report = false
uff = false
bdf = false
"""


@pytest.fixture()
def project(tmp_path):
    case = fg.cases.cantilever_strip(n_elements=12)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fg.io.write_bdf(case.model, tmp_path / "strip.bdf", configurations=[case.configurations["unloaded"]])
    f = fg.solve_modes(fg.solve_static(case.model, case.configurations["unloaded"]), 4, damped=False).frequencies_hz
    (tmp_path / "modes.json").write_text(json.dumps({"frequencies_hz": (1.01 * f[:3]).tolist()}))
    (tmp_path / "project.toml").write_text(PROJECT.format(tip=int(case.model.node_ids[-1])))
    return tmp_path / "project.toml"


def test_show_model_on_a_project_and_iterations_only_with_verbose(project):
    out = runner.invoke(app, ["show", "model", str(project)], env=NARROW)
    assert out.exit_code == 0, out.output
    _lines_fit(out.output)
    assert "PBEAML_2" in out.output and "with shaker" in out.output and "shaker" in out.output
    assert "masses added in 'with shaker'" in out.output and "0.012" in out.output
    quiet = runner.invoke(app, ["run", str(project), "--fresh"], env=NARROW)
    assert quiet.exit_code == 0, quiet.output
    assert "iteration 1: objective" not in quiet.output and "updating (least_squares)" in quiet.output
    loud = runner.invoke(app, ["run", str(project), "--fresh", "--verbose"], env=NARROW)
    assert loud.exit_code == 0, loud.output
    assert "iteration 1: objective" in loud.output and "fresh run: discarded" in loud.output
    _lines_fit(loud.output)


def test_ctrl_c_prints_where_the_run_stopped_and_exits_130(project, monkeypatch):
    from flexgvt import workflow

    def interrupted(*args, **kwargs):
        raise workflow.RunInterrupted("interrupted in the updating after 7 stored evaluations (3 accepted "
                                      "iterations, best objective 0.0123); a rerun resumes", "updating")
    monkeypatch.setattr(workflow, "run", interrupted)
    out = runner.invoke(app, ["run", str(project)], env=NARROW)
    assert out.exit_code == 130
    text = " ".join(out.output.split())
    assert "stopped (Ctrl-C): interrupted in the updating after 7 stored evaluations" in text
    assert "best objective 0.0123" in text and "a rerun resumes" in text


def test_show_marks_the_springs_that_follow_a_table():
    """`flexgvt show model`'s spring table names the components with a force-deflection table (their K
    is the table's slope at zero) and leaves the column out when no spring has one."""
    from rich.console import Console

    import flexgvt as fg
    from flexgvt.cli.show import _springs

    tabled = fg.cases.swept_wing(n_wing=4, n_body=2, n_fin=2, root_hardening=0.02).model.springs[:2]
    console = Console(width=250, record=True)
    _springs(console, tabled, [], "springs")
    text = console.export_text()
    assert "table components" in text
    assert [line.split("│")[-2].strip() for line in text.splitlines() if "root_spring" in line] == ["4,6"]
    plain = Console(width=250, record=True)
    _springs(plain, fg.cases.swept_wing(n_wing=4, n_body=2, n_fin=2).model.springs[:2], [], "springs")
    assert "table components" not in plain.export_text()
