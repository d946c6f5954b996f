"""Solve a Nastran deck's subcases: nonlinear static, then modes about it, as the deck's METHOD asks.

EIGRL/EIGR are honoured as Nastran does: ND modes (the lowest), the frequency window V1-V2 (F1-F2
for EIGR; only modes inside it are reported; for EIGR GIV/HOU the window applies only when ND is
blank) and the normalisation (MASS: phi^T M phi = 1; MAX: largest component +1; POINT: the
named grid component 1, or MAX in a mode where it does not move).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Iterable

import numpy as np

from ..errors import ModelError

if TYPE_CHECKING:  # reading decks imports pyNastran: only when a deck is read
    from ..io.nastran import BdfDeck

MAX_WINDOW_MODES = 400  # a window with no ND stops here (with a ModelError naming the window)


@dataclass
class SubcaseResult:
    """One configuration of a deck solved: ``state`` (nonlinear static) and ``modes`` about it."""

    name: str
    subcase: int
    state: object
    modes: object


def _in_window(f: np.ndarray, method) -> np.ndarray:
    """Modes inside [f1, f2] (rigid-body modes computed as tiny +-numbers count as 0 Hz)."""
    scale = max(abs(method.f2 or 0.0), abs(method.f1 or 0.0), 1.0)
    tol = 1e-6 * scale
    keep = np.ones(len(f), bool)
    if method.f1 is not None:
        keep &= f >= method.f1 - tol
    if method.f2 is not None:
        keep &= f <= method.f2 + tol
    return keep


def normalise(modes, method):
    """Shapes scaled as the method's NORM (MASS: unchanged; MAX; POINT)."""
    if method is None or method.norm == "MASS":
        return modes
    shapes = np.array(modes.shapes, float, copy=True)
    for k, s in enumerate(shapes):
        if method.norm == "MAX":
            flat = s.ravel()
            ref = flat[np.argmax(np.abs(flat))]
        else:
            grid, comp = method.point
            idx = np.flatnonzero(np.asarray(modes.node_ids) == grid)
            ref = s[idx[0], comp - 1] if len(idx) else 0.0
            flat = s.ravel()
            if abs(ref) <= 1e-9 * np.max(np.abs(flat)):  # the point does not move: MAX, as Nastran
                ref = flat[np.argmax(np.abs(flat))]
        if ref != 0.0:
            shapes[k] = s / ref
    return replace(modes, shapes=shapes, complex_shapes=None)


def deck_modes(state, method, n_modes: int | None = None, mass_frame: str = "deformed", reduction=None):
    """Modes about ``state`` as the EigenMethod asks (n_modes, when given, overrides ND); reduction:
    the deck's Guyan sets (BdfDeck.options 'ASET'/'OMIT', see fem.reduction), real modes then."""
    from functools import partial

    from ..fem import solve_modes

    if reduction:
        solve_modes = partial(solve_modes, reduction=reduction, damped=False)
    if method is None:
        return solve_modes(state, n_modes=n_modes or 10, mass_frame=mass_frame)
    window = method.f1 is not None or method.f2 is not None
    if n_modes is not None or (method.nd and not (window and method.window_with_nd)):
        return normalise(solve_modes(state, n_modes=n_modes or method.nd, mass_frame=mass_frame), method)
    n_dof = 6 * state.system.n_nodes
    n = method.nd or 10
    while True:
        modes = solve_modes(state, n_modes=min(n, n_dof), mass_frame=mass_frame)
        f = modes.frequencies_hz
        done = (method.f2 is not None and f[-1] > method.f2) or len(f) >= n_dof - 1 or len(f) < min(n, n_dof) or \
            (method.nd and np.sum(_in_window(f, method)) >= method.nd)
        if done or method.f2 is None:
            break
        if n >= MAX_WINDOW_MODES:
            raise ModelError(f"{method.card} {method.sid}: more than {MAX_WINDOW_MODES} modes below V2 = {method.f2} Hz"
                             "; give ND or a lower V2")
        n = min(2 * n, MAX_WINDOW_MODES)
    keep = np.flatnonzero(_in_window(modes.frequencies_hz, method))
    if method.nd:
        keep = keep[:method.nd]
    return normalise(_select(modes, keep), method)


def _select(modes, keep: np.ndarray):
    """The modes ``keep`` (indices) of a Modes."""
    def pick(a):
        return None if a is None else np.asarray(a)[keep]
    labels = tuple(modes.labels[i] for i in keep) if modes.labels else ()
    return replace(modes, frequencies_hz=pick(modes.frequencies_hz), damping_ratio=pick(modes.damping_ratio),
                   damped_frequencies_hz=pick(modes.damped_frequencies_hz), shapes=pick(modes.shapes), labels=labels,
                   complex_shapes=pick(modes.complex_shapes), eigenvalues=pick(modes.eigenvalues),
                   energy_fractions=pick(modes.energy_fractions))


def guyan_sets(deck) -> dict:
    """The deck's Guyan-reduction sets: {'ASET' and/or 'OMIT': {grid: components}}, those it gives."""
    options = getattr(deck, "options", {}) or {}
    return {k: options[k] for k in ("ASET", "OMIT") if options.get(k)}


def solve_deck(deck: BdfDeck | str | Path, n_modes: int | None = None, configurations: Iterable[str] | None = None,
               mass_frame: str = "deformed",
               **read_options) -> dict[str, SubcaseResult]:
    """Solve every (or the named) configuration of a deck: nonlinear static, then modes about it.

    deck: a BdfDeck or a path (read with read_bdf(path, **read_options)). n_modes: modes per
    configuration, overriding the subcase's EIGRL/EIGR (default: its ND, window V1-V2 and
    normalisation, as Nastran reports them; 10 modes without METHOD). mass_frame: "undeformed"
    reproduces MSC Nastran SOL 400's pre-stressed modes (see solve_modes). A deck's ASET/OMIT sets
    reduce the model as Nastran does (Guyan, fem.reduction; real modes). Returns {name: SubcaseResult}.
    """
    from ..fem import solve_static
    from ..io.nastran import read_bdf

    if isinstance(deck, (str, Path)):
        deck = read_bdf(deck, **read_options)
    names = list(deck.configurations) if configurations is None else list(configurations)
    reduction = guyan_sets(deck)  # Nastran's Guyan reduction
    out = {}
    for name in names:
        cfg = deck.configurations[name]
        state = solve_static(deck.model, cfg)
        method = getattr(deck, "methods", {}).get(name)
        out[name] = SubcaseResult(name, deck.subcases.get(name, 0), state,
                                  deck_modes(state, method, n_modes, mass_frame, reduction))
    return out
