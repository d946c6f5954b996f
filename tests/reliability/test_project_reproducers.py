"""Project-file reproducers of the fuzzing trial (tests/data/reliability/toml): each stops in
load_project, in the first second, with a ProjectError naming the file and the key, and `flexgvt
run` prints it as one line with exit status 2 (it was a traceback and status 1, some of them only
after the whole computation)."""

import time

import pytest
from project_fixtures import DATA, project_copy
from typer.testing import CliRunner

from flexgvt.cli.main import app
from flexgvt.workflow import ProjectError, load_project

TOML = DATA / "toml"
CASES = {  # folder: (key named in the message, what it says)
    "TypeError_flexgvt_updating_variables_py_163___setcomp__": ("variables[22] ('E_tail_boom')", "beam group names"),
    "TypeError_flexgvt_updating_variables_py_177___listcomp__": ("variables[29] ('k6_wing_tail')",
                                                                 "no spring named '['"),
    "OSError_flexgvt_workflow_project_py_99___need_file_": ("configurations[1] ('inboard').test.modes", "too long"),
    "ValueError_flexgvt_suspension_identify_py_71__identify_block_": ("suspension_tests[0] ('left')",
                                                                      "one damping ratio per frequency"),
    "JSONDecodeErrorjson_decoder_py_340__decode_": ("prediction.reference", "not valid JSON"),
    "JSONDecodeErrorjson_decoder_py_355__raw_decod": ("prediction.reference", "/proc/self/status is not valid JSON"),
    "UnicodeDecodeError_codecs__322__decode_": ("prediction.reference", "not a text file"),
    "ValueError_flexgvt_workflow_steps_py_148__score_": ("prediction.reference", "flat list of numbers"),
    "ValueError_posixpath__451___joinrealpath_": ("outputs.directory", "NUL character"),
}


def test_the_base_project_loads(base, tmp_path):
    """The unmutated project (FRFs) and its variant with modes already identified both load."""
    project = load_project(project_copy(base, tmp_path / "p"))
    assert project.to_update == ["outboard", "inboard"]
    text = (TOML / "TypeError_flexgvt_updating_variables_py_163___setcomp__" / "minimal.toml").read_text()
    path = tmp_path / "p" / "project.toml"
    path.write_text(text.replace('"targets" = [-1]', '"targets" = ["tail_boom_*"]'))
    assert len(load_project(path).variables) == 30


@pytest.mark.parametrize("folder", sorted(CASES))
def test_reproducer_fails_early_and_clearly(base, tmp_path, folder):
    key, says = CASES[folder]
    path = project_copy(base, tmp_path / "p", TOML / folder)
    t0 = time.perf_counter()
    with pytest.raises(ProjectError) as err:
        load_project(path)
    assert time.perf_counter() - t0 < 5.0  # before any long step
    msg = str(err.value)
    assert msg.startswith(str(path)) and key in msg and says in msg, msg
    assert "\n" not in msg and "pydantic" not in msg.lower()
    result = CliRunner().invoke(app, ["run", str(path)])
    assert result.exit_code == 2, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert result.output.startswith("error: ") and result.output.count("\n") == 1, result.output
    assert "Traceback" not in result.output


def test_the_reproducers_mutations_are_what_the_cases_say():
    """Guard against a reproducer silently losing its mutation (then the test above proves nothing)."""
    import tomllib
    raw = {f: tomllib.loads((TOML / f / "minimal.toml").read_text()) for f in CASES}
    assert raw["TypeError_flexgvt_updating_variables_py_163___setcomp__"]["variables"][22]["targets"] == [-1]
    assert raw["TypeError_flexgvt_updating_variables_py_177___listcomp__"]["variables"][29]["targets"] == ["["]
    assert len(raw["OSError_flexgvt_workflow_project_py_99___need_file_"]["configurations"][1]["test"]["modes"]) == 5000
    assert raw["ValueError_posixpath__451___joinrealpath_"]["outputs"]["directory"] == "a\x00b"
