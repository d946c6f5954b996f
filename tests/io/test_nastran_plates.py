"""The plate family: CQUAD4/CTRIA3/CQUADR/CTRIAR, PSHELL, PCOMP/PCOMPG, MAT2, MAT8 read into shell
groups, written back, and their errors."""

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.io.nastran import UnsupportedCardsError
from flexgvt.model import AnisotropicMaterial, Laminate, Material, OrthotropicMaterial, ShellProperty
from nastran_helpers import comparable as _values
from nastran_helpers import shell_data

DATA = Path(__file__).parents[1] / "data" / "bdf"
MM = 1e-3  # m per mm; mm-N-t-s: stress MPa = 1e6 Pa, density t/mm^3 = 1e12 kg/m^3


def read(path, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path, **kw)


@pytest.fixture(scope="module")
def plates():
    return read(DATA / "plates.bdf", units="mm-N-t-s")


def group(deck, name):
    return deck.model.shells[deck.model.shell_group(name)]


def test_pshell_mat1_corner_thickness_theta_zoffs(plates):
    g = group(plates, "PSHELL_1_CQUAD4")
    assert plates.shells["PSHELL_1_CQUAD4"].eids == (11, 12)
    assert [plates.element_ids[e] for e in (11, 12)] == g.ids.tolist()
    assert g.nodes.tolist() == [[1, 2, 3, 4], [2, 5, 6, 3]]
    assert g.theta.tolist() == [30.0, 0.0] and g.material_axis is None
    assert g.zoffs == pytest.approx([0.5 * MM, 0.0])
    # CQUAD4 11: TFLAG 0, T2 blank -> T; CQUAD4 12: TFLAG 1 -> factors of T = 1.5 mm
    assert g.corner_thickness == pytest.approx(np.array([[1.2, 1.5, 1.3, 1.4], [1.35, 1.5, 1.65, 1.8]]) * MM)
    mat1 = Material("MAT1_1", E=70e9, rho=2700.0, nu=0.33)
    assert g.property.name == "PSHELL_1"
    assert _values(g.property) == _values(ShellProperty("", 1.5 * MM, mat1, mat1, 0.8, mat1, 0.9, None, 2.0, -0.8 * MM,
                                                        0.8 * MM))
    assert g.mass == "consistent"  # PARAM,COUPMASS,1


def test_mat2_and_mcid(plates):
    g = group(plates, "PSHELL_2_CTRIA3_MCID")
    m2 = _values(AnisotropicMaterial("MAT2_2", 80e9, 25e9, 0.0, 80e9, 0.0, 27e9, rho=2600.0))
    assert _values(g.property.membrane) == m2 and g.property.bending is g.property.membrane
    assert g.property.shear is g.property.membrane
    assert g.property.z1 is None and g.property.thickness == pytest.approx(1.0 * MM)
    # MCID 7: CORD2R with x along (1, 1, 0)
    np.testing.assert_allclose(g.material_axis, [[2**-0.5, 2**-0.5, 0.0]], atol=1e-15)
    assert g.theta.tolist() == [0.0]
    assert g.zoffs == pytest.approx([-0.25 * MM])


def test_pcomp_sym_and_pcompg(plates):
    lam = group(plates, "PCOMP_3_CQUAD4").property  # read from the CQUADR
    assert isinstance(lam, Laminate) and lam.lam == "SYM" and lam.z0 == pytest.approx(-1.0 * MM)
    assert lam.nsm == pytest.approx(1.0) and lam.thickness == pytest.approx(1.2 * MM)
    mat8 = OrthotropicMaterial("MAT8_10", 150e9, 9e9, 0.3, 5e9, 4e9, 3.5e9, rho=1600.0)
    assert _values([(p.material, p.thickness, p.theta, p.sout) for p in lam.plies]) == _values([
        (mat8, 0.2 * MM, 0.0, True), (mat8, 0.3 * MM, 45.0, False),
        (Material("MAT1_1", E=70e9, rho=2700.0, nu=0.33), 0.1 * MM, 90.0, False)])
    lamg = group(plates, "PCOMPG_4_CTRIA3").property
    assert [p.ply_id for p in lamg.plies] == [101, 102] and lamg.z0 is None
    assert isinstance(lamg.plies[1].material, AnisotropicMaterial) and lamg.plies[1].theta == 30.0


def test_notes_options_and_quad_r(plates):
    assert plates.options == {"K6ROT": 100.0}
    notes = " ".join(plates.notes)
    assert "CQUADR/CTRIAR read as CQUAD4/CTRIA3" in notes and "K6ROT=100.0" in notes and "COUPMASS" in notes
    assert "have no element" not in notes  # shell nodes are connected (no AUTOSPC)
    assert plates.shells["PSHELL_1_CTRIA3"].eids == (15,)  # the CTRIAR
    assert plates.model.n_shells == 6 and plates.unsupported == {}


