"""A deck's subcases take their own LABEL as configuration name; names stay unique; the old
'subcase_<id>' still answers (with a DeprecationWarning), also as a project's `from`."""

import warnings

import pytest

import flexgvt as fg
from flexgvt.io.nastran._subcases import subcase_names

CASE_CONTROL = """SOL 103
CEND
LABEL = WHOLE DECK
METHOD = 1
SUBCASE 1
  LABEL = Hang on cords
SUBCASE 2
  SUBTITLE = inherits the deck's label
SUBCASE 3
  LABEL = twin
SUBCASE 4
  LABEL = twin
SUBCASE 5
  LABEL = subcase_2
BEGIN BULK
"""


def test_names_from_own_labels_unique_with_fallback():
    labels = {1: "Hang on cords", 2: "WHOLE DECK", 3: "twin", 4: "twin", 5: "subcase_2", 6: ""}
    assert subcase_names(labels, inherited="WHOLE DECK") == {
        1: "Hang on cords", 2: "subcase_2", 3: "subcase_3", 4: "subcase_4", 5: "subcase_5", 6: "subcase_6"}


def test_deck_subcases_named_by_label(tmp_path):
    case = fg.cases.cantilever_strip(n_elements=6)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        written = fg.io.write_bdf(case.model, tmp_path / "w.bdf", configurations=[case.configurations["unloaded"]])
    bulk = written.read_text().split("BEGIN BULK", 1)[1]
    (tmp_path / "d.bdf").write_text(CASE_CONTROL + bulk.lstrip("\n"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        deck = fg.io.read_bdf(tmp_path / "d.bdf")
    assert list(deck.configurations) == ["Hang on cords", "subcase_2", "subcase_3", "subcase_4", "subcase_5"]
    assert deck.subcases["Hang on cords"] == 1 and deck.configurations["Hang on cords"].name == "Hang on cords"
    with pytest.warns(DeprecationWarning, match="'subcase_1' is now named after its subcase's LABEL: 'Hang on cords'"):
        old = deck.configurations["subcase_1"]
    assert old is deck.configurations["Hang on cords"] and "subcase_1" in deck.configurations
    assert deck.configurations.get("subcase_9") is None
    # A project naming the old 'subcase_1' still loads it.
    (tmp_path / "project.toml").write_text('[model]\nbdf = "d.bdf"\n[[configurations]]\nname = "hang"\n'
                                           'from = "subcase_1"\nrole = "check"\n[prediction]\nfree_free = false\n')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        project = fg.workflow.load_project(tmp_path / "project.toml")
    assert project.configurations["hang"].fixed == deck.configurations["Hang on cords"].fixed
