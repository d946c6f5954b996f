"""Staged updating ([[stages]]) on a 15-element cantilever strip with synthetic data of a mistuned
truth (density x0.95, modulus x1.06, a 60 g tip mass where the model has 50 g): a weighing stage
(density from the measured mass), a GVT stage (modulus from the bare strip's modes) and an
installation stage (only the tip mass, on the strip carrying it), each from the previous stage's
model; the schema's errors; fixed inputs and bounds about the initial model; results.json; the report."""

import json
import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.model import ConcentratedMass
from flexgvt.workflow import ProjectError, load_project, run
from flexgvt.workflow.stages import apply_fixed, stage_variables, start_digest

RHO, E, TIP = 0.95, 1.06, 0.060  # the truth: density and modulus factors, tip mass [kg]

HEAD = """
[project]
name = "cantilever in stages"
[model]
case = "cantilever_strip"
[model.options]
n_elements = 15
[[configurations]]
name = "gvt"
from = "unloaded"
[configurations.test]
modes = "gvt.json"
[[configurations]]
name = "tip"
from = "unloaded"
[[configurations.masses]]
node = 16
mass = "50 g"
name = "tip"
[configurations.test]
modes = "tip.json"
[[variables]]
name = "rho"
kind = "beam"
targets = ["region*"]
attribute = "rho"
bounds = [0.8, 1.2]
[[variables]]
name = "E"
kind = "beam"
targets = ["region*"]
attribute = "E"
bounds = [0.8, 1.2]
[prediction]
free_free = false
[outputs]
report = false
uff = false
"""

STAGES = """
[[stages]]
name = "weights"
description = "the strip weighed"
variables = ["rho"]
[stages.objective.measured_mass]
mass = "{mass} kg"

[[stages]]
name = "GVT"
configurations = ["gvt"]
variables = ["E"]

[[stages]]
name = "installation"
configurations = ["tip"]
[stages.optimiser]
max_iterations = 40
[[stages.variables]]
name = "tip_mass"
kind = "mass"
targets = ["tip"]
configurations = ["tip"]
attribute = "mass"
bounds = [0.5, 2.0]
"""


def _truth():
    case = fg.cases.cantilever_strip(n_elements=15)
    truth = case.model.copy()
    for k in range(len(truth.beams)):
        g = truth.beams[k]
        truth.set_beam_group(k, material=fg.Material("as built", E=g.material.E * E,
                                                      G=g.material.shear_modulus * E, rho=g.material.rho * RHO))
    return case, truth


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("stages")
    case, truth = _truth()
    bare = case.configurations["unloaded"]
    tip = bare.with_(name="tip", masses=(ConcentratedMass(16, TIP, np.zeros(3), np.zeros((3, 3)), "tip"),))
    for name, cfg in (("gvt", bare), ("tip", tip)):
        modes = fg.solve_modes(fg.solve_static(truth, cfg), 6, damped=False)
        keep = [k for k, label in enumerate(modes.labels) if "OOP" in label][:3]  # what vertical sensors see
        (folder / f"{name}.json").write_text(json.dumps({
            "frequencies_hz": [float(modes.frequencies_hz[k]) for k in keep],
            "labels": [modes.labels[k] for k in keep]}))
    mass = fg.mass_properties(truth).mass
    (folder / "project.toml").write_text(HEAD + STAGES.format(mass=f"{mass:.12g}"))
    return folder


@pytest.fixture(scope="module")
def result(folder):
    return run(load_project(folder / "project.toml"))