def test_mat8_blank_transverse_shear_stays_blank(tmp_path):
    text = (DATA / "plates.bdf").read_text().replace("MAT8,10,150000.,9000.,0.3,5000.,4000.,3500.,1.6e-9",
                                                     "MAT8,10,150000.,9000.,0.3,5000.,,,1.6e-9")
    (tmp_path / "p.bdf").write_text(text)
    ply = group(read(tmp_path / "p.bdf", units="mm-N-t-s"), "PCOMP_3_CQUAD4").property.plies[0]
    assert ply.material.G1z is None and ply.material.G2z is None


def test_goland_wing_box_real_deck():
    """The Goland wing box of pyNastran's models/bugs/msc_dscmcol (MSC Nastran 2018, SI): membrane
    PSHELLs (MID1 only) with CROD spar caps and CONM2 masses."""
    deck = read(DATA / "pynastran" / "goland" / "goland_final_test.bdf")
    m = deck.model
    assert (m.n_nodes, m.n_shells, m.n_beams, len(m.masses)) == (66, 92, 137, 66)
    assert deck.unsupported == {}
    pids = {deck.shells[g.name].pid: g for g in m.shells}
    assert sorted(pids) == [1, 2, 3, 4, 9, 10]
    assert pids[1].property.thickness == pytest.approx(0.0155) and pids[2].property.thickness == pytest.approx(6e-4)
    assert all(g.property.bending is None and g.mass == "lumped" for g in m.shells)
    assert pids[1].property.membrane == Material("MAT1_1", E=1.4976e9, rho=1e-4, nu=0.3333333)


def test_round_trip_keeps_the_shell_data(plates, tmp_path):
    path = fg.io.write_bdf(plates.model, tmp_path / "out.bdf", units="mm-N-t-s")
    back = read(path, units="mm-N-t-s")
    assert shell_data(back.model) == shell_data(plates.model)
    assert "CQUAD4" in path.read_text() and "PCOMPG" in path.read_text() and "MAT8" in path.read_text()


def test_round_trip_goland_with_rods(tmp_path):
    deck = read(DATA / "pynastran" / "goland" / "goland_final_test.bdf")
    back = read(fg.io.write_bdf(deck.model, tmp_path / "g.bdf"))
    assert shell_data(back.model) == shell_data(deck.model) and back.model.n_beams == deck.model.n_beams


def test_template_writes_changed_shell_values(plates, tmp_path):
    fg.io.write_bdf(plates.model, tmp_path / "same.bdf", template=plates)
    assert shell_data(read(tmp_path / "same.bdf", units="mm-N-t-s").model) == shell_data(plates.model)
    changed = plates.model.copy()
    # PSHELL 1 is shared by the CQUAD4 and the CTRIAR group: the changed quads take a new PSHELL
    k = changed.shell_group("PSHELL_1_CQUAD4")
    changed.set_shell_group(k, dataclasses.replace(changed.shells[k].property, thickness=0.002, nsm=3.0))
    # MAT2 2 is shared with a PCOMPG ply: the MID1 of PSHELL 2 becomes a new MAT2
    k = changed.shell_group("PSHELL_2_CTRIA3_MCID")
    prop = changed.shells[k].property
    changed.set_shell_group(k, dataclasses.replace(prop, membrane=dataclasses.replace(prop.membrane, G11=90e9)))
    with pytest.warns(UserWarning, match="PSHELL 1 is shared by shell groups that now differ"):
        path = fg.io.write_bdf(changed, tmp_path / "changed.bdf", template=plates)
    back = read(path, units="mm-N-t-s")
    assert sorted(shell_data(back.model)) == sorted(shell_data(changed))  # groups come in property id order
    assert back.shells["PSHELL_1_CTRIA3"].pid == 1 and "PSHELL_1_CQUAD4" not in back.shells
    assert back.shells["PSHELL_1_CTRIA3"].eids == (15,) and back.shells["PSHELL_5_CQUAD4"].eids == (11, 12)
    assert back.model.shells[back.model.shell_group("PSHELL_5_CQUAD4")].property.thickness == pytest.approx(0.002)
    # the template's own cards (PARAMs, CQUADR) are kept; its CTRIAR is written as CTRIA3
    assert back.notes[1:] == plates.notes[1:] and back.notes[0].startswith("CQUADR read as CQUAD4 ")


def test_template_refuses_a_changed_mesh(plates):
    changed = plates.model.copy()
    changed.set_shell_group(0, mass="lumped")
    with pytest.raises(ModelError, match="shell group 'PSHELL_1_CQUAD4': mass 'lumped' differs"):
        fg.io.write_bdf(changed, Path("unused.bdf"), template=plates)


BASE = """BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,1.,1.,0.
GRID,4,,0.,1.,0.
MAT1,1,7.e10,,0.3,2700.
MAT8,8,1.5e11,9.e9,0.3,5.e9,,,1600.
"""


