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
