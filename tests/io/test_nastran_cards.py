"""Every supported card: mapping to the model, and read -> write -> read round trips.

tests/data/bdf/all_cards.bdf holds one of each card; the expected values below are worked out
by hand from the Nastran Quick Reference Guide definitions.
"""

import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from nastran_helpers import assert_close, config_data, model_data, rebuild

import flexgvt as fg
from flexgvt.model import GeneralSection, Material, Model, RectangularSection

ALL = Path(__file__).parents[1] / "data" / "bdf" / "all_cards.bdf"


def read(path=ALL, cbar_torsional_inertia=True, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path, cbar_torsional_inertia=cbar_torsional_inertia, **kw)


@pytest.fixture(scope="module")
def deck():
    # Card mapping is checked on the physical sections (CBAR with rho*Ip, as a PBARL shape);
    # Nastran's CBAR mass convention (the default) is checked in test_nastran_real.py.
    return read()


def group(deck, name):
    return next(g for g in deck.model.beams if g.name == name)


def test_grids_in_rectangular_and_cylindrical_systems(deck):
    xyz = dict(zip(deck.model.node_ids.tolist(), deck.model.xyz))
    assert xyz[4] == pytest.approx([3.0, 0.0, 0.0])  # CP=1 (turned 90 deg): local (0, -3, 0)
    assert xyz[5] == pytest.approx([4.0, 0.0, 0.0])  # CP=2 cylindrical r=4, theta=0


def test_params_wtmass_and_coupmass(deck):
    assert deck.wtmass == 0.5 and deck.mass == "consistent"
    assert group(deck, "PBAR_10").material.rho == pytest.approx(2700 * 0.5)
    # COUPMASS: CBAR groups consistent, CBEAM groups with Nastran's lumped axial and torsional terms
    cards = {name: src.card for name, src in deck.beams.items()}
    assert all(g.mass == {"CBAR": "consistent", "CBEAM": "consistent-bending"}.get(cards[g.name], "consistent")
               and not g.rotary_inertia for g in deck.model.beams)
    assert {cards[g.name] for g in deck.model.beams} >= {"CBAR", "CBEAM"}


def test_pbar_axes_and_shear_factors(deck):
    g = group(deck, "PBAR_10")
    s = g.section
    assert (s.A, s.Iy, s.Iz, s.J) == (1e-4, 2e-8, 1e-8, 1.5e-8)  # Iy = I2, Iz = I1
    assert (s.Ay, s.Az) == pytest.approx((0.8e-4, 0.7e-4))  # K1*A along y (plane 1), K2*A
    assert g.orientation[0] == pytest.approx([0, -1, 0])  # Nastran z = x cross v = (1,0,0) x (0,0,1)


def test_pbar_product_of_inertia_goes_to_principal_axes(deck):
    g = group(deck, "PBAR_11")
    x = np.array([1.0, 0, 0])
    v = np.array([-1.0, 1, 0])  # from G0 = 8
    z_n = np.cross(x, v) / np.linalg.norm(np.cross(x, v))
    y_n = np.cross(z_n, x)
    zp = g.orientation[0] / np.linalg.norm(g.orientation[0])
    yp = np.cross(zp, x)
    # Rebuild the Nastran second moments from the principal ones: I = Iy' zp zp^T + Iz' yp yp^T
    Q = g.section.Iy * np.outer(zp, zp) + g.section.Iz * np.outer(yp, yp)
    assert y_n @ Q @ y_n == pytest.approx(4e-8)  # I1
    assert z_n @ Q @ z_n == pytest.approx(3e-8)  # I2
    assert y_n @ Q @ z_n == pytest.approx(1e-8)  # I12
    assert g.section.Ay is None and g.section.Az is None  # Nastran ignores K1, K2 when I12 != 0


