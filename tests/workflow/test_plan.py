"""Pre-test planning of a user's own project (flexgvt.workflow.plan) on a Nastran deck from tests/data:
the ranking is physically right (pendulum sqrt(g/L); a suspension on the first bending mode's node
lines perturbs it least), sensors and driving points are placed on the deformed configuration, and
[plan] keys are checked like the rest of the project file."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from flexgvt.workflow import ProjectError
from flexgvt.workflow.plan import load_plan_project, plan_project

DECK = Path(__file__).parents[1] / "data" / "bdf" / "free_strip.bdf"
G = 9.80665

# The 2 m free strip (0.81 kg) under its own weight; stations: the first bending mode's node lines
# (y = +-0.55 m, 0.224 L from the ends), the tips, and +-0.25 m.
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
{extra}
[plan]
n_modes = 5
stations = [[110, 132], [101, 141], [116, 126]]
stiffness = ["20 N/m"]
length = ["1 m", "4 m"]
sensors = 6
directions = "Z"
{plan}
"""


def _project(tmp_path, extra: str = "", plan: str = "") -> Path:
    shutil.copy(DECK, tmp_path / "free_strip.bdf")
    path = tmp_path / "project.toml"
    path.write_text(PROJECT.format(extra=extra, plan=plan))
    return path


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plan")
    return plan_project(load_plan_project(_project(folder)))


def _suspension_hz(result, label: str) -> float:
    return float(result.suspension_hz[result.suspension_labels.index(label)])


def test_pendulum_frequency_follows_sqrt_g_over_length(planned):
    """The spanwise swing of the hung strip is a pendulum of the cord's length: sqrt(g/L)/(2 pi)."""
    by = {r.name: r for r in planned.configurations["clean"].layouts}
    for length in (1.0, 4.0):
        r = by[f"20 N/m, {length:g} m at nodes 110, 132"]
        assert _suspension_hz(r, "RB lateral") == pytest.approx(np.sqrt(G / length) / (2 * np.pi), rel=1e-3)
    short, long = by["20 N/m, 1 m at nodes 110, 132"], by["20 N/m, 4 m at nodes 110, 132"]
    assert _suspension_hz(short, "RB lateral") / _suspension_hz(long, "RB lateral") == pytest.approx(2.0, rel=1e-3)
    # The plunge mode is the springs' alone, sqrt(2 k / m), whatever the cord length.
    plunge = np.sqrt(2 * 20.0 / 0.81) / (2 * np.pi)
    assert _suspension_hz(short, "RB plunge") == pytest.approx(plunge, rel=0.005)
    assert _suspension_hz(long, "RB plunge") == pytest.approx(_suspension_hz(short, "RB plunge"), rel=1e-3)


def test_a_suspension_on_the_node_lines_perturbs_the_first_bending_mode_least(planned):
    plan = planned.configurations["clean"]
    rows = plan.layout_rows()
    first = {r["suspension"]: r["first_elastic_shift_percent"] for r in rows}
    node_lines = first["20 N/m, 4 m at nodes 110, 132"]
    tips = first["20 N/m, 4 m at nodes 101, 141"]
    inboard = first["20 N/m, 4 m at nodes 116, 126"]
    assert abs(node_lines) < 0.05 and tips > 10 and 1 < inboard < tips  # springs at the tips stiffen it by 15 %
    # Ranked: the node-line stations first (acceptable, nothing contaminated), the tips last.
    assert [r["suspension"].split(" at ")[1] for r in rows[:2]] == ["nodes 110, 132"] * 2
    assert all(r["acceptable"] for r in rows[:2]) and rows[0]["contaminated"] == ""
    assert [r["suspension"].split(" at ")[1] for r in rows[-2:]] == ["nodes 101, 141"] * 2
    assert rows[-1]["contaminated"].startswith("1 OOP")
    assert plan.tested == rows[0]["suspension"]


def test_sensors_and_driving_points_on_the_deformed_strip(planned):
    plan = planned.configurations["clean"]
    assert [r["label"] for r in plan.target_rows()] == ["1 OOP", "2 OOP", "3 OOP", "4 OOP", "5 OOP"]
    assert len(plan.sensors) == 6 and all(s.name.endswith("+Z") for s in plan.sensors)
    assert plan.auto_mac_max < 0.5
    Phi = np.asarray(plan.sensors.matrix(plan.modes.node_ids, plan.state) @ plan.modes.matrix()[:, plan.targets])
    assert np.linalg.matrix_rank(Phi) == 5
    # The free strip's tips are antinodes of every bending mode: the best driving points.
    assert {e["node"] for e in plan.exciters[:2]} == {101, 141} and plan.exciters[0]["min_residue"] > 0.9
    assert plan.notes == []


def test_plan_writes_tables_and_json(planned):
    files = planned.files
    assert {"layouts_clean", "sensors_clean", "exciters_clean", "targets_clean", "json"} <= set(files)
    data = json.loads(files["json"].read_text())
    cfg = data["configurations"][0]
    assert cfg["configuration"] == "clean" and len(cfg["layouts"]) == 6 and len(cfg["sensors"]) == 6
    assert cfg["auto_mac_max_offdiagonal"] == pytest.approx(planned.configurations["clean"].auto_mac_max)
    header = files["layouts_clean"].read_text().splitlines()[0]
    assert header.startswith("rank,suspension,acceptable,highest_suspension_hz,first_elastic_hz,separation")


