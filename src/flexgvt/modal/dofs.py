"""Labelled degrees of freedom: an (n, 2) integer array of (point or node id, direction code).

Direction codes are the UFF ones: +-1, +-2, +-3 translations X, Y, Z; +-4, +-5, +-6 rotations
about X, Y, Z; 0 a scalar channel. A negative code reads the opposite way, so the DOFs (12, -3)
and (12, 3) are the same physical DOF with opposite signs: `common_dofs` aligns them with -1.
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError

AXES = ("", "X", "Y", "Z", "RX", "RY", "RZ")


def as_dofs(dofs, where: str = "dofs") -> np.ndarray:
    """``dofs`` checked as an (n, 2) array of (id, direction code -6..6); None or empty -> (0, 2)."""
    if dofs is None:
        return np.zeros((0, 2), int)
    a = np.asarray(dofs)
    if a.size == 0:
        return a.reshape(0, 2) if a.ndim == 2 and a.shape[1] == 2 else np.zeros((0, 2), int)
    if a.ndim != 2 or a.shape[1] != 2:
        raise ModelError(f"{where}: expected an (n, 2) array of (point id, direction code), got shape {a.shape}")
    if not np.all(np.isfinite(a)) or np.any(np.round(a) != a) or np.any(np.abs(a[:, 1]) > 6):
        raise ModelError(f"{where}: ids must be integers and direction codes integers in -6..6 (UFF: +-1..3 "
                         "translations, +-4..6 rotations, 0 scalar)")
    return a


def dof_array(ids, directions) -> np.ndarray:
    """(n, 2) DOFs from ids (n,) and direction codes (n,) or one code for all."""
    ids = np.atleast_1d(np.asarray(ids, int))
    return as_dofs(np.column_stack([ids, np.broadcast_to(np.asarray(directions, int), ids.shape)]))


def dof_names(dofs) -> list[str]:
    """'12+Z', '3-RX', '7' (scalar) for each DOF."""
    return [f"{int(i)}{'+' if d > 0 else '-'}{AXES[abs(int(d))]}" if d else f"{int(i)}"
            for i, d in as_dofs(dofs)]


def _keys(dofs: np.ndarray, where: str) -> dict:
    keys = {}
    for k, (i, d) in enumerate(dofs.astype(np.int64)):
        key = (int(i), abs(int(d)))
        if key in keys:
            raise ModelError(f"{where}: DOF {dof_names(dofs[[k]])[0]} appears twice (rows {keys[key]} and {k}); "
                             "DOF labels must be unique to align mode sets by them")
        keys[key] = k
    return keys


def common_dofs(a, b) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ia, ib, sign): rows of ``a`` and ``b`` holding the same physical DOF, in the order of ``a``, and
    the sign (+-1) that turns b's reading into a's (a DOF read the opposite way has the opposite code)."""
    a, b = as_dofs(a, "first DOF set"), as_dofs(b, "second DOF set")
    kb = _keys(b, "second DOF set")
    _keys(a, "first DOF set")
    ia, ib = [], []
    for k, (i, d) in enumerate(a.astype(np.int64)):
        j = kb.get((int(i), abs(int(d))))
        if j is not None:
            ia.append(k)
            ib.append(j)
    ia, ib = np.array(ia, int), np.array(ib, int)
    sign = np.where(np.sign(a[ia, 1]) * np.sign(b[ib, 1]) < 0, -1.0, 1.0) if len(ia) else np.zeros(0)
    return ia, ib, sign
