"""ASET/ASET1/OMIT/OMIT1 read into BdfDeck.options (io/nastran/_reduction.py): components in basic
axes per grid, a rotated CD mapped, THRU ranges over missing grids skipped with a note, and the
errors (unknown grid, scalar point, a DOF in both sets, a CD not aligned with basic)."""

import warnings

import pytest

import flexgvt as fg
from flexgvt.errors import ModelError

DECK = """SOL 103
CEND
BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,2.,0.,0.
GRID,5,,3.,0.,0.,{cd}
CORD2R,7,,0.,0.,0.,0.,1.,0.,
,1.,0.,0.
CORD2R,8,,0.,0.,0.,0.,1.,1.,
,1.,0.,0.
CBAR,10,1,1,2,0.,0.,1.
CBAR,11,1,2,3,0.,0.,1.
CBAR,12,1,3,5,0.,0.,1.
PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8
MAT1,1,7.e10,,0.3,2700.
SPC1,1,123456,1
{cards}
ENDDATA
"""


def read(tmp_path, cards, cd=""):
    path = tmp_path / "deck.bdf"
    path.write_text(DECK.format(cards=cards, cd=cd))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        deck = fg.io.read_bdf(path)
    return deck, " ".join(str(w.message) for w in caught)


def test_sets_in_basic_axes_with_a_rotated_cd(tmp_path):
    # CD 7: x' = x, z' = y basic, y' = -z basic: component 2 is basic 3, 46 (about x', z') is basic 45
    deck, notes = read(tmp_path, "ASET,2,35,3,1\nASET1,2,5\nOMIT1,46,5\nOMIT,3,2", cd="7")
    assert deck.options["ASET"] == {2: "35", 3: "1", 5: "3"}
    assert deck.options["OMIT"] == {3: "2", 5: "45"}
    assert "ASET/ASET1/OMIT/OMIT1 (Guyan reduction: ASET 4 DOFs, OMIT 3 DOFs) kept in BdfDeck.options" in notes


def test_thru_range_skips_missing_grids_with_a_note(tmp_path):
    deck, notes = read(tmp_path, "ASET1,3,2,THRU,5")
    assert deck.options["ASET"] == {2: "3", 3: "3", 5: "3"}
    assert "ASET1 4: not a grid; skipped" in notes


def test_no_sets_no_options(tmp_path):
    deck, notes = read(tmp_path, "")
    assert "ASET" not in deck.options and "OMIT" not in deck.options and "Guyan" not in notes


@pytest.mark.parametrize("cards, cd, match", [
    ("ASET,9,3", "", r"deck.bdf:\d+: ASET 9 refers to grid 9, which is not defined"),
    ("ASET,2,0", "", r"ASET 2: components '0' must be digits 1-6 \(scalar points are not supported\)"),
    ("ASET1,3,2,3\nOMIT1,13,3", "", r"grid 3 components 3 are in both the analysis set .* and the omitted set"),
    ("ASET1,2,5", "8", r"ASET1 2: grid 5 has CD=8 and its components 2 do not line up with basic axes"),
])
def test_bad_sets_are_named(tmp_path, cards, cd, match):
    with pytest.raises(ModelError, match=match):
        read(tmp_path, cards, cd)
