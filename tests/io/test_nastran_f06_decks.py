"""Real aeroelastic decks with the eigenvalues MSC/Simcenter Nastran printed for them (pyNastran's
models/ folder, BSD-3; origins in tests/data/bdf/ORIGIN.md): read with no option, solved as
`solve_deck` does, the rigid-body modes and the first six elastic frequencies are Nastran's.
"""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.workflow import solve_deck

DATA = Path(__file__).parents[1] / "data" / "bdf"
F06 = json.loads((DATA / "pynastran" / "eigenvalues_f06.json").read_text())
# plate decks ("shells": true) are tests/io/test_nastran_plate_decks.py's
DECKS = {name: np.array(v["cycles_hz"]) for name, v in F06.items() if not v.get("shells")}
DECKS["../beam_modes/beam_modes.dat"] = np.loadtxt(DATA / "beam_modes" / "eigenvalues_simcenter.txt",
                                                    comments="#")[:, 3]


def read(name, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(DATA / "pynastran" / name, **options)


@pytest.mark.parametrize("name", sorted(DECKS))
def test_first_six_elastic_frequencies_are_nastrans(name):
    """No option (units do not change frequencies): zero modes as many as Nastran's, then six
    elastic modes within 1e-5 (Nastran prints 7 digits)."""
    nastran = DECKS[name]
    n_rigid = int(np.sum(nastran < 1e-3))
    deck = read(name)
    result = next(iter(solve_deck(deck, n_modes=n_rigid + 6).values()))
    f = result.modes.frequencies_hz
    assert np.all(np.abs(f[:n_rigid]) < 1e-3 * nastran[n_rigid])
    assert f[n_rigid:n_rigid + 6] == pytest.approx(nastran[n_rigid:n_rigid + 6], rel=1e-5)


def test_pt145_cbar_coupled_mass_has_no_torsional_inertia():
    """pt145 (COUPMASS 1, CMASS2 torsional inertia in a swept CD system): Nastran's CBAR mass, lumped or
    coupled, has no rho*Ip. With it (the option) the torsion modes 2, 5 and 6 drop by 2.4-2.6e-4."""
    nastran = DECKS["pt145.bdf"]
    deck = read("pt145.bdf", cbar_torsional_inertia=True)
    f = next(iter(solve_deck(deck, n_modes=6).values())).modes.frequencies_hz
    err = f / nastran[:6] - 1
    assert np.all(np.abs(err[[0, 2, 3]]) < 1e-5) and np.all(err[[1, 4, 5]] < -2e-4)


def test_pt145_zero_i2_is_held_by_the_grid_ps_constraints():
    """PBAR I2 blank (0): Nastran accepts it (plane-2 bending has no stiffness); the GRID PS = 126 in the
    swept system hold those motions. flexgvt refused the deck before."""
    deck = read("pt145.bdf")
    assert deck.model.beams[0].section.Iy == 0.0
    fixed = deck.configurations["pt145"].fixed
    assert fixed[1] == "123456" and all(fixed[g] == "126" for g in range(2, 12))  # 126 in CD 1 span basic 126


@pytest.mark.parametrize("name, support, fixed", [("ha144/ha144ds.bdf", "135", "246"),
                                                   ("ha144/ha144da.bdf", "246", "135")])
def test_ha144_half_models_free_with_suport_give_every_mode_nastran_found(name, support, fixed):
    """HA144D (CBAR + CONM2 dumbbells on RBARs, massless bars and rotations, WTMASS) as symmetric and
    antisymmetric half models: SUPORT 90 in the plane, the centreline SPC out of it. EIGR MGIV asks for
    24 roots, but the massless DOFs (bars without density, point masses without inertia) leave 21 and
    16 finite ones: Nastran printed 21 and 16, the first three rigid; solve_deck with the deck's method
    gives the same count, every one Nastran's."""
    nastran = DECKS[name]
    deck = read(name)
    cfg = next(iter(deck.configurations.values()))
    assert cfg.support == {90: support} and all(cfg.fixed[g] == fixed for g in (90, 97, 98, 99, 100, 310))
    f = next(iter(solve_deck(deck).values())).modes.frequencies_hz
    assert len(f) == len(nastran) and np.all(np.abs(f[:3]) < 1e-3)
    assert f[3:] == pytest.approx(nastran[3:], rel=1e-5)


def test_ha144ds_second_begin_bulk_is_noted():
    assert any("ha144ds.bdf:13: BEGIN BULK repeated inside the bulk data: ignored" in n
               for n in read("ha144/ha144ds.bdf").notes)


def test_strut_wing_cbeam_coupled_mass_lumps_axial_and_torsion():
    """Strut-braced wing (CBEAM, COUPMASS, grids in rotated CP/CD systems, RBE2, SUPORT 1 3): Nastran's
    fourteen elastic modes to 1e-5. Its 5.854 Hz mode twists the strut's first element, whose density
    is 100 times the others' (its A a hundredth): with consistent (linear) torsional and axial mass
    that mode moves to 7.08 Hz and the others by up to 2e-4; Nastran lumps both."""
    nastran = DECKS["strut_wing/buckled.bdf"]
    deck = read("strut_wing/buckled.bdf")
    assert next(iter(deck.configurations.values())).support == {1: "3"}
    assert {g.mass for g in deck.model.beams} == {"consistent-bending"}
    assert {deck.bdf.nodes[n].cd for n in (43, 8035, 8041)} == {222, 111}
    f = next(iter(solve_deck(deck, n_modes=15).values())).modes.frequencies_hz
    assert abs(f[0]) < 1e-3 and f[1:] == pytest.approx(nastran[1:], rel=1e-5)
    model = deck.model.copy()
    for i in range(len(model.beams)):
        model.set_beam_group(i, mass="consistent")
    full = fg.solve_modes(fg.solve_static(model, next(iter(deck.configurations.values()))), 8).frequencies_hz
    assert np.min(np.abs(full / 5.8542 - 1)) > 0.03 and np.min(np.abs(full / 7.08 - 1)) < 0.01
