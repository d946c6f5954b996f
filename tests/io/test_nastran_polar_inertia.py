"""A beam whose polar mass moment is not rho (Iy + Iz) (an equivalent wing section) survives the compact
deck: written as CBEAM/PBEAM with NSI carrying the difference, read back to the same modes."""

import numpy as np
import pytest

import flexgvt as fg


def test_equivalent_wing_section_round_trip(tmp_path):
    """The model's consistent mass is written under COUPMASS, where Nastran's CBEAM lumps the axial and
    torsional terms (noted): the deck read back is the model with that mass formulation."""
    case = fg.cases.xhale()
    free = fg.Configuration("free_free")
    nastran = case.model.copy()
    for i in range(len(nastran.beams)):
        nastran.set_beam_group(i, mass="consistent-bending")
    before = fg.solve_modes(fg.solve_static(nastran, free), 14)
    with pytest.warns(UserWarning, match="axial and torsional terms lumped"):
        fg.io.write_bdf(case.model, tmp_path / "x.bdf", configurations=[free])
    text = (tmp_path / "x.bdf").read_text()
    assert "PBEAM" in text and "CBEAM" in text
    deck = fg.io.read_bdf(tmp_path / "x.bdf")
    assert not deck.unsupported
    after = fg.solve_modes(fg.solve_static(deck.model, next(iter(deck.configurations.values()))), 14)
    assert np.allclose(after.frequencies_hz[6:], before.frequencies_hz[6:], rtol=1e-6)
