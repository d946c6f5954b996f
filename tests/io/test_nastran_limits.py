"""Bounds on what a deck may hold (io/nastran/_limits.py): expansions refused on the raw lines
before pyNastran expands them, ids in Nastran's range, real fields finite and bounded, section
properties bounded. Each refusal names the file line, the card and the field."""

import time
from pathlib import Path

import pytest

import flexgvt as fg
from flexgvt.errors import FileFormatError, ModelError
from flexgvt.io.nastran._limits import MAX_EXPANDED_IDS, ExpansionBudget

HEAD = "SOL 103\nCEND\nSPC = 1\nBEGIN BULK\n"
BEAM = """GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
CBAR,10,1,1,2,0.,0.,1.
PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8
MAT1,1,7.e10,,0.3,2700.
SPC1,1,123456,1
"""


def deck(tmp_path, body, head=HEAD, name="deck.bdf"):
    path = tmp_path / name
    path.write_text(head + body + "ENDDATA\n")
    return path


def scan(text: str) -> ExpansionBudget:
    budget = ExpansionBudget()
    budget.scan(Path("deck.bdf"), text.splitlines(keepends=True))
    return budget


def test_thru_ranges_are_counted_in_every_format():
    assert scan("BEGIN BULK\nSET1,1,1,THRU,10\n").ids == 10
    assert scan("BEGIN BULK\nSPC1    1       123456  1       THRU    1000\n").ids == 1000  # small field
    assert scan("BEGIN BULK\nSET1    7       5       6       7       8       9       10      THRU\n"
                "+       2000\n").ids == 1991  # the range's end on the continuation line
    assert scan("BEGIN BULK\nSET1,1,1,THRU,1000,BY,10\n").ids == 100
    assert scan("CEND\nSET 5 = 1 THRU 100, 200 THRU 299\nBEGIN BULK\n").ids == 200  # case control


def test_a_huge_range_is_refused_in_the_line_scan(tmp_path):
    path = deck(tmp_path, BEAM + "SET1,1001,1,THRU,2147483648\n")
    t0 = time.perf_counter()
    with pytest.raises(FileFormatError, match=r"deck.bdf:11: SET1 1 THRU 2147483648 expands to 2,147,483,648 ids"):
        fg.io.read_bdf(path)
    assert time.perf_counter() - t0 < 2.0


def test_the_limit_is_on_the_whole_deck(tmp_path):
    half = MAX_EXPANDED_IDS // 2 + 1
    with pytest.raises(FileFormatError, match=r"deck.bdf:3: SPOINT 1 THRU .* past the 10,000,000 ids"):
        scan(f"BEGIN BULK\nSET1,1,1,THRU,{half}\nSPOINT,1,THRU,{half}\n")
    with pytest.raises(FileFormatError, match="case control SET 1 THRU 20000000"):
        fg.io.read_bdf(deck(tmp_path, BEAM, head="SOL 103\nCEND\nSET 5 = 1 THRU 20000000\nSPC = 1\nBEGIN BULK\n"))


def test_card_replication_is_bounded(tmp_path):
    with pytest.raises(FileFormatError, match=r"deck.bdf:11: replication =\(1000000\) .* more than the 100,000"):
        fg.io.read_bdf(deck(tmp_path, BEAM + "=(1000000),*1,=,*1.,==\n"))


def test_ids_outside_nastrans_range(tmp_path):
    with pytest.raises(ModelError, match="deck.bdf:7: CBAR 100000000: element id 100000000 is outside Nastran's "
                                         "range 1 to 99999999"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("CBAR,10,", "CBAR,100000000,")))


def test_real_fields_finite_and_bounded(tmp_path):
    with pytest.raises(ModelError, match=r"deck.bdf:9: MAT1 1: field 3 \(E\) = 1e\+31 exceeds 1e\+30"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("7.e10", "1.e31")))
    with pytest.raises(ModelError, match=r"deck.bdf:6: GRID 2: basic coordinates .* more than 1e\+06 m"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("GRID,2,,1.,", "GRID,2,,1.e7,")))


def test_section_properties_bounded(tmp_path):
    tube = "PBARL,1,1,,TUBE\n,{},0.01\n"
    with pytest.raises(ModelError, match=r"deck.bdf:8: PBARL 1: section properties .*Iy = 7.85e\+79"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8", tube.format("1.e20"))))
    with pytest.raises(ModelError, match=r"PBAR 1: section moments .* differ by more than a factor 1e\+12"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("1.e-8,2.e-8,1.e-8", "1.e-8,2.e-8,1.e5")))
    assert fg.io.read_bdf(deck(tmp_path, BEAM.replace("1.e-8,2.e-8,1.e-8", "1.e-8,2.e-8,1.e3"))).model.n_beams == 1


