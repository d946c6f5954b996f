"""Resuming a project run: changed limits continue the stored run, --fresh starts again, Ctrl-C says
where the run stopped and the rerun says it resumes, a previous run's outputs never look current."""

import json
import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.workflow import RunInterrupted, load_project, run

PROJECT = """
[model]
bdf = "strip.bdf"
[[configurations]]
name = "hang"
from = "unloaded"
[configurations.test]
modes = "modes.json"
[[variables]]
name = "E1"
kind = "beam"
targets = ["PBEAML_1"]
attribute = "E"
bounds = [0.8, 1.2]
[[variables]]
name = "E2"
kind = "beam"
targets = ["PBEAML_2"]
attribute = "E"
bounds = [0.8, 1.2]
[optimiser]
max_iterations = {max_iterations}
tolerance = 1e-12
[prediction]
free_free = false
[outputs]
report = false
uff = false
bdf = false
"""


def _project(folder, max_iterations):
    (folder / "project.toml").write_text(PROJECT.format(max_iterations=max_iterations))
    return load_project(folder / "project.toml")


@pytest.fixture()
def folder(tmp_path):
    case = fg.cases.cantilever_strip(n_elements=15)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fg.io.write_bdf(case.model, tmp_path / "strip.bdf", configurations=[case.configurations["unloaded"]])
        deck = fg.io.read_bdf(tmp_path / "strip.bdf")
    truth = deck.model.copy()
    for k, factor in ((0, 1.06), (1, 0.95)):
        g = truth.beams[k]
        truth.set_beam_group(k, material=fg.Material("t", E=g.material.E * factor,
                                                      G=g.material.shear_modulus * factor, rho=g.material.rho))
    f = fg.solve_modes(fg.solve_static(truth, deck.configurations["unloaded"]), 5, damped=False).frequencies_hz
    (tmp_path / "modes.json").write_text(json.dumps({"frequencies_hz": f[:4].tolist()}))
    return tmp_path


def test_raised_limit_continues_from_the_stored_point_and_fresh_starts_again(folder):
    lines = []
    short = run(_project(folder, 4), progress=lines.append)
    assert not short.update.success and any("stopped before its tolerance" in s and "max_iterations" in s
                                            for s in lines)
    # The same limits: the stored answer, said so.
    lines.clear()
    same = run(_project(folder, 4), progress=lines.append)
    assert any("finished run read back from the store" in s for s in lines)
    assert np.array_equal(same.update.x, short.update.x)
    # Raised: the stored run continues (its evaluations answered without solving) to the uninterrupted answer.
    lines.clear()
    longer = run(_project(folder, 60), progress=lines.append)
    assert any("continuing it under max_iterations = 60" in s and "max_iterations = 4" in s for s in lines)
    assert longer.update.success and longer.update.solves < 60
    assert longer.update.x == pytest.approx([1.06, 0.95], rel=1e-6)
    # --fresh discards the store and computes the same answer from the start.
    lines.clear()
    fresh = run(_project(folder, 60), progress=lines.append, fresh=True)
    assert any(s.startswith("fresh run: discarded the stored results") for s in lines)
    assert not any("from the store" in s for s in lines)
    np.testing.assert_allclose(fresh.update.x, longer.update.x, rtol=1e-12)


def test_ctrl_c_says_where_it_stopped_and_the_rerun_resumes(folder):
    project = _project(folder, 60)
    run(project, fresh=True)  # a completed run: its outputs are the 'previous' ones below
    results = project.output / "results.json"
    assert results.is_file()

    def interrupt(row):
        if row["iteration"] == 2:
            raise KeyboardInterrupt

    with pytest.raises(RunInterrupted) as info:
        run(project, iterations=interrupt, fresh=True)
    msg = info.value.message
    assert "interrupted in the updating after" in msg and "best objective" in msg and "rerun resumes" in msg
    assert info.value.status["evaluations"] > 0 and isinstance(info.value, KeyboardInterrupt)
    # The previous outputs are set aside, with a note, not left looking current.
    stale = project.output / "stale-outputs"
    assert not results.exists() and (stale / "results.json").is_file() and (stale / "README.txt").is_file()
    lines = []
    res = run(project, progress=lines.append)
    assert any("resuming the interrupted run from the store" in s for s in lines)
    assert res.update.x == pytest.approx([1.06, 0.95], rel=1e-6)
    assert results.is_file() and not stale.exists()  # completed: the outputs are current again
