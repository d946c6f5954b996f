"""Project files: a broken file stops before any long computation, naming the file and the key."""

import json
import time

import pytest

from flexgvt.workflow import ProjectError, load_project

GOOD = """
[project]
name = "strip"
[model]
case = "strip_366"
[[suspension_tests]]
name = "left"
mass = "0.8 kg"
frequency_hz = [0.40, 0.41]
damping_ratio = [0.07, 0.068]
[[configurations]]
name = "outboard"
from = "outboard"
[[configurations.cords]]
node = 10
anchor = [0.0, -1.52, 3.0]
block_test = "left"
carries = "800 g"
[[configurations.cords]]
node = 114
anchor = [0.0, 1.52, 3.0]
stiffness = "5.19 N/m"
damping = 0.45
carries = 0.8
[configurations.test]
modes = "modes.json"
[[configurations]]
name = "inboard"
from = "inboard"
role = "check"
[[variables]]
name = "E"
kind = "beam"
targets = ["strip"]
attribute = "E"
bounds = [0.8, 1.2]
"""


def write(tmp_path, text, modes=True):
    if modes:
        (tmp_path / "modes.json").write_text(json.dumps({"frequencies_hz": [1.3, 3.3, 6.5]}))
    path = tmp_path / "project.toml"
    path.write_text(text)
    return path


def test_good_project_resolves(tmp_path):
    p = load_project(write(tmp_path, GOOD))
    out = p.configurations["outboard"]
    assert len(out.suspension) == 2
    left, right = out.suspension
    # The block test (mass 0.8 kg, 0.40/0.41 Hz, 7 %) gives K = m w_n^2 averaged over the two tests.
    wn = 2 * 3.141592653589793 * 0.405 / (1 - 0.069 ** 2) ** 0.5
    assert left.stiffness == pytest.approx(0.8 * wn ** 2, rel=0.01)
    assert right.stiffness == 5.19 and right.damping == 0.45
    # Sized to carry 0.8 kg: stretch m g / K.
    node_z = p.model.xyz[p.model.index_of([114])[0]]
    length = ((node_z - [0.0, 1.52, 3.0]) ** 2).sum() ** 0.5
    assert right.unstretched_length == pytest.approx(length - 0.8 * 9.80665 / 5.19)
    assert p.to_update == ["outboard"] and [v.name for v in p.variables] == ["E"]


@pytest.mark.parametrize("change, expected", [
    (("[model]", "[model]\nmesh = 3"), "model.mesh: unknown key"),
    (('modes = "modes.json"', 'modes = "missing.json"'), "configurations[0] ('outboard').test.modes: test data file"),
    (('stiffness = "5.19 N/m"', 'stiffness = "5.19 kg"'), "configurations[0].cords[1].stiffness: unit mismatch"),
    (('targets = ["strip"]', 'targets = ["wing"]'), "variables[0] ('E'): design variable 'E': no beam group named"),
    (('role = "check"', 'role = "update"'), "configurations[1] ('inboard'): no test data"),
    (('from = "inboard"', 'from = "midspan"'), "configurations[1] ('inboard').from: the model has no configuration"),
    (('block_test = "left"', 'block_test = "centre"'), "cords[0].block_test: no suspension test 'centre'"),
    (('case = "strip_366"', 'case = "strip_367"'), "model.case: no built-in case 'strip_367'"),
    (('mass = "0.8 kg"', 'mass = "0.8 N"'), "suspension_tests[0].mass: unit mismatch"),
    (('node = 114', 'node = 9999'), "cords[1].node: node 9999 is not in model"),
    (("[project]", "[project\n"), "not valid TOML"),
])
def test_broken_project_names_the_key(tmp_path, change, expected):
    old, new = change
    assert old in GOOD
    t0 = time.perf_counter()
    with pytest.raises(ProjectError) as err:
        load_project(write(tmp_path, GOOD.replace(old, new, 1)))
    assert expected in str(err.value), str(err.value)
    assert str(tmp_path / "project.toml") in str(err.value)
    assert time.perf_counter() - t0 < 5.0  # stopped before any long computation


def test_missing_project_file(tmp_path):
    with pytest.raises(ProjectError, match="project file not found"):
        load_project(tmp_path / "nope.toml")


