"""`flexgvt solve deck.bdf`: static shape and pre-stressed modes of every subcase of a deck."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass
class SubcaseResult:
    """One configuration of a deck solved: ``state`` (nonlinear static) and ``modes`` about it."""

    name: str
    subcase: int
    state: object
    modes: object


def solve_deck(deck, n_modes: int | None = None, configurations=None, mass_frame: str = "deformed",
               **read_options) -> dict[str, SubcaseResult]:
    """Solve every (or the named) configuration of a deck: nonlinear static, then modes about it.

    deck: a BdfDeck or a path (read with read_bdf(path, **read_options)). n_modes: modes per
    configuration (default: the subcase's EIGRL ND, else 10). mass_frame: "undeformed" reproduces
    MSC Nastran SOL 400's pre-stressed modes (see solve_modes). Returns {name: SubcaseResult}.
    """
    from ...fem import solve_modes, solve_static
    from ._read import read_bdf

    if isinstance(deck, (str, Path)):
        deck = read_bdf(deck, **read_options)
    names = list(deck.configurations) if configurations is None else list(configurations)
    out = {}
    for name in names:
        cfg = deck.configurations[name]
        state = solve_static(deck.model, cfg)
        n = n_modes or deck.n_modes.get(name) or 10
        out[name] = SubcaseResult(name, deck.subcases.get(name, 0), state,
                                  solve_modes(state, n_modes=n, mass_frame=mass_frame))
    return out
