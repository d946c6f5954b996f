"""Writing concentrated masses: CONM2/CONM1 values updated in a template deck, CONM2 in a compact deck."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import Model
from ._common import Units
from ._grids import coord_axes
from ._read import BdfDeck
from ._write_common import Numbering, same


def update_masses(bdf, model: Model, deck: BdfDeck, notes: list[str]) -> None:
    """Write the model's masses into the template's CONM2/CONM1 cards (one per deck mass, same nodes)."""
    u, w, tmodel = deck.units, deck.wtmass, deck.model
    if len(model.masses) != len(deck.mass_sources):
        raise ModelError(f"write_bdf: the model has {len(model.masses)} concentrated masses, the template "
                         f"{len(deck.mass_sources)}; write without template=")
    for item, old, (card, ident) in zip(model.masses, tmodel.masses, deck.mass_sources):
        if item.node != old.node:
            raise ModelError(f"write_bdf: concentrated mass from {card} {ident} moved from node {old.node} to "
                             f"{item.node}")
        if same(item.mass, old.mass) and same(item.offset, old.offset) and same(item.inertia, old.inertia):
            continue
        if card.startswith("NSM"):
            notes.append(f"mass lumped from the NSM of {card[4:]} {ident} changed; NSM is not written back")
            continue
        elem = bdf.masses[ident]
        node_xyz = deck.model.xyz[deck.model.index_of([item.node])[0]] / u.length
        m = item.mass / (u.mass * w)
        r = np.asarray(item.offset) / u.length
        J = np.asarray(item.inertia) / (u.inertia * w)
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


def write_masses(bdf, model: Model, u: Units, ids: Numbering) -> None:
    """Every model mass as a CONM2 in basic axes."""
    for item in model.masses:
        J = np.asarray(item.inertia) / u.inertia
        bdf.add_conm2(ids.eid, item.node, item.mass / u.mass, cid=0, X=list(np.asarray(item.offset) / u.length),
                      I=[J[0, 0], -J[1, 0], J[1, 1], -J[2, 0], -J[2, 1], J[2, 2]])
        ids.eid += 1
