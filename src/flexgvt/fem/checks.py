"""Checks of a compiled system before it is solved: values that overflow the solvers, parts of
the model that nothing holds, DOFs that carry no mass, and what is at a DOF (for messages).

Each check raises a ModelError naming the entities (node, element, group ids) and the remedy, so
that no LinAlgError, NaN or silently empty result reaches the user.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ..errors import ModelError

# No structural model holds a stiffness [N/m, N m/rad], mass [kg] or inertia [kg m^2] entry near
# 1e40 in SI units (a 1e18 N/m clamp spring, 2e17 N/m for a 1 m^2 steel rod 1 um long, 1e18 kg m^2
# for 1e10 kg at 10 km). Such values come from a misplaced field (1e300 in a deck); squared or
# summed by the eigensolvers they overflow to inf and NaN.
VALUE_LIMIT = 1e40
COORDINATE_LIMIT = 1e10  # [m] (ten times the Moon's distance): rigid motions scale with it, squared

_DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")


def _ids(ids, count: int | None = None, first: int = 5) -> str:
    ids = [int(i) for i in ids]
    count = len(ids) if count is None else count
    shown = ", ".join(str(i) for i in ids[:first])
    return shown + (f", ... ({count} in all)" if count > first else "")


def _bad(values: np.ndarray, limit: float = VALUE_LIMIT) -> np.ndarray:
    """Rows of ``values`` (first axis) holding NaN, inf or a magnitude above ``limit``."""
    v = np.asarray(values, float).reshape(len(values), -1)
    with np.errstate(invalid="ignore"):
        return ~np.all(np.isfinite(v) & (np.abs(v) <= limit), axis=1)


_REMEDY = ("a value like that is a misplaced or mistyped field (e.g. 1e300 in a deck); correct it in the model "
           "or the input file")


def check_coordinates(node_ids: np.ndarray, xyz: np.ndarray, where: str) -> None:
    """Refuse node coordinates [m] that are not finite or lie beyond COORDINATE_LIMIT."""
    bad = _bad(xyz, COORDINATE_LIMIT)
    if np.any(bad):
        raise ModelError(f"{where}: node(s) {_ids(node_ids[bad])} lie beyond {COORDINATE_LIMIT:g} m from the "
                         f"origin: {_REMEDY}")


def check_values(system) -> None:
    """Refuse node coordinates, element values (each family's check_values) and applied loads that
    would overflow the solvers (NaN, inf, or beyond VALUE_LIMIT / COORDINATE_LIMIT), naming the first
    offending entity."""
    cm, where = system.cm, f"configuration '{system.config.name}'"
    check_coordinates(cm.node_ids, cm.xyz, where)
    for family in system.families:
        family.check_values(where, cm.node_ids)
    f = system.applied.reshape(-1, 6)
    bad = _bad(f)
    if np.any(bad):
        raise ModelError(f"{where}: the applied loads at node(s) {_ids(cm.node_ids[bad])} are not finite or exceed "
                         f"{VALUE_LIMIT:g} N: check the loads, gravity and masses there; {_REMEDY}")


def reduced_nodes(system, reduced_dofs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(node ids, DOF components 1-6) of reduced DOFs."""
    free = np.flatnonzero(system.dof_map >= 0)
    full = free[np.asarray(reduced_dofs, int)]
    return system.cm.node_ids[full // 6], full % 6 + 1


def _at_nodes(system, nodes: np.ndarray) -> str:
    """What is attached to storage indices ``nodes`` (each family's describe)."""
    parts = [text for text in (family.describe(nodes) for family in system.families) if text]
    return "; attached there: " + ", ".join(parts) if parts else ""


def check_matrix(system, A: sp.spmatrix, what: str) -> None:
    """Raise a ModelError if the assembled reduced matrix ``A`` ('stiffness', 'mass') holds NaN, inf
    or entries beyond VALUE_LIMIT, naming the nodes and DOFs where they are."""
    A = A.tocoo()
    with np.errstate(invalid="ignore"):
        bad = ~(np.isfinite(A.data) & (np.abs(A.data) <= VALUE_LIMIT))
    if not np.any(bad):
        return
    dofs = np.unique(np.r_[A.row[bad], A.col[bad]])
    ids, comps = reduced_nodes(system, dofs)
    nodes_u = np.unique(ids)
    listed = ", ".join(f"{i} {_DOF_NAMES[c - 1]}" for i, c in zip(ids[:6], comps[:6]))
    raise ModelError(f"configuration '{system.config.name}': the {what} matrix has entries that are NaN, infinite or "
                     f"beyond {VALUE_LIMIT:g} at {len(dofs)} DOF(s) of {len(nodes_u)} node(s) ({listed}"
                     f"{', ...' if len(dofs) > 6 else ''})"
                     f"{_at_nodes(system, system.model.index_of(nodes_u[:20]))}. Check the material, section, "
                     "mass and spring values and the node coordinates there for a misplaced or absurd value")


def check_connected(system) -> None:
    """Raise a ModelError if the model falls apart into parts and one of them is free: connected by
    no element, spring, link, cord or constraint to a part that is held (fixed or prescribed DOFs,
    grounded springs, cords to their anchors). Nodes with nothing attached and no mass are inert
    (orientation or output grids) and left out; a single free part is a free-free structure."""
    cm, n = system.cm, system.n_nodes
    pairs = [family.connections() for family in system.families]
    a, b = [p[:, 0] for p in pairs], [p[:, 1] for p in pairs]
    dep = np.flatnonzero(cm.links >= 0)
    a.append(dep)
    b.append(cm.links[dep])
    ip = cm.interp
    for k in range(len(ip)):
        a.append(np.full(len(ip.nodes[k]), ip.reference[k]))
        b.append(ip.nodes[k])
    for d, (dofs, _) in zip(cm.mpc_dependent, cm.mpc_terms):
        a.append(np.full(len(dofs), d // 6))
        b.append(np.asarray(dofs) // 6)
    a, b = np.concatenate(a).astype(int), np.concatenate(b).astype(int)
    graph = sp.coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    n_parts, label = connected_components(graph, directed=False)
    if n_parts == 1:
        return
    held = np.zeros(n, bool)
    held[np.flatnonzero(system.fixed.reshape(n, 6).any(axis=1))] = True
    for family in system.families:
        held[family.held_nodes()] = True
    used = np.zeros(n, bool)
    used[a] = used[b] = True
    for family in system.families:
        used[family.used_nodes()] = True
    used |= held
    parts = [np.flatnonzero((label == p) & used) for p in range(n_parts)]
    parts = [p for p in parts if len(p)]
    if len(parts) <= 1:
        return
    free = [p for p in parts if not held[p].any()]
    if not free:
        return
    part = min(free, key=len) if len(free) < len(parts) else sorted(parts, key=len)[0]
    rest = n - len(part)
    raise ModelError(
        f"configuration '{system.config.name}': the model falls apart into {len(parts)} parts and a part of "
        f"{len(part)} node(s) (ids {_ids(cm.node_ids[part])}) is free: no element, spring, rigid link, constraint "
        "or cord connects it to the rest of the model, and no fixed DOF, grounded spring or cord holds it "
        f"(the other {rest} node(s) include ids {_ids(cm.node_ids[np.setdiff1d(np.arange(n), part)], first=3)}). "
        "Connect it (a beam, spring or rigid link; check for duplicated nodes at the joint), fix or suspend it, "
        "or remove it from the model")
