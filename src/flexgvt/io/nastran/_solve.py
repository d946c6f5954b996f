"""Deprecated home of ``solve_deck``: solving is a workflow step (flexgvt.workflow.solve_deck)."""

from __future__ import annotations

import warnings


def solve_deck(*args, **kwargs):
    """Deprecated alias of flexgvt.workflow.solve_deck (io reads and writes; it does not solve)."""
    warnings.warn("flexgvt.io.solve_deck moved to flexgvt.workflow.solve_deck; the io alias will be removed",
                  DeprecationWarning, stacklevel=2)
    from ...workflow.deck import solve_deck as _solve_deck

    return _solve_deck(*args, **kwargs)