def test_masses_of_a_configuration_are_hung_with_it(tmp_path):
    extra = """[[configurations.masses]]
node = 101
mass = "50 g"
[[configurations.masses]]
node = 141
mass = "50 g"
"""
    path = _project(tmp_path, extra)
    path.write_text(path.read_text().replace('length = ["1 m", "4 m"]', 'length = ["4 m"]'))
    res = plan_project(load_plan_project(path))
    plan = res.configurations["clean"]
    assert all(r.tensions == pytest.approx([(0.81 + 0.1) * G / 2] * 2, rel=1e-3) for r in plan.layouts)


def test_a_bad_plan_key_is_an_error_naming_it(tmp_path):
    with pytest.raises(ProjectError, match=r"project.toml: plan.sensor: unknown key"):
        load_plan_project(_project(tmp_path, plan="sensor = 4"))
    with pytest.raises(ProjectError, match=r"plan.stiffness\[0\]: .*mm"):
        load_plan_project(_project_replacing(tmp_path, 'stiffness = ["20 N/m"]', 'stiffness = ["20 mm"]'))
    with pytest.raises(ProjectError, match=r"plan.stations\[1\]: node\(s\) \[999\] not in model"):
        load_plan_project(_project_replacing(tmp_path, "[101, 141]", "[101, 999]"))
    with pytest.raises(ProjectError, match=r"plan: exciter_directions: 'W' must be letters of X, Y, Z"):
        load_plan_project(_project(tmp_path, plan='exciter_directions = "W"'))
    with pytest.raises(ProjectError, match=r"plan.sensors: 50 sensors but only 41 candidates"):
        load_plan_project(_project_replacing(tmp_path, "sensors = 6", "sensors = 50"))
    with pytest.raises(ProjectError, match=r"plan.configurations\[0\]: no configuration 'hung'"):
        load_plan_project(_project(tmp_path, plan='configurations = ["hung"]'))


def _project_replacing(tmp_path, old: str, new: str) -> Path:
    path = _project(tmp_path)
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    return path


OWN = """
[model]
bdf = "free_strip.bdf"
[model.options]
cbar_torsional_inertia = true
[[configurations]]
name = "hung"
from = "subcase_2"
[[configurations.cords]]
node = 110
anchor = [0.0, -0.55, 2.0]
stiffness = "5 N/m"
carries = "0.405 kg"
[[configurations.cords]]
node = 132
anchor = [0.0, 0.55, 2.0]
stiffness = "5 N/m"
carries = "0.405 kg"
[[configurations]]
name = "free"
from = "subcase_1"
[plan]
n_modes = 4
sensors = 4
directions = "Z"
exciters = 2
"""


def test_a_configuration_with_its_own_cords_or_none_is_planned_as_it_stands(tmp_path):
    """No candidates in [plan]: a configuration with cords is assessed and planned on them; a free
    one on itself, its six rigid-body modes (0 Hz) left out of the targets. No test data, no variables."""
    shutil.copy(DECK, tmp_path / "free_strip.bdf")
    (tmp_path / "project.toml").write_text(OWN)
    res = plan_project(load_plan_project(tmp_path / "project.toml"))
    hung, free = res.configurations["hung"], res.configurations["free"]
    assert hung.tested == "as configured (hung)" and [r.name for r in hung.layouts] == ["as configured (hung)"]
    assert hung.layouts[0].acceptable and hung.layouts[0].tensions == pytest.approx([0.405 * G] * 2, rel=1e-3)
    assert free.tested == "as configured (no suspension)" and free.layouts == []
    assert [r["label"] for r in free.target_rows()] == ["1 OOP", "2 OOP", "3 OOP", "4 OOP"]
    assert free.target_rows()[0]["frequency_hz"] == pytest.approx(3.918, rel=1e-3)  # free-free first bending
    assert len(free.sensors) == 4 and len(free.exciters) == 2


def test_a_free_configuration_under_gravity_without_a_suspension_is_refused_with_the_remedy(tmp_path):
    path = _project_replacing(tmp_path, 'stations = [[110, 132], [101, 141], [116, 126]]', "")
    path.write_text(path.read_text().replace('stiffness = ["20 N/m"]\nlength = ["1 m", "4 m"]', ""))
    with pytest.raises(ProjectError, match=r"plan \(configuration 'clean'\): the configuration has no supports and "
                       r"no suspension .*give candidate suspensions \(plan.stations"):
        plan_project(load_plan_project(path))


def test_sensor_directions_that_miss_the_targets_are_noted(tmp_path):
    """Chordwise (X) sensors on a strip whose targets bend flatwise (Z): the plan says they barely see them."""
    shutil.copy(DECK, tmp_path / "free_strip.bdf")
    text = OWN.replace('directions = "Z"', 'directions = "X"\nconfigurations = ["free"]')
    (tmp_path / "project.toml").write_text(text)
    plan = plan_project(load_plan_project(tmp_path / "project.toml")).configurations["free"]
    assert [r["seen_by_candidates"] < 1e-6 for r in plan.target_rows()] == [True] * 4
    assert any("candidate sensor directions (X) barely see 1 OOP (0.0 %), 2 OOP" in n for n in plan.notes)


def test_a_band_picks_the_targets_by_frequency(tmp_path):
    """band_hz above the lowest modes: more modes are solved until the band's are found."""
    path = _project_replacing(tmp_path, "[[110, 132], [101, 141], [116, 126]]", "[[110, 132]]")
    path.write_text(path.read_text() + 'band_hz = ["40 Hz", "100 Hz"]\n')
    plan = plan_project(load_plan_project(path)).configurations["clean"]
    rows = plan.target_rows()
    assert [r["label"] for r in rows] == ["5 OOP", "1 IP", "6 OOP", "1 T", "7 OOP"]
    assert all(40 <= r["frequency_hz"] <= 100 for r in rows)
    assert any("barely see 1 IP (0.0 %), 1 T (0.0 %)" in n for n in plan.notes)  # Z sensors on the axis
