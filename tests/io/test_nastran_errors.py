"""Malformed decks give one clear error: what, where (file:line, card id) and what to do."""


import pytest

import flexgvt as fg
from flexgvt.errors import FileFormatError, ModelError
from flexgvt.io.nastran import UnsupportedCardsError

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


def test_bad_field_names_file_line_and_card(tmp_path):
    path = deck(tmp_path, BEAM.replace("GRID,2,,1.,", "GRID,2,,1.x,"))
    with pytest.raises(FileFormatError) as err:
        fg.io.read_bdf(path)
    msg = str(err.value)
    assert f"{path}:6" in msg and "GRID 2" in msg and "1.X" in msg.upper()


def test_missing_node_and_material_are_listed_together(tmp_path):
    path = deck(tmp_path, BEAM.replace("CBAR,10,1,1,2,", "CBAR,10,1,1,3,").replace("PBAR,1,1,", "PBAR,1,7,"))
    with pytest.raises(ModelError) as err:
        fg.io.read_bdf(path)
    msg = str(err.value)
    assert "CBAR 10 refers to node 3" in msg and "PBAR 1 refers to material 7" in msg
    assert f"{path}:7" in msg  # the CBAR line


def test_missing_coordinate_system(tmp_path):
    with pytest.raises(ModelError, match="GRID 2 uses CP=9 but coordinate system 9 is not defined"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("GRID,2,,1.", "GRID,2,9,1.")))


def test_duplicate_ids_name_both_lines(tmp_path):
    path = deck(tmp_path, BEAM + "GRID,2,,5.,0.,0.\nCBAR,10,1,1,2,0.,1.,0.\n")
    with pytest.raises(ModelError) as err:
        fg.io.read_bdf(path)
    msg = str(err.value)
    assert "node id 2 is defined 2 times" in msg and f"{path}:6" in msg and f"{path}:11" in msg
    assert "element id 10" in msg


def test_missing_spc_and_load_sets(tmp_path):
    with pytest.raises(ModelError, match="SPC = 5 but no SPC, SPC1 or SPCADD"):
        fg.io.read_bdf(deck(tmp_path, BEAM, head="CEND\nSPC = 5\nBEGIN BULK\n"))
    with pytest.raises(ModelError, match="LOAD = 8 but no LOAD, FORCE"):
        fg.io.read_bdf(deck(tmp_path, BEAM, head="CEND\nSPC = 1\nLOAD = 8\nBEGIN BULK\n"))


def test_unknown_and_unsupported_cards_in_one_error(tmp_path):
    body = BEAM + "RBE3,50,,2,123,1.,1,1\nFOOBAR,1,2\nGRID,3,,1.,1.,0.\nGRID,4,,0.,1.,0.\n" \
        "CQUAD8,60,2,1,2,3,4\nPSHELL,2,1,0.001\n"
    with pytest.raises(UnsupportedCardsError) as err:
        fg.io.read_bdf(deck(tmp_path, body))
    assert set(err.value.unsupported) == {"RBE3 (independent components other than 123)", "FOOBAR", "CQUAD8"}
    assert "unsupported='warn'" in str(err.value)
    assert "CQUAD8: 60" in str(err.value) and "CQUAD8: 8-node quads: remesh with CQUAD4" in str(err.value)
    with pytest.warns(UserWarning, match=r"RBE3 \(independent components other than 123\): 50"):
        got = fg.io.read_bdf(deck(tmp_path, body), unsupported="warn")
    assert got.model.n_beams == 1


def test_card_features_without_counterpart(tmp_path):
    body = BEAM.replace("CBAR,10,1,1,2,0.,0.,1.", "CBAR,10,1,1,2,0.,0.,1.,GOO\n,,,0.,0.,0.1") + \
        "RBE2,20,1,1235,2\nCELAS2,30,1.,1,1,2,2\n"
    with pytest.raises(UnsupportedCardsError) as err:
        fg.io.read_bdf(deck(tmp_path, body))
    keys = set(err.value.unsupported)
    assert keys == {"CBAR (offsets in the element system, OFFT GOO)", "RBE2 (some of the rotations 456 only)",
                    "CELAS2 (components along different directions)"}


