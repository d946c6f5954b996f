"""A project on the user's own Nastran deck: subcases as configurations, a shaker and a test load,
the updated deck written back with the user's cards and read to the updated frequencies."""

import json

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.workflow import load_project, run

PROJECT = """
[model]
bdf = "strip.bdf"
[[configurations]]
name = "loaded"
from = "{loaded}"
[configurations.shaker]
node = {tip}
mass = "12 g"
[[configurations.forces]]
node = {mid}
force = [0.0, 0.0, "-0.05 N"]
[configurations.test]
modes = "modes.json"
[[variables]]
name = "E_mid"
kind = "beam"
targets = ["PBEAML_2"]
attribute = "E"
bounds = [0.9, 1.1]
[prediction]
free_free = false
[outputs]
report = false
uff = false
"""


def test_deck_project_updates_the_users_deck(tmp_path):
    case = fg.cases.cantilever_strip(n_elements=30)
    fg.io.write_bdf(case.model, tmp_path / "strip.bdf",
                    configurations=[case.configurations["unloaded"], case.configurations["self_weight"]])
    deck = fg.io.read_bdf(tmp_path / "strip.bdf")
    tip, mid = int(case.references["tip_node"]), int(case.references["tip_node"]) - 15
    # The 'test': the deck's model with E of the middle third 4 % up, shaker mass and load on.
    truth = deck.model.copy()
    g = truth.beams[1]
    truth.set_beam_group(1, material=fg.Material("t", E=g.material.E * 1.04, G=g.material.shear_modulus * 1.04,
                                                  rho=g.material.rho))
    cfg = deck.configurations["self_weight"].with_(  # the subcase's LABEL (written from the configuration's name)
        masses=(fg.model.ConcentratedMass(tip, 0.012, np.zeros(3), np.zeros((3, 3))),),
        forces=(fg.NodalLoad(mid, (0.0, 0.0, -0.05)),))
    f = fg.solve_modes(fg.solve_static(truth, cfg), 6, damped=False).frequencies_hz[:5]
    (tmp_path / "modes.json").write_text(json.dumps({"frequencies_hz": f.tolist()}))
    (tmp_path / "project.toml").write_text(PROJECT.format(tip=tip, mid=mid, loaded="self_weight"))
    project = load_project(tmp_path / "project.toml")
    c = project.configurations["loaded"]
    assert c.masses[-1].mass == pytest.approx(0.012) and c.forces[-1].force == (0.0, 0.0, -0.05)
    res = run(project)
    assert res.update.x[0] == pytest.approx(1.04, abs=2e-3)
    text = (project.output / "updated.bdf").read_text()
    assert "SUBCASE" in text  # the user's case control kept
    back = fg.io.read_bdf(project.output / "updated.bdf")
    assert back.model.beams[1].material.E == pytest.approx(res.model.beams[1].material.E, rel=1e-9)
    m1 = fg.solve_modes(fg.solve_static(back.model, back.configurations["unloaded"]), 5).frequencies_hz
    m0 = fg.solve_modes(fg.solve_static(res.model, deck.configurations["unloaded"]), 5).frequencies_hz
    np.testing.assert_allclose(m1, m0, rtol=1e-8)
