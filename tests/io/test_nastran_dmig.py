"""DMIG (direct matrix input): Nastran adds a DMIG to the model only where the case control selects it.
One selected only by K2PP/M2PP/B2PP with every term on extra points (EPOINT, no structure; pyNastran's
glider deck fmondsp.dat puts a 1 on its dynamic-load point this way) leaves the structure unchanged and
is noted, not refused (it was refused before); one on the structure's grids is refused, named."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.io import UnsupportedCardsError

DECK = """SOL 103
CEND
METHOD = 1
{selector} = STIFF
SUBCASE 1
BEGIN BULK
EIGRL,1,,,4
GRID,1,,0.,0.,0.,,123456
GRID,2,,1.,0.,0.
GRID,3,,2.,0.,0.
CBEAM,10,1,1,2,0.,0.,1.
CBEAM,11,1,2,3,0.,0.,1.
PBEAM,1,1,1.e-4,1.e-8,2.e-8,,1.e-8
MAT1,1,7.e10,,0.3,2700.
EPOINT,1000
DMIG,STIFF,0,6,1,0
DMIG,STIFF,{col},{comp},,{col},{comp},1.
ENDDATA
"""


def _read(tmp_path, **fields):
    path = tmp_path / "dmig.bdf"
    path.write_text(DECK.format(**fields))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        deck = fg.io.read_bdf(path)
    return deck, " ".join(str(w.message) for w in caught)


def test_dmig_on_extra_points_through_k2pp_is_noted_not_refused(tmp_path):
    deck, said = _read(tmp_path, selector="K2PP", col=1000, comp=0)
    assert "DMIG STIFF: selected by K2PP on extra points (EPOINT 1000) only" in said
    f = fg.solve_modes(fg.solve_static(deck.model, next(iter(deck.configurations.values()))), 4).frequencies_hz
    assert np.all(f > 0)


@pytest.mark.parametrize("selector", ["K2PP", "K2GG"])
def test_dmig_on_a_grid_is_refused_naming_it(tmp_path, selector):
    with pytest.raises(UnsupportedCardsError, match=rf"DMIG \({selector} on the structure's grids: direct matrix "
                                                    r"input\): STIFF"):
        _read(tmp_path, selector=selector, col=3, comp=3)