def test_orientation_and_end_grids(tmp_path):
    with pytest.raises(ModelError, match=r"deck.bdf:7: CBAR 10: orientation G0 = 0 .* \(0.0, not 0\)"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("CBAR,10,1,1,2,0.,0.,1.", "CBAR,10,1,1,2,0,0.,1.")))
    with pytest.raises(ModelError, match=r"deck.bdf:7: CBAR 10 has GA/GB = \[0, 2\]"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("CBAR,10,1,1,2,", "CBAR,10,1,0,2,")))


def test_grav_in_an_undefined_system_and_nu_of_minus_one(tmp_path):
    with pytest.raises(ModelError, match="GRAV 4 refers to coordinate system 9, which is not defined"):
        fg.io.read_bdf(deck(tmp_path, BEAM + "GRAV,4,9,9.81,0.,0.,-1.\n",
                            head="SOL 103\nCEND\nSPC = 1\nLOAD = 4\nBEGIN BULK\n"))
    got = fg.io.read_bdf(deck(tmp_path, BEAM.replace("MAT1,1,7.e10,,0.3,", "MAT1,1,7.e10,2.6e10,-1.,")))
    assert got.materials[1].shear_modulus == pytest.approx(2.6e10)


def test_a_malformed_include_is_refused_before_pynastran_dumps_the_deck(tmp_path, monkeypatch):
    """An INCLUDE with its closing quote gone (fuzzed beam_modes.dat) made pyNastran write
    ./pyNastran_crash.bdf into the user's working directory and raise an IndexError."""
    monkeypatch.chdir(tmp_path)
    path = deck(tmp_path, BEAM, head="SOL 103\nCEND\nSPC = 1\nBEGIN BULK\nINCLUDE 'other.blk\n")
    with pytest.raises(FileFormatError, match=r"deck.bdf:5: \"INCLUDE 'other.blk\" is not an INCLUDE statement"):
        fg.io.read_bdf(path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.bdf"]


def test_eigrl_nd_and_point_and_an_empty_dmig(tmp_path):
    """Fuzzed decks: EIGRL ND = -99999999 reached the eigensolver (ValueError 'k must be greater than
    0'); a DMIG header without columns raised a ValueError while classifying it."""
    head = "SOL 103\nCEND\nSPC = 1\nMETHOD = 9\nBEGIN BULK\n"
    with pytest.raises(ModelError, match="EIGRL 9: ND = -99999999; give the number of modes"):
        fg.io.read_bdf(deck(tmp_path, BEAM + "EIGRL,9,,,-99999999\n", head=head))
    got = fg.io.read_bdf(deck(tmp_path, BEAM + "DMIG, STIFF, 0, 6, 1, 0\n"))
    assert got.model.n_beams == 1


def test_a_pynastran_error_whose_message_fails_still_names_the_card(tmp_path):
    """A LOAD with a load set id of 0 (fuzzed all_cards.bdf): pyNastran's AssertionError message
    prints the card, which raised an AttributeError while the error was being reported."""
    path = deck(tmp_path, BEAM + "LOAD     2      1.      1.             0\n")
    with pytest.raises(FileFormatError, match=r"deck.bdf:11: cannot read the deck in LOAD 2: pyNastran refused the "
                                              r"card \(AssertionError\); check its fields"):
        fg.io.read_bdf(path)


def test_enforced_motion_bounded(tmp_path):
    """An SPC enforcing -99999999 on a 10-long beam (fuzzed beam_modes.dat) kept the static solver
    stepping for ever (10 sizes: 400 steps, 100 sizes: 3,700)."""
    with pytest.raises(ModelError, match=r"deck.bdf:10: SPC 1: enforced displacement -99999 on node 1 component 1 is "
                                         r"more than 10 times the structure's size \(1 in deck units\)"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("SPC1,1,123456,1", "SPC,1,1,1,-99999.\nSPC1,1,23456,1")))
    with pytest.raises(ModelError, match="enforced rotation 7 rad on node 1 component 4 is more than one turn"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("SPC1,1,123456,1", "SPC,1,1,4,7.\nSPC1,1,12356,1")))