def test_pbarl_shapes(deck):
    bar = group(deck, "PBARL_12")
    assert bar.section == RectangularSection(width=0.003, height=0.05)  # DIM2 along y, DIM1 along z
    assert bar.orientation[0] / np.linalg.norm(bar.orientation[0]) == pytest.approx([0, -2**-0.5, 2**-0.5])  # BGG
    tube = group(deck, "PBARL_13").section
    assert (tube.outer_radius, tube.inner_radius) == (0.02, 0.015)
    box = group(deck, "PBARL_14").section.properties()
    assert box["A"] == pytest.approx(0.1 * 0.06 - 0.092 * 0.05)
    assert box["Iz"] == pytest.approx((0.1 * 0.06**3 - 0.092 * 0.05**3) / 12)  # I1: depth DIM2 along y
    ell = group(deck, "PBARL_17")
    assert ell.section.Ay is None  # I12 != 0: principal axes, no shear factors
    assert group(deck, "PBARL_18").section.outer_radius == 0.01


def test_pbeam_default_shear_factor_and_nsm(deck):
    s = group(deck, "PBEAM_20").section
    assert (s.Ay, s.Az) == (s.A, s.A)  # PBEAM K1 = K2 = 1.0 by default
    nsm = [(m.node, m.mass) for m, src in zip(deck.model.masses, deck.mass_sources) if src == ("NSM:PBEAM", 20)]
    half = 0.5 * 0.5 * np.sqrt(2) * 0.5  # NSM * L / 2 * WTMASS
    assert nsm == [(2, pytest.approx(half)), (8, pytest.approx(half))]


def test_conm2_cid_offset_and_inertia_signs(deck):
    m = deck.model.masses[deck.mass_sources.index(("CONM2", 100))]
    T = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])  # columns: CID 1 axes in basic
    assert m.mass == pytest.approx(1.0)  # 2.0 * WTMASS
    assert m.offset == pytest.approx(T @ [0.1, 0.2, 0.3])
    J = np.array([[0.01, -0.002, -0.003], [-0.002, 0.02, -0.001], [-0.003, -0.001, 0.03]])  # I21 etc. enter negated
    assert m.inertia == pytest.approx(0.5 * T @ J @ T.T)
    m = deck.model.masses[deck.mass_sources.index(("CONM2", 101))]
    assert m.offset == pytest.approx([0.05, 0.0, 0.1])  # CID = -1: X is the centre in basic


def test_conm1_rigid_mass_matrix(deck):
    m = deck.model.masses[deck.mass_sources.index(("CONM1", 102))]
    assert m.mass == pytest.approx(1.0)
    assert m.offset == pytest.approx([0, 0.1, 0], abs=1e-12)
    assert m.inertia == pytest.approx(0.5 * np.diag([0.001, 0.002, 0.003]))


def test_springs_dampers_and_bushes(deck):
    by = {src: s for s, src in zip(deck.model.springs, deck.spring_sources)}
    celas1 = by[("CELAS1", 200)]
    assert (celas1.node_a, celas1.node_b) == (9, None) and celas1.stiffness[2] == 1e5
    celas2 = by[("CELAS2", 201)]  # node 6 has CD = 1: component 1 is basic y
    assert celas2.frame[:, 0] == pytest.approx([0, 1, 0]) and celas2.stiffness[0] == 2e4
    assert by[("CELAS2", 202)].stiffness[3] == 300.0 and by[("CELAS2", 202)].node_b == 16
    assert by[("CDAMP1", 210)].damping[2] == 5.0 and by[("CDAMP2", 211)].damping[1] == 0.3
    cvisc = by[("CVISC", 212)]
    assert cvisc.frame[:, 0] == pytest.approx(np.array([-1, 0, 0.5]) / np.linalg.norm([-1, 0, 0.5]))
    assert cvisc.damping[[0, 3]] == pytest.approx([10.0, 0.1])
    bush = by[("CBUSH", 220)]  # CID 3 = CORD1R on grids 1, 2, 8: z = basic x, x = basic y
    assert bush.frame == pytest.approx(np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0.0]]))
    assert bush.stiffness == pytest.approx([1e5, 2e5, 3e5, 10, 20, 30])
    assert bush.damping == pytest.approx([1, 2, 3, 0.1, 0.2, 0.3])
    assert by[("CBUSH", 221)].node_b is None


