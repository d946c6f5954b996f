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
DECKS = {name: np.array(v["cycles_hz"]) for name, v in F06.items()}
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
