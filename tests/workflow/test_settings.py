"""Settings defined once: the project file's tables come from the library's settings dataclasses,
update() takes the same defaults, and docs/settings.md is generated from them."""

import inspect
from dataclasses import fields
from pathlib import Path

import pytest

import flexgvt.updating as up
from flexgvt.errors import ModelError
from flexgvt.workflow.schema import ProjectFile
from flexgvt.workflow.settingsdoc import settings_page
from flexgvt.workflow.template import example_project

DOC = Path(__file__).resolve().parents[2] / "docs" / "settings.md"
MINIMAL = {"model": {"case": "xhale"}, "configurations": [{"name": "a"}]}


def test_settings_page_is_up_to_date():
    assert DOC.read_text(encoding="utf-8") == settings_page() + "\n", \
        "docs/settings.md is out of date: run `python bench/settingsdoc.py`"


def test_update_and_the_project_file_share_the_optimiser_defaults():
    spec = ProjectFile.model_validate(MINIMAL)
    assert spec.optimiser == up.OptimiserSettings()
    signature = inspect.signature(up.update).parameters
    for f in fields(up.OptimiserSettings):
        assert signature[f.name].default == getattr(spec.optimiser, f.name), f.name
    objective = spec.objective
    assert up.Objective(**{f.name: getattr(objective, f.name) for f in fields(up.Objective)}) == up.Objective()


def test_project_tables_validate_into_the_dataclasses_with_units_and_limits():
    spec = ProjectFile.model_validate({**MINIMAL, "optimiser": {"max_iterations": 7},
                                       "objective": {"measured_mass": {"mass": "2.5 kg", "cg": [0, "4 mm", 0]}}})
    assert isinstance(spec.optimiser, up.OptimiserSettings) and spec.optimiser.max_iterations == 7
    assert spec.objective.measured_mass == up.MassTarget(mass=2.5, cg=(0.0, 0.004, 0.0))
    for bad in ({"optimiser": {"max_iterations": 0}}, {"optimiser": {"method": "newton"}},
                {"optimiser": {"tol": 1e-3}}, {"objective": {"mac_floor": 1.5}},
                {"objective": {"measured_mass": {"mass": "2 m"}}}):
        with pytest.raises(ValueError):
            ProjectFile.model_validate({**MINIMAL, **bad})
    with pytest.raises(ModelError, match="max_iterations"):
        up.OptimiserSettings(max_iterations=0)


def test_the_shipped_project_states_its_limits():
    """flexgvt init, the demo and the X-HALE example state their limits explicitly: 100 evaluations at a
    relative tolerance of 1e-4, under which they converge (docs/workflow.md, "Limits, convergence and
    resuming under other limits"), instead of stopping at the evaluation limit as with 60 at 1e-8."""
    text = example_project("xhale")
    assert "max_iterations = 100" in text and "tolerance = 1e-4" in text


def test_callback_is_a_deprecated_name_of_progress():
    with pytest.warns(DeprecationWarning, match="progress"):
        with pytest.raises(ModelError, match="design variable"):  # no variables: after the warning
            up.update(None, [], [], [], callback=print)


def test_a_variable_without_bounds_gets_its_kinds_default_in_scripts_and_projects():
    from flexgvt.updating.variables import DEFAULT_BOUNDS
    assert up.spring("k", "root").bounds == DEFAULT_BOUNDS["spring"] == (0.5, 2.0)
    assert up.cord("c").bounds == up.Variable("c", "cord", "stiffness").bounds == (0.8, 1.2)
    spec = ProjectFile.model_validate({**MINIMAL, "variables": [{"name": "k", "kind": "spring", "targets": ["root"],
                                                                 "attribute": "k1"}]})
    assert spec.variables[0].bounds is None  # resolved by Variable, as a script's
