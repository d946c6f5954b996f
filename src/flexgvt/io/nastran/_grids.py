"""Grids and coordinate systems: basic positions of the grids, local axes of CORD systems, element
orientation vectors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...errors import ModelError
from ._limits import MAX_COORDINATE_M
from ._parse import CardIndex, where_prefix

CARDS = ("GRID", "GRDSET", "CORD2R", "CORD2C", "CORD2S", "CORD1R", "CORD1C", "CORD1S")


def grid_positions(bdf, index: CardIndex, path: Path, length: float) -> tuple[list[int], np.ndarray]:
    """(sorted grid ids, basic positions [m] in that order) of a cross-referenced deck whose length
    unit is ``length`` m; raises at no grid, a non-finite position or one beyond MAX_COORDINATE_M."""
    nids = sorted(bdf.nodes)
    if not nids:
        raise ModelError(f"{path}: the deck has no GRID cards; a model needs nodes")
    xyz = np.array([bdf.nodes[n].get_position() for n in nids], float).reshape(-1, 3) * length
    bad = np.flatnonzero(~np.all(np.isfinite(xyz), axis=1))
    if len(bad):
        raise ModelError(f"{where_prefix(index, 'GRID', nids[bad[0]])}: coordinates {xyz[bad[0]] / length} are not "
                         f"finite ({len(bad)} grid(s)); give real numbers for X1-X3")
    far = np.flatnonzero(np.abs(xyz).max(axis=1) > MAX_COORDINATE_M)
    if len(far):
        raise ModelError(f"{where_prefix(index, 'GRID', nids[far[0]])}: basic coordinates {xyz[far[0]] / length} lie "
                         f"more than {MAX_COORDINATE_M:g} m from the origin ({len(far)} grid(s)); element lengths "
                         "of that size overflow the stiffness and mass products. Fix the coordinates, their CP "
                         "system or the deck's units")
    return nids, xyz


def coord_axes(bdf, cid: int | None, xyz_basic: np.ndarray, what: str) -> np.ndarray:
    """3x3 matrix whose columns are the axes of coordinate system ``cid`` at basic point ``xyz_basic``.

    Rectangular systems give constant axes; cylindrical (r, theta, z) and spherical (r, theta, phi)
    systems give the local axes at the point (Nastran's convention for displacement/load components).
    """
    if cid is None or cid == 0:
        return np.eye(3)
    coord = bdf.coords.get(cid)
    if coord is None:
        raise ModelError(f"{what}: coordinate system {cid} is not defined; add its CORD2R/CORD2C/CORD1R card")
    beta = np.asarray(coord.beta(), dtype=float)  # rows: local axes in basic
    kind = coord.Type
    if kind == "R":
        return beta.T.copy()
    local = beta @ (np.asarray(xyz_basic, float) - np.asarray(coord.origin, float))
    x, y, z = local
    if kind == "C":
        if math.hypot(x, y) < 1e-12 * max(1.0, abs(z)):
            raise ModelError(f"{what}: point lies on the axis of cylindrical system {cid}, where its r/theta "
                             "directions are undefined; use a rectangular system")
        t = math.atan2(y, x)
        axes = np.array([[math.cos(t), -math.sin(t), 0.0], [math.sin(t), math.cos(t), 0.0], [0.0, 0.0, 1.0]])
    elif kind == "S":
        r = math.sqrt(x * x + y * y + z * z)
        if math.hypot(x, y) < 1e-12 * max(1.0, r):
            raise ModelError(f"{what}: point lies on the polar axis of spherical system {cid}; use a rectangular "
                             "system")
        th, ph = math.acos(z / r), math.atan2(y, x)
        e_r = [math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)]
        e_t = [math.cos(th) * math.cos(ph), math.cos(th) * math.sin(ph), -math.sin(th)]
        e_p = [-math.sin(ph), math.cos(ph), 0.0]
        axes = np.array([e_r, e_t, e_p]).T
    else:  # pragma: no cover - pyNastran only has R, C, S
        raise ModelError(f"{what}: coordinate system {cid} of type {kind!r} is not supported")
    return beta.T @ axes



def basic_dofs(deck, nid: int, dofs: list[int], where: str, noun: str, what: str, remedy: str) -> set[int]:
    """DOF indices 0-5 in basic axes of the components ``dofs`` (0-5, in grid ``nid``'s displacement
    system CD). A CD whose named components do not line up with basic axes is refused with
    ``remedy`` (the message names the ``noun`` and ``what`` components)."""
    cd = deck.bdf.nodes[nid].cd
    if cd in (None, 0):
        return set(dofs)
    T = coord_axes(deck.bdf, cd, deck.xyz_deck[nid], f"{where} at {noun} {nid}")
    out: set[int] = set()
    for base in (0, 3):
        group = [d - base for d in dofs if base <= d < base + 3]
        if not group:
            continue
        P = T[:, group] @ T[:, group].T  # projector on the named directions, basic axes
        diag = np.diag(P)
        if not (np.allclose(P, np.diag(diag), atol=1e-9) and np.allclose(diag, np.round(diag), atol=1e-9)):
            raise ModelError(f"{where}: {noun} {nid} has CD={cd} and its {what} "
                             f"{''.join(str(base + g + 1) for g in group)} do not line up with basic axes; {remedy}")
        out.update(base + int(k) for k in np.flatnonzero(np.round(diag) == 1))
    return out


def frame_from_x(ex: np.ndarray) -> np.ndarray:
    """Orthonormal frame (columns) whose first axis is along ex."""
    x = ex / np.linalg.norm(ex)
    helper = np.eye(3)[int(np.argmin(np.abs(x)))]
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


def orientation_vector(deck, elem) -> np.ndarray:
    """Nastran v vector of a CBAR/CBEAM/CBUSH of ``deck`` (a Deck) in basic axes (deck length units)."""
    ga = elem.nodes[0] if hasattr(elem, "nodes") else elem.ga
    if elem.g0 not in (None, 0):
        return deck.xyz_deck[elem.g0] - deck.xyz_deck[ga]
    if elem.x is None or np.shape(elem.x) != (3,):
        given = "G0 = 0 (an integer in the X1 field is read as the node id G0)" if elem.g0 == 0 else \
            f"X1-X3 = {elem.x!r}"
        raise ModelError(f"{deck.at(elem.type, elem.eid)}: orientation {given} defines no direction; give X1, X2, "
                         "X3 as real numbers (0.0, not 0) or G0 as the id of a grid off the element axis")
    x = np.asarray(elem.x, float)
    offt = (getattr(elem, "offt", None) or "GGG") if elem.type != "CBUSH" else "GGG"
    if isinstance(offt, str) and offt[0] == "G":
        cd = deck.bdf.nodes[ga].cd
        x = coord_axes(deck.bdf, cd, deck.xyz_deck[ga], deck.at(elem.type, elem.eid)) @ x
    return x