def test_each_stage_recovers_its_part_of_the_truth_from_the_previous_stages_model(result):
    weights, gvt, installation = result.stages
    assert [s.stage.name for s in result.stages] == ["weights", "GVT", "installation"]
    assert weights.update.x == pytest.approx([RHO], rel=1e-6)
    assert gvt.update.x == pytest.approx([E], rel=1e-6)
    assert installation.update.variables[0]["final"] == pytest.approx(TIP, rel=1e-6)
    # Each stage starts from the model the previous one produced: stage 2 carries stage 1's density,
    # stage 3 both, and stage 3 updates only the tip mass (the strip's values stay stage 2's).
    for before, after in ((weights, gvt), (gvt, installation)):
        for g0, g1 in zip(before.model.beams, after.project.model.beams):
            assert g1.material.E == g0.material.E and g1.material.rho == g0.material.rho
    initial = fg.cases.cantilever_strip(n_elements=15).model.beams[0].material
    assert gvt.project.model.beams[0].material.rho == pytest.approx(initial.rho * RHO, rel=1e-6)
    final = result.model.beams[0].material
    assert (final.E, final.rho) == pytest.approx((initial.E * E, initial.rho * RHO), rel=1e-6)
    assert [v.name for v in installation.project.variables] == ["tip_mass"]
    # Stage 3's initial frequencies are stage 2's model on the tip configuration.
    start = fg.solve_modes(fg.solve_static(gvt.model, installation.project.configurations["tip"]), 6, damped=False)
    rows = installation.update.tables["tip"]
    assert [r["initial_hz"] for r in rows] == pytest.approx(
        [start.frequencies_hz[r["initial_mode"] - 1] for r in rows], rel=1e-9)
    assert max(abs(r["updated_error_percent"]) for r in rows) < 1e-6
    # The final model carries the tip mass into the configuration, and the run's update is the final stage's.
    assert result.update is installation.update
    assert result.stages[-1].configurations["tip"].masses[-1].mass == pytest.approx(TIP, rel=1e-6)


def test_results_json_lists_the_stages_and_keeps_the_final_stage_where_readers_expect_it(result):
    data = json.loads((result.project.output / "results.json").read_text())
    stages = data["stages"]
    assert [s["name"] for s in stages] == ["weights", "GVT", "installation"]
    assert stages[0]["description"] == "the strip weighed" and stages[0]["configurations"] == []
    assert stages[0]["mass_properties"][0]["updated_error_percent"] == pytest.approx(0, abs=1e-6)
    v = stages[1]["variables"][0]
    assert v["name"] == "E" and (v["lower"], v["upper"]) == (0.8, 1.2)
    assert v["final"] == pytest.approx(v["initial"] * E, rel=1e-6) and "std" in v
    assert list(stages[1]["frequencies"]) == ["gvt"] and len(stages[1]["frequencies"]["gvt"]) == 3
    for s in stages:
        assert s["objective"]["final"] < 1e-12 < s["objective"]["initial"] and s["iterations"] >= 1
    assert data["updating"]["variables"][0]["name"] == "tip_mass"
    assert data["updating"]["x"] == pytest.approx([stages[2]["variables"][0]["x"]])
    assert data["checks"]["updated"] == {}  # no check configuration; the final model was checked


def test_a_rerun_reads_every_stage_back_and_fresh_starts_again(result, folder):
    lines = []
    again = run(load_project(folder / "project.toml"), progress=lines.append)
    assert [s.resumed for s in again.stages] == [True, True, True]
    assert "updating GVT" in again.resumed
    assert np.array_equal(again.stages[2].update.x, result.stages[2].update.x)
    # A changed start (stage 1's answer) discards a stage's stored runs.
    stage = result.project.stages[1]
    assert start_digest("", stage, result.stages[0]) != start_digest("", stage, None)
    fresh = []
    run(load_project(folder / "project.toml"), progress=fresh.append, fresh=True)
    assert any("discarded the stored results" in s and "stage-2-GVT.sqlite" in s for s in fresh)


