"""File formats: UFF (pyuff), Nastran bulk data (pyNastran). Readers load on first use."""

from __future__ import annotations

import importlib

_EXPORTS = {
    "read_uff": ".uff", "write_uff": ".uff",
    "read_bdf": ".nastran", "write_bdf": ".nastran", "BdfDeck": ".nastran",
    "UnsupportedCardsError": ".nastran",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name], __name__), name)
    if name == "solve_deck":  # removed alias (deprecated since the move): io never calls the solver
        raise AttributeError("flexgvt.io.solve_deck was removed: io reads and writes files and never solves; "
                             "use flexgvt.workflow.solve_deck(deck) (the same arguments and results)")
    raise AttributeError(f"module 'flexgvt.io' has no attribute {name!r}")