def test_rbe2_chain_merges(deck):
    links = [(link.independent, link.dependents, link.components) for link in deck.model.rigid_links]
    # RBE2 302 hangs on the chain's root; RBAR 304 (CNA = CMB = 123456) is a rigid link from GA to GB
    assert sorted(zip(links, deck.rigid_sources)) == [((2, (10, 11, 12), "123456"), (300, 301)),
                                                      ((2, (17,), "123"), (302,)), ((3, (19,), "123456"), (304,))]
    # The ball joint's rotations have no stiffness: fixed as AUTOSPC would, in every subcase.
    assert all(cfg.fixed[17] == "456" for cfg in deck.configurations.values())


def test_rbe3_reads_as_an_interpolation(deck):
    (ip,) = deck.model.interpolations
    assert (ip.reference, ip.nodes, ip.components) == (18, (3, 8, 13), "123456")
    assert ip.weights.tolist() == [1.0, 1.0, 2.5] and deck.interpolation_sources == [303]


def test_subcases_constraints_and_loads(deck):
    c1, c2 = deck.configurations["gravity"], deck.configurations["tip loads"]  # the subcases' LABELs
    # SPCADD 101 = SPC1 100 + SPC 100 + SPC1 102 (component 1 of CD 1 is basic y); GRID 9 PS = 6
    assert c1.fixed == {1: "123456", 6: "2", 9: "6", 16: "3", 17: "456"}
    assert c2.fixed == {1: "123456", 9: "6", 16: "3", 17: "456"}
    assert (c1.gravity, c1.g) == (2.0, 9.81) and c1.gravity_direction == pytest.approx((0, 0, -1))
    assert c2.gravity == 0.0
    loads = config_data(deck.model, c2)
    assert loads["loads"][9] == pytest.approx([0, 100, 0, 0, 0, 0], abs=1e-12)  # FORCE in cylindrical CID 2
    assert loads["loads"][16] == pytest.approx([0, 0, 0, 0, 0, 5])
    assert loads["distributed"][(3, 4)] == pytest.approx([0, 0, -25])  # 0.5 x PLOAD1 FZ FR -50
    assert loads["distributed"][(4, 5)] == pytest.approx([0, 10, 0])
    assert loads["distributed"][(5, 6)] == pytest.approx([0, 0, -5])
    assert deck.n_modes == {"gravity": 6, "tip loads": 6} and deck.subcases == {"gravity": 1, "tip loads": 2}


def test_template_round_trip_is_exact(deck, tmp_path):
    out = fg.io.write_bdf(deck.model, tmp_path / "same.bdf", template=deck)
    again = read(out)
    assert_close(model_data(deck.model), model_data(again.model), rtol=1e-12)
    for name in deck.configurations:
        assert_close(config_data(deck.model, deck.configurations[name]),
                     config_data(again.model, again.configurations[name]), rtol=1e-12)
    assert again.wtmass == 0.5 and again.mass == "consistent"


def test_template_writes_updated_values(deck, tmp_path):
    stiffer = replace(group(deck, "PBAR_10").material, E=7.7e10)
    changes = dict(
        material={"PBAR_10": stiffer},  # MAT1 1 is shared with 5 other groups: it must split
        section={"PBAR_11": GeneralSection(A=3e-4, Iy=5e-8, Iz=6e-8, J=7e-8, Ip=1.1e-7),
                 "PBARL_12": RectangularSection(width=0.004, height=0.05),  # still a BAR: DIMs written
                 "PBARL_14": GeneralSection(A=2e-3, Iy=2e-6, Iz=1e-6, J=2e-6, Ay=5e-4, Az=9e-4)},  # BOX -> PBAR
        mass={deck.mass_sources.index(("CONM2", 100)): 1.5, deck.mass_sources.index(("CONM1", 102)): 2.0},
        spring={deck.spring_sources.index(("CELAS1", 200)): 3.0, deck.spring_sources.index(("CBUSH", 220)): 2.0})
    updated = rebuild(deck.model, **changes)
    with pytest.warns(UserWarning, match="PBARL 14"):
        out = fg.io.write_bdf(updated, tmp_path / "updated.bdf", template=deck)
    again = read(out)
    expected = model_data(updated)
    got = model_data(again.model)
    assert_close(expected, got, rtol=1e-10)
    assert group(again, "PBAR_10").material.E == 7.7e10
    assert group(again, "PBARL_13").material.E == 7.0e10  # the other users of MAT1 1 keep it
    assert again.bdf.properties[14].type == "PBAR"
    assert again.bdf.properties[12].dim == [0.05, 0.004]
    # CBUSH 221 shared PBUSH 220 with CBUSH 220 and keeps the old values through a copied property
    by = dict(zip(again.spring_sources, again.model.springs))
    assert by[("CBUSH", 221)].stiffness[0] == 1e5 and by[("CBUSH", 220)].stiffness[0] == 2e5
    for name in deck.configurations:  # case control and loads untouched
        assert_close(config_data(deck.model, deck.configurations[name]),
                     config_data(again.model, again.configurations[name]), rtol=1e-12)