@pytest.mark.parametrize("cards, error, match", [
    ("CQUAD4,7,5,1,2,3,4\n", ModelError, r"deck.bdf:8: CQUAD4 7 refers to property 5, which is not defined"),
    ("CQUAD4,7,5,1,2,3,4\nPCOMP,5\n,8,0.,0.\n", ModelError, r"deck.bdf:9: PCOMP 5: ply 1 has thickness 0.0"),
    ("CQUAD4,7,5,1,2,3,4\nPSHELL,5,1,0.\n", ModelError, r"deck.bdf:9: PSHELL 5: T = 0.0 must be positive"),
    ("CQUAD4,7,5,1,2,3,4\nPSHELL,5,8,0.01\n", ModelError, r"deck.bdf:9: PSHELL 5 MID1 refers to MAT8 8; this field"),
    ("CQUAD4,7,5,1,2,3,4\nPSHELL,5,9,0.01\n", ModelError, r"PSHELL 5 MID1 refers to material 9, which is not def"),
    ("CQUAD4,7,5,1,2,4,3\nPSHELL,5,1,0.01\n", ModelError, r"deck.bdf:8: CQUAD4 7: .*zero area or crossing edges"),
    ("CTRIA3,7,5,1,2,3,,,\n,,,0.01,-1.,0.01\nPSHELL,5,1,0.01\n", ModelError,
     r"deck.bdf:8: CTRIA3 7: .*corner_thickness of element 1 \(nodes \[1, 2, 3\]\) is \[0.01, -1.0, 0.01\]; each "
     "must be >= 0 and at least one positive"),
    ("CQUAD8,7,5,1,2,3,4\nCHEXA,8,5,1,2,3,4,1,2\n,3,4\nCSHEAR,9,5,1,2,3,4\nPSHELL,5,1,0.01\n",
     UnsupportedCardsError, r"CHEXA: 8; CQUAD8: 7; CSHEAR: 9 \(CHEXA: solids: .*CQUAD8: 8-node quads: remesh with "
                            r"CQUAD4; CSHEAR: shear panels"),
])
def test_malformed_plate_cards(tmp_path, cards, error, match):
    path = tmp_path / "deck.bdf"
    path.write_text(BASE + cards + "ENDDATA\n")
    with pytest.raises(error, match=match):
        read(path)


def test_shell_group_name_addresses_the_property(plates):
    k = plates.model.shell_group("PCOMPG_4_CTRIA3")
    assert plates.shells["PCOMPG_4_CTRIA3"].property_card == "PCOMPG" and plates.model.shells[k].ids.size == 1


def test_template_shells_keep_their_mat1_when_the_rods_change_it(tmp_path):
    """Goland: CROD and PSHELL share MAT1 1; a stiffer rod material must not reach the skins."""
    deck = read(DATA / "pynastran" / "goland" / "goland_final_test.bdf")
    changed = deck.model.copy()
    for k, g in enumerate(changed.beams):
        changed.set_beam_group(k, material=dataclasses.replace(g.material, E=2 * g.material.E))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        back = read(fg.io.write_bdf(changed, tmp_path / "g.bdf", template=deck))
    assert sorted(shell_data(back.model)) == sorted(shell_data(deck.model))
    assert {g.material.E for g in back.model.beams} == {2 * 1.4976e9}


MEMBRANES = """SOL 103
CEND
BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,1.,1.,0.
GRID,4,,0.,1.,0.
GRID,5,,0.,1.,1.
GRID,6,,0.,0.,1.
GRID,7,,2.,0.,0.
GRID,8,,3.,1.,0.
GRID,9,,3.,1.,1.
GRID,10,,2.,0.,1.
GRID,11,,5.,0.,0.
GRID,12,,6.,0.,0.
CQUAD4,1,1,1,2,3,4
CQUAD4,2,1,1,4,5,6
CQUAD4,3,1,7,8,9,10
CTRIA3,4,2,11,12,8
PSHELL,1,1,0.001
PSHELL,2,1,0.001,1
MAT1,1,7.e10,,0.3,2700.
ENDDATA
"""


def test_membrane_nodes_keep_their_drilling_rotations(tmp_path):
    """A membrane (PSHELL without MID2) stiffens only the rotation about its normal (flexgvt's drilling
    DOF): the other rotations are fixed, in basic axes; at an edge of two membranes (normals z and x)
    only the rotation about y; on a membrane whose in-plane axes are not basic, all three; a node of a
    bending plate keeps all three free."""
    path = tmp_path / "membranes.bdf"
    path.write_text(MEMBRANES)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        deck = fg.io.read_bdf(path)
    fixed = next(iter(deck.configurations.values())).fixed
    assert fixed == {1: "5", 4: "5", 2: "45", 3: "45", 5: "56", 6: "56", 7: "456", 9: "456", 10: "456"}
    assert "the drilling rotation about a membrane's normal stays free" in str(caught[0].message)
