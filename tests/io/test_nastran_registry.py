"""The card-family registry of the bulk data reader: which family reads which card, and a new
family plugging in without touching the others (what the plate family will do)."""

import dataclasses

import pytest

import flexgvt as fg
from flexgvt.io.nastran import UnsupportedCardsError, _read, _registry
from flexgvt.io.nastran._deck import Deck, Family, Parts

# The cards read_bdf read before the registry (the old READ_CARDS literal): the registry must read
# exactly these, each in one family.
READ_BEFORE = {
    "CBAR", "CBEAM", "CROD", "CONROD", "CONM2", "CONM1", "CELAS1", "CELAS2", "CDAMP1", "CDAMP2", "CVISC", "CBUSH",
    "RBE2", "RBE3", "RBAR", "PBAR", "PBARL", "PBEAM", "PBEAML", "PROD", "PELAS", "PDAMP", "PVISC", "PBUSH",
    "FORCE", "MOMENT", "GRAV", "PLOAD1", "SPCD", "GRID", "GRDSET", "MAT1", "CORD2R", "CORD2C", "CORD2S", "CORD1R",
    "CORD1C", "CORD1S", "SPC", "SPC1", "SPCADD", "LOAD", "MPC", "MPCADD", "SUPORT", "SUPORT1", "CMASS1", "CMASS2",
    "PMASS"}
PLATE_CARDS = {"CQUAD4", "CTRIA3", "CQUADR", "CTRIAR", "PSHELL", "PCOMP", "PCOMPG", "MAT2", "MAT8"}
REDUCTION_CARDS = {"ASET", "ASET1", "OMIT", "OMIT1"}
TABLE_SPRING_CARDS = {"CBUSH1D", "PBUSH1D", "PBUSHT", "PELAST", "TABLED1"}

PLATE = """SOL 103
CEND
BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,1.,1.,0.
GRID,4,,0.,1.,0.
CBAR,10,1,1,2,0.,0.,1.
PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8
MAT1,1,7.e10,,0.3,2700.
CQUAD4,60,2,1,2,3,4
PSHELL,2,1,0.001
ENDDATA
"""


def test_each_card_is_read_by_one_family_and_the_set_is_unchanged():
    names = [card for family in _registry.FAMILIES for card in family.cards]
    names += list(_registry.DECK_CARDS) + list(_registry.CASE_CARDS)
    assert len(names) == len(set(names)), "a card is claimed by two families"
    assert _registry.READ_CARDS == READ_BEFORE | PLATE_CARDS | REDUCTION_CARDS | TABLE_SPRING_CARDS
    assert [f.name for f in _registry.FAMILIES] == ["materials", "beams", "rods", "plates", "masses", "springs",
                                                    "rigid", "reduction"]


def test_a_new_family_plugs_in_through_the_registry(tmp_path, monkeypatch):
    path = tmp_path / "plate.bdf"
    path.write_text(PLATE)
    # the registry as it was before the plate family: plates unsupported
    before = tuple(f for f in _registry.FAMILIES if f.name != "plates")
    monkeypatch.setattr(_read, "FAMILIES", before)
    monkeypatch.setattr(_read, "READ_CARDS", READ_BEFORE)
    with pytest.raises(UnsupportedCardsError) as err:
        fg.io.read_bdf(path)
    assert set(err.value.unsupported) == {"CQUAD4", "PSHELL"}
    seen = []

    def read_plates(deck: Deck, model, log, parts: Parts) -> Parts:
        # The family sees the parsed deck (cards with their lines), the model so far and earlier parts.
        seen.append((sorted(deck.bdf.elements[60].nodes), deck.at("CQUAD4", 60), sorted(parts.materials),
                     model.n_beams))
        log.note("plates read by a test family")
        return Parts()

    plates = Family("plates", ("CQUAD4", "PSHELL"), read_plates, needs_property=("CQUAD4",))
    monkeypatch.setattr(_read, "FAMILIES", before + (plates,))
    monkeypatch.setattr(_read, "READ_CARDS", READ_BEFORE | set(plates.cards))
    with pytest.warns(UserWarning, match="plates read by a test family"):
        deck = fg.io.read_bdf(path)
    assert seen == [([1, 2, 3, 4], f"{path}:11: CQUAD4 60", [1], 1)]
    assert deck.unsupported == {} and deck.model.n_beams == 1


def test_the_deck_and_parts_are_plain_frozen_data():
    assert dataclasses.is_dataclass(Deck) and Deck.__dataclass_params__.frozen
    a = Parts(mass_sources=(("CONM2", 1),), element_ids={1: 1})
    b = Parts(mass_sources=(("CONM2", 2),), element_ids={2: 2})
    merged = a.merged(b)
    assert merged.mass_sources == (("CONM2", 1), ("CONM2", 2)) and merged.element_ids == {1: 1, 2: 2}
    assert a.mass_sources == (("CONM2", 1),)  # merging leaves both unchanged
