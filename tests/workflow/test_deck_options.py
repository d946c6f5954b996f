"""A project's deck: unit systems by the names engineers write (or a table of units), [model.options]
passed to the reader (unsupported = "warn"), unknown options refused, hints in project keys."""

import re
import warnings

import numpy as np
import pytest

from flexgvt.errors import FlexGVTWarning
from flexgvt.workflow import load_project
from flexgvt.workflow.projectbase import ProjectError
from flexgvt.workflow.units import unit_system

BEAM = """SOL 103
CEND
SPC = 1
BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1000.,0.,0.
CBAR,10,1,1,2,0.,0.,1.
PBAR,1,1,100.,1.e4,2.e4,1.e4
MAT1,1,7.e4,,0.3,2.7e-9
SPC1,1,123456,1
"""
PROJECT = """[model]
bdf = "deck.bdf"
%s
[[configurations]]
name = "c"
from = "deck"
role = "check"
"""


def _load(tmp_path, model_keys: str, extra_cards: str = ""):
    (tmp_path / "deck.bdf").write_text(BEAM + extra_cards + "ENDDATA\n")
    (tmp_path / "project.toml").write_text(PROJECT % model_keys)
    return load_project(tmp_path / "project.toml")


@pytest.mark.parametrize("value, expected", [
    ('"SI"', (1.0, 1.0)), ('"m-kg-s"', (1.0, 1.0)), ('"mm-N-t-s"', (1e-3, 1.0)), ('"mm-t-s"', (1e-3, 1.0)),
    ('"MM-T-S"', (1e-3, 1.0)), ('"in-lbf-s"', (0.0254, 4.4482216152605)), ('"ft-lbf-s"', (0.3048, 4.4482216152605)),
    ('{length = "mm", force = "N"}', (1e-3, 1.0)), ('{length = "mm", mass = "t", time = "s"}', (1e-3, 1.0)),
    ('{length = "in", mass = "lbm"}', (0.0254, 0.45359237 * 0.0254)),
])
def test_unit_systems_by_name_or_table(value, expected):
    import tomllib

    name, length, force = unit_system(tomllib.loads(f"u = {value}")["u"])
    assert (length, force) == pytest.approx(expected, rel=1e-12)


def test_an_mm_deck_reads_the_same_as_its_si_twin(tmp_path):
    mm = _load(tmp_path, 'units = "mm-t-s"').model
    table = _load(tmp_path, 'units = {length = "mm", force = "N"}').model
    assert mm.xyz[1, 0] == pytest.approx(1.0) and table.xyz[1, 0] == pytest.approx(1.0)
    assert mm.beams[0].material.E == pytest.approx(7e10) and mm.beams[0].material.rho == pytest.approx(2700.0)


@pytest.mark.parametrize("value, match", [
    ('"mm-kg-fortnight"', r"model\.units: unknown unit system 'mm-kg-fortnight'; write one of \"SI\".*\"mm-t-s\""),
    ("5", r"model\.units: expected a unit system name"),
    ('{length = "mm", force = "kg"}', r"model\.units: force: 'kg' is not a unit of force"),
    ('{length = "mm", speed = "N"}', r"model\.units: unknown key\(s\) \['speed'\]"),
    ('{length = "mm", force = "N", mass = "kg"}', r"model\.units: .*not consistent"),
    ('{length = "mm", force = "N", time = "ms"}', r"model\.units: time: 'ms': decks are read in seconds only"),
])
def test_bad_units_say_what_to_write_without_pydantic_internals(tmp_path, value, match):
    with pytest.raises(ProjectError, match=match) as err:
        _load(tmp_path, f"units = {value}")
    assert not re.search(r"function-|<lambda>|pydantic|Value error|Input should", str(err.value))


def test_template_units_suggestions_load(tmp_path):
    from flexgvt.workflow.template import example_project

    lines = [ln for ln in example_project().splitlines() if "units" in ln]
    value = lines[0].split("=", 1)[1].split("#")[0].strip()
    assert _load(tmp_path, f"units = {value}").model.xyz[1, 0] == pytest.approx(1.0)  # "mm-t-s"
    names = re.split(r"[,:()]\s*|\s+", lines[0].split("units:")[1])
    assert {"SI", "m-kg-s", "mm-N-t-s", "mm-t-s", "in-lbf-s", "ft-lbf-s"} <= set(names)
    for name in filter(None, names):
        unit_system(name)
    table = lines[1].split("units =", 1)[1].strip()
    assert _load(tmp_path, f"units = {table}").model.xyz[1, 0] == pytest.approx(1.0)


def test_unsupported_cards_from_a_project(tmp_path):
    # A shear panel: a card flexgvt does not read (plates it reads since the plate cards came in).
    shear_panel = "GRID,3,,1000.,1000.,0.\nGRID,4,,0.,1000.,0.\nCSHEAR,60,2,1,2,3,4\nPSHEAR,2,1,1.\n"
    with pytest.raises(ProjectError, match=r"model\.bdf: .*CSHEAR: 60.*unsupported = \"warn\" under "
                                           r"\[model\.options\].*--allow-unsupported") as err:
        _load(tmp_path, 'units = "mm-t-s"', shear_panel)
    assert "read_bdf" not in str(err.value)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        project = _load(tmp_path, 'units = "mm-t-s"\n[model.options]\nunsupported = "warn"', shear_panel)
    assert project.model.n_beams == 1 and np.isclose(project.model.xyz[1, 0], 1.0)
    assert any(issubclass(w.category, FlexGVTWarning) and "CSHEAR" in str(w.message) and "model.bdf" in
               str(w.message) for w in caught)


@pytest.mark.parametrize("options, match", [
    ('unsuported = "warn"', r"model\.options\.unsuported: unknown key for a deck; the keys are unsupported, mass"),
    ('unsupported = "ignore"', r"model\.options\.unsupported: 'ignore' must be \"error\" or \"warn\""),
    ('rotary_inertia = 1', r"model\.options\.rotary_inertia: 1 must be true or false"),
])
def test_deck_options_are_checked(tmp_path, options, match):
    with pytest.raises(ProjectError, match=match):
        _load(tmp_path, f"[model.options]\n{options}")


def test_a_deck_asking_for_guyan_reduction_is_solved_whole_and_says_so(tmp_path):
    """ASET/OMIT in a project's deck: the project works on the full model (updating needs its exact
    modes and sensitivities) and says so once, naming the sets and where the reduced modes are."""
    with pytest.warns(FlexGVTWarning, match=r"Guyan reduction \(ASET\).*full model.*flexgvt solve"):
        project = _load(tmp_path, "", "ASET1,3,2\n")
    assert project.model.n_nodes == 2
    with warnings.catch_warnings():
        warnings.simplefilter("error", FlexGVTWarning)
        _load(tmp_path, "")  # no sets: no such warning
