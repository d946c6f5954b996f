"""SUPORT: a free-flying deck is read, solved free-free with its six rigid-body modes at zero, and
its reference DOFs kept on the configuration (they were refused as unsupported before)."""

import numpy as np

import flexgvt as fg

DECK = """SOL 103
CEND
METHOD = 1
SUBCASE 1
  SUPORT1 = 7
BEGIN BULK
EIGRL,1,,,10
GRID,1,,0.,0.,0.
GRID,2,,1.,0.,0.
GRID,3,,2.,0.,0.
GRID,4,,3.,0.,0.
CBEAM,10,1,1,2,0.,0.,1.
CBEAM,11,1,2,3,0.,0.,1.
CBEAM,12,1,3,4,0.,0.,1.
PBEAM,1,1,1.e-4,1.e-8,2.e-8,,1.e-8
MAT1,1,7.e10,,0.3,2700.
SUPORT,2,123
SUPORT1,7,2,456
PLOTEL,100,1,4
EPOINT,900
ENDDATA
"""


def test_free_flying_deck_with_suport_is_read_and_solved_free_free(tmp_path):
    path = tmp_path / "free.bdf"
    path.write_text(DECK)
    deck = fg.io.read_bdf(path)  # no option: SUPORT and the monitoring cards no longer refused
    cfg = next(iter(deck.configurations.values()))
    assert cfg.support == {2: "123456"}
    assert not cfg.fixed
    modes = fg.solve_modes(fg.solve_static(deck.model, cfg), 9)
    assert np.sum(modes.frequencies_hz == 0) == 6
    assert modes.frequencies_hz[6] > 1.0