def test_skew_displacement_system_with_partial_spc(tmp_path):
    skew = "CORD2R,3,0,0.,0.,0.,0.,0.,1.\n,1.,1.,0.\n"
    body = skew + BEAM.replace("GRID,2,,1.,0.,0.", "GRID,2,,1.,0.,0.,3") + "SPC1,1,1,2\n"
    with pytest.raises(ModelError, match="node 2 has CD=3 .* do not line up with basic axes"):
        fg.io.read_bdf(deck(tmp_path, body))
    # all three translations in a skew CD are all three in basic
    got = fg.io.read_bdf(deck(tmp_path, skew + BEAM.replace("GRID,2,,1.,0.,0.", "GRID,2,,1.,0.,0.,3")
                              + "SPC1,1,123,2\n"))
    assert got.configurations["deck"].fixed == {1: "123456", 2: "123"}


def test_orientation_parallel_to_the_axis(tmp_path):
    with pytest.raises(ModelError, match="CBAR 10: orientation vector .* parallel"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("CBAR,10,1,1,2,0.,0.,1.", "CBAR,10,1,1,2,2.,0.,0.")))


def test_bad_section_and_material_values(tmp_path):
    with pytest.raises(ModelError, match="PBAR 1: A=0.0"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8",
                                                   "PBAR,1,1,0.,1.e-8,2.e-8,1.e-8")))
    with pytest.raises(ModelError, match="MAT1 1: G and NU are both blank"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("MAT1,1,7.e10,,0.3,2700.", "MAT1,1,7.e10,,,2700.")))
    with pytest.raises(FileFormatError, match="deck.bdf:8: cannot read the deck in PBARL 1: .*dim4"):
        fg.io.read_bdf(deck(tmp_path, BEAM.replace("PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8",
                                                   "PBARL,1,1,,BOX\n,0.1,0.1,0.01")))


def test_negative_or_nan_shear_factor_names_the_property(tmp_path):
    """PBAR K1 = -1 or nan (fuzzed ha144ds) raised a ModelError from the section without the deck's name."""
    for k in ("-1.", "nan"):
        path = deck(tmp_path, BEAM.replace("PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8", f"PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8\n"
                                           f",,,,,,,,\n,{k},0."))
        expected = (f"deck.bdf:8: PBAR 1: K1={k.rstrip('.')}.*shear factors must be >= 0" if k != "nan" else
                    r"deck.bdf:8: PBAR 1: field 2 of continuation 2 \(K1\) = nan is not a finite number")
        with pytest.raises(ModelError, match=expected):
            fg.io.read_bdf(path)


def test_repeated_begin_bulk_is_ignored_with_a_note(tmp_path):
    """A deck pasted together with BEGIN BULK twice (pyNastran's ha144ds.bdf): pyNastran refused it
    ('expected BEGIN SUPER=1'); the second one is ignored and named in the notes."""
    path = deck(tmp_path, "\nBEGIN BULK\n" + BEAM)
    with pytest.warns(UserWarning, match="deck.bdf:6: BEGIN BULK repeated inside the bulk data: ignored"):
        got = fg.io.read_bdf(path)
    assert got.model.n_beams == 1 and got.configurations["deck"].fixed == {1: "123456"}


def test_empty_and_missing_files(tmp_path):
    with pytest.raises(FileFormatError, match="no such file"):
        fg.io.read_bdf(tmp_path / "nope.bdf")
    empty = tmp_path / "empty.bdf"
    empty.write_text("$ only a comment\n")
    with pytest.raises(FileFormatError, match="empty"):
        fg.io.read_bdf(empty)


def test_bulk_only_file_without_case_control(tmp_path):
    path = tmp_path / "wing.blk"
    path.write_text(BEAM + "FORCE,7,2,,10.,0.,0.,1.\n")
    got = fg.io.read_bdf(path)
    cfg = got.configurations["wing"]
    assert cfg.fixed == {1: "123456"} and cfg.forces[0].force == pytest.approx((0, 0, 10.0))


def test_missing_include_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # pyNastran would drop a crash file in the working folder
    path = deck(tmp_path, BEAM + "INCLUDE 'nowhere.inc'\n")
    with pytest.raises(FileFormatError, match=r"deck.bdf:11: INCLUDE file .*nowhere.inc does not exist"):
        fg.io.read_bdf(path)
    assert not (tmp_path / "pyNastran_crash.bdf").exists()
