"""write_bdf and read_bdf on shells mixed with beams: the one-mass-formulation rule of a compact
deck (PARAM,COUPMASS is global) named group by group, a mixed model written and read back, and the
reader's laminates without plies."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import FileFormatError, ModelError
from flexgvt.model import Material

AL = Material("al", 70e9, 2700.0, nu=0.3)


def stiffened_plate():
    """A 0.4 x 0.1 m plate (8 x 2 quads, group 'skin', default lumped mass) with a beam stiffener
    (group 'spar', default consistent mass) on rigid links below its centre line, and a rod."""
    x, y = np.meshgrid(np.linspace(0, 0.4, 9), np.linspace(0, 0.1, 3))
    ids = np.arange(1, x.size + 1).reshape(x.shape)
    model = fg.Model("stiffened")
    model.add_nodes(np.c_[x.ravel(), y.ravel(), 0 * x.ravel()], ids=ids.ravel())
    quads = [[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]] for j in range(2) for i in range(8)]
    model.add_shells(np.array(quads), material=AL, thickness=0.002, name="skin")
    below = model.add_nodes(np.c_[x[1], np.full(9, 0.05), np.full(9, -0.011)])
    model.add_beams(np.c_[below[:-1], below[1:]], AL, fg.RectangularSection(width=0.005, height=0.02),
                    rotary_inertia=False, name="spar")  # a deck has no rotary inertia of beams
    for top, bottom in zip(ids[1], below):
        model.add_rigid_link(int(top), [int(bottom)])
    model.add_rods([[int(ids[0, -1]), int(ids[2, -1])]], AL, area=1e-5, name="tie")
    return model, ids


def test_a_default_mixed_model_is_refused_naming_its_groups(tmp_path):
    """Beams default to consistent mass, rods and shells to lumped: the message names each group
    under its formulation and says what to pass."""
    model, _ = stiffened_plate()
    with pytest.raises(ModelError) as info:
        fg.io.write_bdf(model, tmp_path / "m.bdf")
    text = str(info.value)
    assert "lumped mass (rod group 1 'tie', shell group 0 'skin')" in text
    assert "consistent mass (beam group 0 'spar')" in text
    assert "set_beam_group(k, mass=...)" in text and "defaults differ" in text


def test_a_mixed_model_with_one_formulation_is_written_and_read_back(tmp_path):
    """With the beam group lumped too, the deck is written (no COUPMASS) and reads back with the same
    clamped frequencies (to 1e-6: the deck's 8 significant digits)."""
    model, ids = stiffened_plate()
    model.set_beam_group(0, mass="lumped")
    config = fg.Configuration("clamped", fixed={int(i): "123456" for i in ids[:, 0]})
    before = fg.solve_modes(fg.solve_static(model, config), 6).frequencies_hz
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = fg.io.read_bdf(fg.io.write_bdf(model, tmp_path / "m.bdf"))
    assert "COUPMASS" not in deck.options
    assert deck.model.n_shells == model.n_shells and len(deck.model.beams) == 2
    after = fg.solve_modes(fg.solve_static(deck.model, config), 6).frequencies_hz
    np.testing.assert_allclose(after, before, rtol=1e-6)


NO_PLIES = """BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,1.,1.,0.
GRID,4,,0.,1.,0.
MAT8,8,1.5e11,9.e9,0.3,5.e9,,,1600.
CQUAD4,7,5,1,2,3,4
{card},5
ENDDATA
"""


@pytest.mark.parametrize("card, error, match", [
    ("PCOMP", FileFormatError, r"deck.bdf:8: cannot read the deck in PCOMP 5: No PCOMP layers defined"),
    ("PCOMPG", ModelError, r"deck.bdf:8: PCOMPG 5: the laminate has no plies; give at least one ply \(MID, T, THETA\)"),
])
def test_a_laminate_without_plies_is_named(tmp_path, card, error, match):
    """PCOMP: pyNastran refuses it while parsing (the reader names file, line and card); PCOMPG
    reaches the reader's own check (io/nastran/_plates.py)."""
    path = tmp_path / "deck.bdf"
    path.write_text(NO_PLIES.format(card=card))
    with pytest.raises(error, match=match):
        fg.io.read_bdf(path)