def test_the_report_shows_each_stage(result, tmp_path):
    from flexgvt.report.html import render
    from flexgvt.report.project import build_report_content
    content = build_report_content(result)
    assert [s.name for s in content.stages] == ["weights", "GVT", "installation"]
    assert content.stages[0].mass and content.stages[0].mass[0]["property"] == "mass [kg]"
    assert list(content.stages[2].frequencies) == ["tip"] and content.stages[2].variables[0]["name"] == "tip_mass"
    html = render(content)
    for title in ("Stage 1 of 3: weights", "Stage 2 of 3: GVT", "Stage 3 of 3: installation", "Mass properties"):
        assert title in html
    assert ("stages", "1. weights -> 2. GVT -> 3. installation") in content.summary


def _project(folder, stages: str, head: str = HEAD):
    (folder / "project.toml").write_text(head + stages)
    return load_project(folder / "project.toml")


STAGE = """
[[stages]]
name = "one"
configurations = ["gvt"]
variables = ["E"]
[[stages]]
name = "two"
configurations = ["tip"]
variables = ["rho"]
"""


OWN = """
[[stages]]
name = "three"
configurations = ["gvt"]
"""


@pytest.mark.parametrize("stages, message", [
    (STAGE.replace('["tip"]', '["tips"]'), "stages[1] ('two').configurations[0]: no configuration 'tips'"),
    (STAGE.replace('variables = ["rho"]', 'variables = ["rh0"]'), "stages[1] ('two').variables[0]: no variable 'rh0'"),
    (STAGE + '[[stages]]\nname = "empty"\n', "stages[2] ('empty'): an empty stage"),
    (STAGE.replace('name = "two"', 'name = "one"'), "stages: names must be unique; repeated: ['one']"),
    (STAGE.replace('["tip"]', '["gvt"]'), "configurations ['tip'] are updated on by no stage"),
    (STAGE.replace('configurations = ["tip"]\n', ''), "stages[1] ('two'): variables ['rho'] but nothing to update"),
    (STAGE.replace('variables = ["rho"]', 'variables = []'), "stages[1] ('two').variables: no design variable"),
    (STAGE + '[stages.bounds]\nE = [0.9, 1.1]\n', "stages[1] ('two').bounds.E: 'E' is not a variable of this stage"),
    (STAGE + '[stages.bounds]\nrho = [1.1, 0.9]\n', "stages[1] ('two').bounds.rho: design variable 'rho': bounds"),
    (STAGE + '[stages.set]\nG = "3 GPa"\n', "stages[1] ('two').set.G: no variable 'G'"),
    (STAGE + '[stages.set]\nE = "3 kg"\n', "stages[1] ('two').set.E: unit mismatch"),
    (STAGE + OWN + '[[stages.variables]]\nname = "k"\nkind = "beam"\ntargets = ["wing"]\nattribute = "E"\n',
     "stages[2] ('three').variables: design variable 'k': no beam group named ['wing']"),
    (STAGE + OWN + '[[stages.variables]]\nname = "E"\nkind = "beam"\ntargets = ["region1"]\nattribute = "E"\n',
     "stages[2] ('three').variables[0]: a variable 'E' is defined under [[variables]] already"),
    (STAGE + '[[stages]]\nname = "three"\nvariables = ["E"]\n[[stages.configurations]]\nname = "gvt"\n',
     "stages[2] ('three').configurations[0]: a configuration 'gvt' is defined already"),
    (STAGE.replace('configurations = ["gvt"]\n', 'configurations = ["gvt"]\nrecentre = "maybe"\n'),
     "stages[0].recentre: expected true or false"),
])
def test_bad_stage_definitions_are_named(folder, tmp_path, stages, message):
    for name in ("gvt.json", "tip.json"):
        (tmp_path / name).write_bytes((folder / name).read_bytes())
    with pytest.raises(ProjectError) as err:
        _project(tmp_path, stages)
    assert message in str(err.value), str(err.value)


