"""Modes followed across load levels: pairing successive mode sets by a mass-weighted MAC, and
frequencies versus load (a nonlinear static solve through the levels, modes at each)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..model import Configuration, Model
from .labels import mac_matrix
from .modes import Modes, solve_modes
from .static import StaticSettings, solve_static


@dataclass(frozen=True)
class ModeTracking:
    """Modes followed across load levels.

    load_factors (n_levels,); frequencies_hz (n_levels, n_tracks) where column j follows one
    physical mode; labels (n_tracks,) at the first level; mac (n_levels - 1, n_tracks): MAC
    between consecutive levels; order (n_levels, n_tracks): index of the mode in each level's
    sorted list.
    """

    load_factors: np.ndarray
    frequencies_hz: np.ndarray
    labels: tuple[str, ...]
    mac: np.ndarray
    order: np.ndarray
    modes: tuple = ()


def _weighted(modes: Modes) -> np.ndarray:
    """(n_dof, n_modes) shapes scaled by sqrt(diag M): translations and rotations weighted by their inertia."""
    state = modes.state
    w = np.sqrt(np.abs(state.system.full_mass_matrix(state.positions, state.rotations).diagonal()))
    return modes.matrix() * w[:, None]


def track_modes(mode_sets, load_factors: np.ndarray | None = None) -> ModeTracking:
    """Pair the modes of successive levels by a mass-weighted MAC (Hungarian assignment).

    The shapes are weighted by sqrt(diag M) so torsion modes (rotations only on a beam axis)
    are compared as reliably as bending modes.
    """
    mode_sets = list(mode_sets)
    n = min(m.n_modes for m in mode_sets)
    order = np.zeros((len(mode_sets), n), dtype=int)
    order[0] = np.arange(n)
    macs = np.zeros((max(len(mode_sets) - 1, 0), n))
    shapes = [_weighted(m) for m in mode_sets]
    for k in range(1, len(mode_sets)):
        M = mac_matrix(shapes[k - 1][:, order[k - 1]], shapes[k])
        rows, cols = linear_sum_assignment(-M)
        order[k, rows] = cols
        macs[k - 1, rows] = M[rows, cols]
    freqs = np.stack([mode_sets[k].frequencies_hz[order[k]] for k in range(len(mode_sets))])
    lf = np.asarray(load_factors if load_factors is not None else np.arange(len(mode_sets)), float)
    labels = tuple(mode_sets[0].labels[i] for i in order[0]) if mode_sets[0].labels else ()
    return ModeTracking(lf, freqs, labels, macs, order, tuple(mode_sets))


def modes_versus_load(model: Model, configuration: Configuration, load_factors: np.ndarray | list[float],
                      n_modes: int = 10,
                      settings: StaticSettings | None = None) -> ModeTracking:
    """Modes at each load factor (fractions of the configuration's loads, 0 to 1), tracked by MAC.

    One load-stepped solve passes through every level, so the cost is that of a single solve
    plus one eigensolution per level.
    """
    levels = np.unique(np.clip(np.asarray(load_factors, float), 0.0, 1.0))
    final = solve_static(model, configuration, settings=settings, load_factors=levels)
    by_level = {round(s.load_factor, 9): s for s in final.steps}
    by_level[round(final.load_factor, 9)] = final
    states = [by_level[round(lv, 9)] for lv in levels]
    mode_sets = [solve_modes(s, n_modes) for s in states]
    return track_modes(mode_sets, levels)
