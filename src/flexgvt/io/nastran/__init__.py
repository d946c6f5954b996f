"""Nastran bulk data in and out (pyNastran): ``read_bdf`` -> BdfDeck(.model, .configurations), ``write_bdf``.

See docs/nastran.md for the card mapping, axes, units and what is not supported.
"""

from __future__ import annotations

from ._common import UNIT_SYSTEMS, EigenMethod, Units, UnsupportedCardsError
from ._read import BdfDeck, BeamSource, read_bdf
from ._write import write_bdf

__all__ = [
           "UNIT_SYSTEMS",
           "BdfDeck",
           "BeamSource",
           "EigenMethod",
           "Units",
           "UnsupportedCardsError",
           "read_bdf",
           "write_bdf",
]
