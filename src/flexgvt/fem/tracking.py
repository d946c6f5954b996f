"""Frequencies versus load: nonlinear static at a series of load levels, modes at each, tracked by MAC."""

from __future__ import annotations

import numpy as np

from ..model import Configuration, Model
from .labels import ModeTracking, track_modes
from .modes import solve_modes
from .static import StaticSettings, solve_static


def modes_versus_load(model: Model, configuration: Configuration, load_factors, n_modes: int = 10,
                      settings: StaticSettings | None = None) -> ModeTracking:
    """Modes at each load factor (fractions of the configuration's loads, 0 to 1), tracked by MAC.

    One load-stepped solve passes through every level, so the cost is that of a single solve
    plus one eigensolution per level.
    """
    levels = np.unique(np.clip(np.asarray(load_factors, float), 0.0, 1.0))
    final, saved = solve_static(model, configuration, settings=settings, load_factors=levels, keep_steps=True)
    by_level = {round(s.load_factor, 9): s for s in saved}
    by_level[round(final.load_factor, 9)] = final
    states = [by_level[round(lv, 9)] for lv in levels]
    mode_sets = [solve_modes(s, n_modes) for s in states]
    return track_modes(mode_sets, levels)
