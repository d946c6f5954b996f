"""Clusters of stable poles in a stabilisation diagram, shared by the automatic selections
(`Stabilisation.select` and `flexgvt.ema.selection`): poles grouped by frequency gaps, a group
holding k poles of one order split into k modes, and each cluster's representative pole."""

from __future__ import annotations

from typing import Callable

import numpy as np


def group_by_gap(order, f: np.ndarray, gap: Callable[[float], float]) -> list[list[int]]:
    """Indices ``order`` (sorted by frequency f) grouped where the step to the next exceeds gap(f)."""
    order = list(order)
    groups, current = [], [order[0]]
    for i in order[1:]:
        if f[i] - f[current[-1]] <= gap(f[current[-1]]):
            current.append(i)
        else:
            groups.append(current)
            current = [i]
    groups.append(current)
    return groups


def split_by_order(group: list[int], pts, f: np.ndarray) -> list[np.ndarray]:
    """A group holding k poles of one model order is k modes: split it at its k - 1 largest gaps.
    pts: (pole, participation, order index) per index."""
    c = sorted(group, key=lambda i: f[i])
    per_order: dict = {}
    for i in c:
        per_order[pts[i][2]] = per_order.get(pts[i][2], 0) + 1
    k = max(per_order.values())
    cuts = sorted(np.argsort(np.diff(f[c]))[::-1][:k - 1] + 1) if k > 1 else []
    return np.split(np.array(c), cuts)


def representative(pts, idx, f: np.ndarray, tol_f: float) -> int:
    """Among the poles of the upper half of the cluster's orders (the better fits), the one nearest
    their median frequency and damping (outliers out; damping, which scatters more, measured on its
    own scale)."""
    middle = np.median([pts[j][2] for j in idx])
    top = [i for i in idx if pts[i][2] >= middle]
    z_top = {i: -pts[i][0].real / abs(pts[i][0]) for i in top}
    f_med, z_med = np.median(f[top]), max(np.median(list(z_top.values())), 1e-12)
    return min(top, key=lambda i: (abs(f[i] / f_med - 1) / tol_f + abs(z_top[i] / z_med - 1), -pts[i][2]))
