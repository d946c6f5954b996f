"""Static (Guyan) reduction sets: ASET/ASET1 (the analysis set, a-set) and OMIT/OMIT1 (the omitted
set, o-set), read into ``BdfDeck.options`` for the solver: solve_deck applies them, and
``solve_modes(state, n, reduction=deck.options)`` (fem.reduction: static condensation as Nastran's).

``options["ASET"]`` and ``options["OMIT"]``: {grid id: components in basic axes, digits 1-6 as
``Configuration.fixed`` writes them}. Nastran: when ASET/ASET1 are present, every DOF not constrained
(SPC, MPC/RBE dependent) and not in the a-set is omitted; OMIT/OMIT1 name omitted DOFs directly.
Components are in the grid's displacement system (CD): a CD whose named components do not line up
with basic axes cannot be expressed as flexgvt DOFs and is refused. ASET1/OMIT1 ids that are not
grids are skipped with a note (Nastran skips them in a THRU range); an ASET/OMIT grid that does
not exist, scalar points (component 0) and a DOF in both sets are errors naming the card.
"""

from __future__ import annotations

from ...errors import ModelError
from ...model import Model
from ._deck import Deck, Family, Findings, Parts
from ._grids import basic_dofs

CARDS = ("ASET", "ASET1", "OMIT", "OMIT1")


def _basic_dofs(deck: Deck, nid: int, comps: str, where: str) -> set[int]:
    """DOF indices 0-5 in basic axes of components ``comps`` of grid ``nid`` (in its CD)."""
    comps = str(comps).strip()
    if not comps or any(c not in "123456" for c in comps):
        raise ModelError(f"{where}: components {comps!r} must be digits 1-6 (scalar points are not supported)")
    return basic_dofs(deck, nid, sorted({int(c) - 1 for c in comps}), where, "grid", "components",
                      "flexgvt's DOFs are in basic axes: give the grid a CD aligned with basic or name all three "
                      "translations/rotations")


def _read_sets(deck: Deck, cards, log: Findings) -> dict[int, set[int]]:
    found: dict[int, set[int]] = {}
    missing: list[str] = []
    for card in cards:
        if card.type in ("ASET1", "OMIT1"):
            where = deck.at(card.type, card.components)
            pairs = [(int(n), str(card.components)) for n in card.ids]
        else:
            where = deck.at(card.type, card.ids[0])
            pairs = [(int(n), str(c)) for n, c in zip(card.ids, card.components)]
        for nid, comps in pairs:
            if nid not in deck.bdf.nodes:
                if card.type in ("ASET", "OMIT"):
                    raise ModelError(f"{where} refers to grid {nid}, which is not defined; add the GRID or fix the "
                                     "id")
                missing.append(f"{card.type} {nid}")
                continue
            found.setdefault(nid, set()).update(_basic_dofs(deck, nid, comps, where))
    if missing:
        log.note(f"{', '.join(missing[:8])}{' ...' if len(missing) > 8 else ''}: not a grid; skipped (as Nastran "
                 "skips the missing points of a THRU range)")
    return found


def _as_text(dofs: dict[int, set[int]]) -> dict[int, str]:
    return {nid: "".join(str(d + 1) for d in sorted(s)) for nid, s in sorted(dofs.items()) if s}


def read_reduction(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """options['ASET'] / options['OMIT'] from the deck's ASET/ASET1 and OMIT/OMIT1 cards (see module)."""
    bdf = deck.bdf
    asets, omits = list(getattr(bdf, "asets", []) or []), list(getattr(bdf, "omits", []) or [])
    if not asets and not omits:
        return Parts()
    kept = _read_sets(deck, asets, log)
    omitted = _read_sets(deck, omits, log)
    for nid in sorted(set(kept) & set(omitted)):
        both = kept[nid] & omitted[nid]
        if both:
            raise ModelError(f"{deck.path}: grid {nid} components {''.join(str(d + 1) for d in sorted(both))} are "
                             "in both the analysis set (ASET/ASET1) and the omitted set (OMIT/OMIT1); a DOF "
                             "belongs to one: remove it from one card")
    options = {}
    if kept:
        options["ASET"] = _as_text(kept)
    if omitted:
        options["OMIT"] = _as_text(omitted)
    names = "/".join(sorted(name for name in bdf.card_count if name in CARDS))
    counts = ", ".join(f"{k} {sum(len(c) for c in v.values())} DOFs" for k, v in options.items())
    log.note(f"{names} (Guyan reduction: {counts}) kept in BdfDeck.options: solve_deck reduces the model as Nastran "
             "does; with solve_modes pass reduction=deck.options (without it the full model's modes: lower, the "
             "reduced model is stiffer)")
    return Parts(options=options)


FAMILY = Family("reduction", CARDS, read_reduction)