def test_a_check_configuration_cannot_be_updated_on_in_a_stage(folder, tmp_path):
    for name in ("gvt.json", "tip.json"):
        (tmp_path / name).write_bytes((folder / name).read_bytes())
    head = HEAD.replace('name = "tip"\nfrom = "unloaded"\n', 'name = "tip"\nfrom = "unloaded"\nrole = "check"\n')
    with pytest.raises(ProjectError, match=r"configuration 'tip' has role = \"check\""):
        _project(tmp_path, STAGE, head)


def test_fixed_inputs_and_bounds_about_the_initial_model(folder, tmp_path):
    """A component-test stage of fixed inputs (the tip-load modulus, in GPa) sets every target; a later
    stage with recentre = false keeps its bounds about the initial model, in its own normalised values."""
    for name in ("gvt.json", "tip.json"):
        (tmp_path / name).write_bytes((folder / name).read_bytes())
    stages = """
[[stages]]
name = "components"
[stages.set]
E = "77 GPa"
[[stages]]
name = "GVT"
configurations = ["gvt", "tip"]
variables = ["E", "rho"]
recentre = false
"""
    project = _project(tmp_path, stages)
    components, gvt = project.stages
    assert not components.updates and components.values == {"E": 77e9}
    model, configs, rows = apply_fixed(components, project.model, project.configurations)
    assert [g.material.E for g in model.beams] == pytest.approx([77e9] * 3)
    assert rows[0]["before"] == pytest.approx(70e9) and rows[0]["value"] == 77e9
    assert project.model.beams[0].material.E == pytest.approx(70e9)  # the project's model is not changed
    bounds = {v.name: v.bounds for v in stage_variables(gvt, project, model, configs)}
    assert bounds["E"] == pytest.approx((0.8 / 1.1, 1.2 / 1.1)) and bounds["rho"] == pytest.approx((0.8, 1.2))
    # Set outside the bounds about the initial model: said, with the remedy.
    too_far = _project(tmp_path, stages.replace("77 GPa", "90 GPa"))
    model, configs, _ = apply_fixed(too_far.stages[0], too_far.model, too_far.configurations)
    with pytest.raises(ProjectError, match="outside its bounds .* set recentre = true"):
        stage_variables(too_far.stages[1], too_far, model, configs)


def test_a_project_without_stages_is_one_stage_as_before(folder, tmp_path):
    for name in ("gvt.json", "tip.json"):
        (tmp_path / name).write_bytes((folder / name).read_bytes())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        project = _project(tmp_path, "")
    assert project.stages == [] and project.to_update == ["gvt", "tip"]
    assert [v.name for v in project.variables] == ["rho", "E"]


def test_a_shell_stage_of_fixed_inputs_then_a_shell_variable(tmp_path):
    """Shell variables (the swept wing's laminate spar) in a project file: a component stage sets the spars'
    modulus, the next updates the skins' thickness on the wingbox's GVT."""
    (tmp_path / "gvt.json").write_text(json.dumps({"frequencies_hz": [9.1, 27.3, 40.2]}))  # loaded, not run
    (tmp_path / "project.toml").write_text("""
[model]
case = "wingbox"
[model.options]
element_size = 0.25
[[configurations]]
name = "gvt"
from = "unloaded"
[configurations.test]
modes = "gvt.json"
[[variables]]
name = "E_spars"
kind = "shell"
targets = ["spar_*"]
attribute = "E"
[[stages]]
name = "coupons"
set = { E_spars = "70 GPa" }
[[stages]]
name = "GVT"
configurations = ["gvt"]
[[stages.variables]]
name = "t_skin"
kind = "shell"
targets = ["skin_*"]
attribute = "thickness"
bounds = [0.8, 1.2]
""")
    project = load_project(tmp_path / "project.toml")
    coupons, gvt = project.stages
    assert coupons.values == {"E_spars": 70e9} and gvt.variables[0].kind == "shell"
    model, _, rows = apply_fixed(coupons, project.model, project.configurations)
    assert rows[0]["value"] == 70e9 and rows[0]["before"] > 0
