"""The card families flexgvt reads, in reading order, and which family reads which card.

Adding a family (e.g. plates: CQUAD4, CTRIA3, PSHELL, PCOMP, MAT2, MAT8) is a new module with a
``FAMILY = Family(...)`` entry and one line in FAMILIES; no other family's code changes. The order
is the order of the model's beams, masses, springs and rigid links (and of their *_sources): a
family reads what earlier ones returned (materials, element ids, end links) from ``parts``.
"""

from __future__ import annotations

from . import _beams, _grids, _masses, _materials, _plates, _reduction, _rigid, _rods, _springs, _subcases
from ._deck import Family

# Structure families: each adds its entities to the model. The rigid family comes after every
# family that adds end nodes (their links hang on the roots of RBE2 chains).
FAMILIES: tuple[Family, ...] = (
    _materials.FAMILY,
    _beams.FAMILY,
    _rods.FAMILY,
    _plates.FAMILY,
    _masses.FAMILY,
    _springs.FAMILY,
    _rigid.FAMILY,
    _reduction.FAMILY,
)

# Bulk cards read outside the families: grids and coordinate systems (the Deck), subcases (after
# the structure: AUTOSPC needs every element).
DECK_CARDS = _grids.CARDS
CASE_CARDS = _subcases.CARDS

# card -> the family reading it ('deck' and 'subcases' for the two above)
CARD_FAMILY: dict[str, str] = {
    **{card: "deck" for card in DECK_CARDS},
    **{card: family.name for family in FAMILIES for card in family.cards},
    **{card: "subcases" for card in CASE_CARDS},
}
READ_CARDS = frozenset(CARD_FAMILY)
NEEDS_PROPERTY = frozenset(card for family in FAMILIES for card in family.needs_property)
NEEDS_MATERIAL = frozenset(card for family in FAMILIES for card in family.needs_material)