def test_a_configurations_own_masses_as_design_variables(tmp_path):
    """A mass variable with `configurations` reaches those configurations' own masses (the
    `from` configuration's, then `masses`, then the shaker's moving mass), not the model's."""
    text = GOOD.replace('[configurations.test]\nmodes = "modes.json"', '''[[configurations.masses]]
node = 10
mass = "20 g"
[[configurations.masses]]
node = 114
mass = "20 g"
[configurations.test]
modes = "modes.json"''', 1) + '''[[variables]]
name = "hardware"
kind = "mass"
targets = [0, 1]
attribute = "mass"
configurations = ["outboard"]
bounds = [0.25, 2.5]
'''
    p = load_project(write(tmp_path, text))
    hardware = p.variables[1]
    assert hardware.per_configuration and hardware.configurations == ("outboard",)
    from flexgvt.updating import Parametrisation
    par = Parametrisation(p.model, list(p.configurations.values()), p.variables)
    applied = par.apply(p.model.copy(), [1.0, 2.0])
    assert [m.mass for m in applied["outboard"].masses] == pytest.approx([0.04, 0.04])
    bad = text.replace("targets = [0, 1]", "targets = [0, 2]")
    with pytest.raises(ProjectError, match=r"configuration 'outboard' has no mass 2 \(2 masses of its own"):
        load_project(write(tmp_path, bad))


@pytest.mark.parametrize("directory, allow, expected", [
    ("../x", False, "outputs.directory: '../x' is outside the project folder"),
    ("/tmp/elsewhere", False, "outputs.directory: '/tmp/elsewhere' is outside the project folder"),
    ("results/../../x", False, "is outside the project folder"),
    ("a\\u0000b", False, "outputs.directory: the output directory path 'a\\x00b' contains a NUL character"),
    ("x" * 300, False, "outputs.directory: the output directory path is too long (300 characters"),
    ("modes.json", False, "outputs.directory: 'modes.json' exists and is not a folder"),
])
def test_output_directory_is_contained(tmp_path, directory, allow, expected):
    text = GOOD + f'[outputs]\ndirectory = "{directory}"\nallow_outside = {str(allow).lower()}\n'
    with pytest.raises(ProjectError) as err:
        load_project(write(tmp_path, text))
    assert expected in str(err.value), str(err.value)


def test_output_directory_outside_on_purpose(tmp_path):
    (tmp_path / "p").mkdir()
    p = load_project(write(tmp_path / "p", GOOD + '[outputs]\ndirectory = "../x"\nallow_outside = true\n'))
    assert p.output.resolve() == (tmp_path / "x").resolve()
    assert load_project(write(tmp_path / "p", GOOD + '[outputs]\ndirectory = "sub/results"\n')).output == \
        tmp_path / "p" / "sub" / "results"


@pytest.mark.parametrize("reference, expected", [
    ("project.toml", "is not valid JSON"),
    ("/proc/self/status", "is not valid JSON"),
    ("binary.bin", "is not a text file (expected JSON)"),
    ("ragged.json", "'frequencies_hz' must be a flat list of numbers"),
    ("labels.json", "2 labels for 1 frequencies"),
    ("negative.json", "finite frequencies > 0"),
    ("x" * 5000, "path is too long"),
])
def test_reference_is_read_and_checked_when_the_project_loads(tmp_path, reference, expected):
    import json
    (tmp_path / "binary.bin").write_bytes(bytes(range(256)))
    (tmp_path / "ragged.json").write_text(json.dumps({"free_free": {"frequencies_hz": [1.0, [], 3.0]}}))
    (tmp_path / "labels.json").write_text(json.dumps({"frequencies_hz": [1.0], "labels": ["a", "b"]}))
    (tmp_path / "negative.json").write_text(json.dumps({"frequencies_hz": [1.0, -2.0]}))
    text = GOOD + f'[prediction]\nreference = "{reference}"\n'
    with pytest.raises(ProjectError) as err:
        load_project(write(tmp_path, text))
    assert "prediction.reference" in str(err.value) and expected in str(err.value), str(err.value)


@pytest.mark.parametrize("change, expected", [
    (('targets = ["strip"]', "targets = [-1]"), "targets [-1] are not beam group names"),
    (("damping_ratio = [0.07, 0.068]", "damping_ratio = [0.07, 0.068, 0.07]"),
     "suspension_tests[0] ('left'): identify_block: 2 frequencies and 3 damping ratios"),
    (('stiffness = "5.19 N/m"', "stiffness = 0"), "cords[1]: stiffness 0.0 N/m must be > 0"),
    (('bounds = [0.8, 1.2]', 'bounds = "wide"'), "variables[0].bounds: expected a list [...], got 'wide'"),
    (("node = 114", "node = 1.5"), "cords[1].node: expected an integer, got 1.5"),
    (('modes = "modes.json"', 'modes = "modes.json"\npoints = "pts.csv"'), "pts.csv' not found"),
])
def test_wrong_values_are_named_in_the_projects_words(tmp_path, change, expected):
    old, new = change
    assert old in GOOD
    with pytest.raises(ProjectError) as err:
        load_project(write(tmp_path, GOOD.replace(old, new, 1)))
    msg = str(err.value)
    assert expected in msg and "pydantic" not in msg.lower() and "Input should" not in msg, msg