def test_template_rejects_a_different_mesh(deck, tmp_path):
    other = Model("other")
    other.add_nodes([[0, 0, 0], [1, 0, 0]])
    with pytest.raises(fg.errors.ModelError, match="node ids differ"):
        fg.io.write_bdf(other, tmp_path / "x.bdf", template=deck)


def test_compact_round_trip(deck, tmp_path):
    """A model written without template (CBAR/PBAR(L)/MAT1/CONM2/CELAS2/CDAMP2/CBUSH/RBE2 + SUBCASEs) reads back
    to the same model and configurations."""
    with pytest.warns(UserWarning) as record:
        out = fg.io.write_bdf(deck.model, tmp_path / "compact.bdf", configurations=deck.configurations.values())
    assert any("CBEAMs, whose coupled mass (COUPMASS) Nastran forms with the axial and torsional terms lumped"
               in str(w.message) for w in record)
    again = read(out)
    a, b = model_data(deck.model), model_data(again.model)
    for g in a["beams"]:  # compact decks keep sections in principal axes (PBAR I12 = 0), same numbers
        g["section"] = {k: v for k, v in g["section"].items()}
        if g["section"]["Ip"] > 0:  # the CBARs with rho*Ip (fixture option) are written as CBEAMs (noted)
            g["mass"] = "consistent-bending"
    assert_close(a, b, rtol=1e-10)
    assert list(again.configurations) == ["gravity", "tip loads"]  # written as LABELs, read back as names
    for name, cfg in deck.configurations.items():
        assert_close(config_data(deck.model, cfg), config_data(again.model, again.configurations[name]), rtol=1e-10)


def test_compact_deck_in_other_units(tmp_path):
    model = Model("strip")
    ids = model.add_nodes([[0, 0, 0], [0.5, 0, 0], [1.0, 0, 0]])
    al = Material("Al", E=70e9, nu=0.33, rho=2700.0)
    model.add_beams([[1, 2], [2, 3]], al, RectangularSection(0.05, 0.003), orientation=(0, 0, 1), mass="lumped",
                    rotary_inertia=False)
    model.add_mass(3, 0.01, offset=(0.02, 0, 0), inertia=[1e-6, 2e-6, 3e-6])
    model.add_spring(3, None, stiffness=[0, 0, 17.0, 0, 0, 0], damping=[0, 0, 0.23, 0, 0, 0])
    cfg = fg.Configuration("hang", fixed={1: "123456"}, gravity=1.0)
    out = fg.io.write_bdf(model, tmp_path / "mm.bdf", configurations=[cfg], units="mm-N-t-s")
    text = out.read_text()
    assert "1000." in text and "70000." in text  # mm and MPa in the file
    again = read(out, units="mm-N-t-s")
    assert_close(model_data(model), model_data(again.model), rtol=1e-10)
    assert again.configurations["hang"].gravity_vector == pytest.approx(cfg.gravity_vector)
    assert ids.tolist() == again.model.node_ids.tolist()
