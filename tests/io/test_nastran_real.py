"""Real bulk data decks from public repositories (see tests/data/bdf/ORIGIN.md).

beam_modes: a 10-element cantilever rod (9 CBAR on PBARL ROD, 1 CBEAM on PBEAML ROD, tip
CONM2 with inertia, in-lbf-s) whose real eigenvalues Simcenter Nastran printed in the .f06:
flexgvt must reproduce them.
"""

import warnings
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.io.nastran import UnsupportedCardsError
from flexgvt.workflow import solve_deck

DATA = Path(__file__).parents[1] / "data" / "bdf"
BEAM_MODES = DATA / "beam_modes" / "beam_modes.dat"


def nastran_frequencies() -> np.ndarray:
    rows = np.loadtxt(DATA / "beam_modes" / "eigenvalues_simcenter.txt", comments="#")
    return rows[:, 3]


def read_beam_modes(**options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(BEAM_MODES, units="in-lbf-s", **options)


def test_beam_modes_reads_with_the_includes_and_params():
    deck = read_beam_modes()
    model = deck.model
    assert model.n_nodes == 12 and model.n_beams == 10 and len(model.masses) == 1
    assert deck.mass == "lumped"  # no COUPMASS
    assert [g.name for g in model.beams] == ["PBARL_1", "PBEAML_3"]
    cfg = deck.configurations["beam_modes"]
    assert cfg.fixed[1] == "123456"
    assert cfg.fixed[12] == "123456"  # GRID 12 has no element: AUTOSPC
    assert deck.n_modes["beam_modes"] == 10
    # in-lbf-s converted to SI: 10 in long, E = 3e7 psi
    assert model.xyz[:, 0].max() == pytest.approx(10 * 0.0254)
    assert model.beams[0].material.E == pytest.approx(3.0e7 * 6894.757, rel=1e-6)


def test_beam_modes_matches_simcenter_nastran_eigenvalues():
    """All ten modes (bending pairs, torsion, axial) within 1e-5 of Nastran's by default: CBAR mass
    without torsional inertia, as Nastran's."""
    deck = read_beam_modes()
    state = fg.solve_static(deck.model, deck.configurations["beam_modes"])
    modes = fg.solve_modes(state, 10)
    assert modes.frequencies_hz == pytest.approx(nastran_frequencies(), rel=1e-5)


def test_beam_modes_option_keeps_torsional_inertia():
    """cbar_torsional_inertia=True keeps rho*Ip on the CBARs: bending and axial modes stay Nastran's,
    torsion drops."""
    deck = read_beam_modes(cbar_torsional_inertia=True)
    modes = fg.solve_modes(fg.solve_static(deck.model, deck.configurations["beam_modes"]), 8)
    f = nastran_frequencies()
    bending_axial = [0, 1, 5, 6, 7]
    got = np.sort(modes.frequencies_hz)
    for k in bending_axial:
        assert np.min(np.abs(got / f[k] - 1)) < 1e-5
    torsion = [lab for lab in modes.labels if lab.endswith("T")]
    t1 = modes.frequencies_hz[list(modes.labels).index(torsion[0])]
    assert t1 < 0.8 * f[4]  # the rod's own torsional inertia is now counted


def test_beam_modes_with_a_crod_added_reads_it_as_a_rod(tmp_path):
    """A CROD on the real deck's (until then unused) PROD 2, to a node no other element reaches."""
    text = BEAM_MODES.read_text().replace(
        "INCLUDE 'cbar_cbeam.blk'", f"INCLUDE '{BEAM_MODES.parent / 'cbar_cbeam.blk'}'\nCROD,99,2,1,12")
    path = tmp_path / "beam_modes_crod.dat"
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = fg.io.read_bdf(path, units="in-lbf-s")
    rod = next(g for g in deck.model.beams if g.name == "PROD_2")
    assert rod.nodes.tolist() == [[1, 12]] and isinstance(rod.section, fg.RodSection)
    assert deck.element_ids[99] == int(rod.ids[0])
    assert any("[12] have no rotational stiffness" in n for n in deck.notes)


PYN = DATA / "pynastran"


def test_patran_crod_deck_gives_its_single_dof_frequency():
    """Patran-written SOL 103 deck: 100 kg CONM2 on a CROD (E = 100, A = 1, L = 0.01, weightless),
    guided along the rod: f = sqrt(E A / (L m)) / (2 pi) = 10 / (2 pi) Hz."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = fg.io.read_bdf(PYN / "sdof_crod.bdf")
    length = 0.009999999776483  # the deck's GRID* 7 z, a single-precision 0.01
    modes = solve_deck(deck)["subcase_1"].modes
    assert modes.frequencies_hz[0] == pytest.approx(np.sqrt(100.0 * 1.0 / (length * 100.0)) / (2 * np.pi), rel=1e-9)


def test_patran_offset_cbeam_deck_fails_naming_the_feature():
    """The CBEAM offsets (WA/WB) are read; the channel's PBEAM neutral-axis offsets (N1/N2) are not,
    and the error names them and the beams they leave out."""
    with pytest.raises(UnsupportedCardsError) as err:
        fg.io.read_bdf(PYN / "cantilever_2014.1.bdf")
    assert set(err.value.unsupported) == {"PBEAM (neutral-axis/NSM offsets)", "CBEAM on unsupported PBEAM"}
    assert len(err.value.unsupported["CBEAM on unsupported PBEAM"]) == 10


def test_euler_column_reads_with_grdset_and_prestress_lowers_the_frequency():
    """420 CBEAM (PBEAML ROD), GRDSET PS=345 (planar), SOL 105 deck in mm-N. Compression P lowers the
    first pinned-pinned bending frequency by sqrt(1 - P/Pcr) (same mode shape as buckling)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = fg.io.read_bdf(PYN / "euler_column_linear_buckling.bdf", units="mm-N-t-s")
    cfg = deck.configurations["subcase_1"]
    assert cfg.fixed[1] == "12345" and cfg.fixed[421] == "2345" and cfg.fixed[200] == "345"
    assert cfg.forces[0].force == pytest.approx((-1.0, 0, 0))
    E, R, L = 207000e6, 0.010, 0.420
    p_cr = np.pi**2 * E * (np.pi * R**4 / 4) / L**2
    free = fg.solve_modes(fg.solve_static(deck.model, cfg.with_(forces=())), 1).frequencies_hz[0]
    loaded_cfg = cfg.with_(forces=(fg.NodalLoad(421, force=(-0.5 * p_cr, 0.0, 0.0)),))
    loaded = fg.solve_modes(fg.solve_static(deck.model, loaded_cfg), 1).frequencies_hz[0]
    assert loaded / free == pytest.approx(np.sqrt(0.5), rel=1e-2)


def test_beam_modes_template_round_trip_keeps_frequencies(tmp_path):
    """Write the real deck back through its template (PBARL and PBEAML ROD kept) and solve it again."""
    deck = read_beam_modes()
    out = fg.io.write_bdf(deck.model, tmp_path / "beam_modes_out.bdf", template=deck)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        again = fg.io.read_bdf(out, units="in-lbf-s")
    assert again.bdf.properties[3].type == "PBEAML" and again.bdf.properties[1].type == "PBARL"
    modes = fg.solve_modes(fg.solve_static(again.model, again.configurations["beam_modes_out"]), 10)
    assert modes.frequencies_hz == pytest.approx(nastran_frequencies(), rel=1e-5)
