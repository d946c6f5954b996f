"""Writing concentrated masses: CONM2/CONM1/CMASS1/CMASS2 values updated in a template deck, CONM2 in a
compact deck."""

from __future__ import annotations

import copy

import numpy as np

from ...errors import ModelError
from ...model import Model
from ._common import Units
from ._grids import coord_axes
from ._read import BdfDeck
from ._write_common import Numbering, same


def update_masses(bdf, model: Model, deck: BdfDeck, notes: list[str]) -> None:
    """Write the model's masses into the template's CONM2/CONM1/CMASS1/CMASS2 cards (one per deck mass,
    same nodes)."""
    u, w, tmodel = deck.units, deck.wtmass, deck.model
    if len(model.masses) != len(deck.mass_sources):
        raise ModelError(f"write_bdf: the model has {len(model.masses)} concentrated masses, the template "
                         f"{len(deck.mass_sources)}; write without template=")
    pmass: dict[int, float] = {}  # PMASS id -> the mass written into it (a shared PMASS is split)
    next_pid = [max(list(bdf.properties) + list(getattr(bdf, "properties_mass", {}) or {}) + [0]) + 1]
    for item, old, (card, ident) in zip(model.masses, tmodel.masses, deck.mass_sources):
        if item.node != old.node:
            raise ModelError(f"write_bdf: concentrated mass from {card} {ident} moved from node {old.node} to "
                             f"{item.node}")
        unchanged = same(item.mass, old.mass) and same(item.offset, old.offset) and same(item.inertia, old.inertia)
        if card == "CMASS1" and unchanged:  # keeps its PMASS value: a PMASS it shares with a changed one is split
            elem = bdf.masses[ident]
            _pmass_for(bdf, elem, float(deck.bdf.properties_mass[elem.pid].mass), pmass, next_pid)
        if unchanged:
            continue
        if card.startswith("NSM"):
            notes.append(f"mass lumped from the NSM of {card[4:]} {ident} changed; NSM is not written back")
            continue
        elem = bdf.masses[ident]
        node_xyz = deck.model.xyz[deck.model.index_of([item.node])[0]] / u.length
        m = item.mass / (u.mass * w)
        r = np.asarray(item.offset) / u.length
        J = np.asarray(item.inertia) / (u.inertia * w)
        if card in ("CMASS1", "CMASS2"):
            _update_scalar_mass(bdf, elem, node_xyz, m, r, J, pmass, next_pid)
            continue
        if card == "CONM2":
            if elem.cid == -1:
                elem.X = node_xyz + r
                T = np.eye(3)
            else:
                T = coord_axes(bdf, elem.cid, node_xyz, f"CONM2 {ident}")
                elem.X = T.T @ r
            Jl = T.T @ J @ T
            elem.mass = m
            elem.I = np.array([Jl[0, 0], -Jl[1, 0], Jl[1, 1], -Jl[2, 0], -Jl[2, 1], Jl[2, 2]])
        else:  # CONM1
            T = coord_axes(bdf, elem.cid, node_xyz, f"CONM1 {ident}")
            S = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
            M = np.zeros((6, 6))
            M[:3, :3] = m * np.eye(3)
            M[:3, 3:] = -m * S
            M[3:, :3] = m * S
            M[3:, 3:] = J - m * S @ S
            T6 = np.zeros((6, 6))
            T6[:3, :3] = T6[3:, 3:] = T
            elem.mass_matrix = T6.T @ M @ T6


def _update_scalar_mass(bdf, elem, node_xyz: np.ndarray, m: float, r: np.ndarray, J: np.ndarray,
                        pmass: dict[int, float], next_pid: list[int]) -> None:
    """A CMASS1/CMASS2 on rotation C1 of its grid holds the inertia m e e^T about that axis of the grid's
    CD system (see the reader): write m back, or refuse a mass that no longer has that form."""
    where = f"write_bdf: {elem.type} {elem.eid}"
    n1, c1 = int(elem.nodes[0]), int(elem.c1)
    axis = coord_axes(bdf, bdf.nodes[n1].cd, node_xyz, where)[:, c1 - 4]
    value = float(axis @ J @ axis)
    scale = max(float(np.abs(J).max()), 1e-300)
    if m != 0.0 or np.any(r != 0.0) or not np.allclose(J, value * np.outer(axis, axis), rtol=0.0, atol=1e-9 * scale):
        raise ModelError(f"{where}: the updated mass is no longer an inertia about component {c1} of grid {n1} "
                         "(a scalar mass holds only that); write without template=")
    if elem.type == "CMASS2":
        elem.mass = value
        return
    _pmass_for(bdf, elem, value, pmass, next_pid)


def _pmass_for(bdf, elem, value: float, pmass: dict[int, float], next_pid: list[int]) -> None:
    """Write ``value`` into the PMASS of CMASS1 ``elem``: its own, or a copy with a new id when another
    CMASS1 sharing it was given a different value."""
    pid = elem.pid
    if pid in pmass and not np.isclose(pmass[pid], value, rtol=1e-9, atol=0.0):
        new = copy.deepcopy(bdf.properties_mass[pid])
        new.pid = next_pid[0]
        bdf.properties_mass[new.pid] = new
        elem.pid, pid = new.pid, new.pid
        next_pid[0] += 1
    elif pid not in pmass:  # PMASS cards are shared with the template deck (see _copy_deck): write a copy
        bdf.properties_mass[pid] = copy.deepcopy(bdf.properties_mass[pid])
    pmass[pid] = value
    bdf.properties_mass[pid].mass = value


def write_masses(bdf, model: Model, u: Units, ids: Numbering) -> None:
    """Every model mass as a CONM2 in basic axes."""
    for item in model.masses:
        J = np.asarray(item.inertia) / u.inertia
        bdf.add_conm2(ids.eid, item.node, item.mass / u.mass, cid=0, X=list(np.asarray(item.offset) / u.length),
                      I=[J[0, 0], -J[1, 0], J[1, 1], -J[2, 0], -J[2, 1], J[2, 2]])
        ids.eid += 1
