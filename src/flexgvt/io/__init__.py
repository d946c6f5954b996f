"""File formats: UFF (pyuff), Nastran bulk data (pyNastran). Readers load on first use."""

from __future__ import annotations

import importlib

_EXPORTS = {
    "read_uff": ".uff", "write_uff": ".uff",
    "read_bdf": ".nastran", "write_bdf": ".nastran", "solve_deck": ".nastran", "BdfDeck": ".nastran",
    "UnsupportedCardsError": ".nastran",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name], __name__), name)
    raise AttributeError(f"module 'flexgvt.io' has no attribute {name!r}")
