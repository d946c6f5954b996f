"""Smoke test: a two-element cantilever deck reads, writes back and reads again."""

import numpy as np

import flexgvt as fg

DECK = """SOL 103
CEND
SPC = 1
BEGIN BULK
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,2.,0.,0.
CBAR,10,1,1,2,0.,0.,1.
CBAR,11,1,2,3,0.,0.,1.
PBAR,1,1,1.e-4,1.e-8,2.e-8,1.e-8
MAT1,1,7.e10,,0.3,2700.
SPC1,1,123456,1
ENDDATA
"""


def test_smoke_round_trip(tmp_path):
    path = tmp_path / "cantilever.bdf"
    path.write_text(DECK)
    deck = fg.io.read_bdf(path)
    assert list(deck.configurations) == ["cantilever"]
    assert deck.configurations["cantilever"].fixed == {1: "123456"}
    out = fg.io.write_bdf(deck.model, tmp_path / "out.bdf", template=deck)
    again = fg.io.read_bdf(out)
    assert np.allclose(again.model.xyz, deck.model.xyz)
    assert again.model.beams[0].section == deck.model.beams[0].section
