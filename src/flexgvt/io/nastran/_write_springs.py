"""Writing springs and dampers: CELAS/CDAMP/CVISC/CBUSH/CBUSH1D values updated in a template deck
(shared properties split), CELAS2/CDAMP2, CVISC or CBUSH + CORD2R in a compact deck. Table springs:
CELAS1 + PELAS + PELAST (basic axes) or CBUSH + PBUSH + PBUSHT (turned axes), with their TABLED1s
(a scaled table as a new TABLED1); the linear rates written are the tables' slopes at zero."""

from __future__ import annotations

import copy

import numpy as np

from ...errors import ModelError
from ...model import Model
from ._common import Units
from ._read import BdfDeck
from ._spring_tables import TableIds, linear_rate
from ._write_common import Numbering, same


def _linear_rates(item, k: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Deck rates of spring ``item``: its stiffness, or a table component's slope at zero (k: deck units)."""
    k = k.copy()
    for c, (t, sc) in enumerate(zip(item.tables, item.table_scale)):
        if t is not None:
            k[c] = linear_rate(t, sc) / scale[c]
    return k


def _update_tables(bdf, item, card: str, elem, old_pid: int, tabs: TableIds, u: Units) -> None:
    """Point the PELAST / PBUSHT / PBUSH1D of ``elem`` (its property may have been split from
    ``old_pid``) at the spring's tables: the deck's where the scale is 1, else a scaled new TABLED1."""
    grounded = item.node_b is None
    mirror = (not grounded) if card == "CELAS1" else grounded
    tids = []
    for c, (t, sc) in enumerate(zip(item.tables, item.table_scale)):
        if t is None:
            tids.append(0)
            continue
        original = t.name.startswith("TABLED1 ") and abs(sc - 1.0) <= 1e-12
        tids.append(int(t.name.split()[1]) if original else tabs.add(t, sc, c >= 3, mirror, u))
    if card == "CBUSH1D":
        p = bdf.properties[elem.pid]
        p.spring_idt = p.spring_idc = p.spring_idtc = tids[0]
        return
    store = bdf.pelast if card == "CELAS1" else bdf.pbusht
    if elem.pid not in store:
        new = copy.deepcopy(store[old_pid])
        new.pid = elem.pid
        store[elem.pid] = new
    if card == "CELAS1":
        store[elem.pid].tknid = tids[int(elem.c1 or elem.c2) - 1]
    else:
        store[elem.pid].kn_tables = tids


def update_springs(bdf, model: Model, deck: BdfDeck, next_pid: int) -> None:
    """Write the model's springs into the template's cards; a property shared by springs that now
    differ is copied to new ids from ``next_pid``."""
    u, tmodel = deck.units, deck.model
    if len(model.springs) != len(deck.spring_sources):
        raise ModelError(f"write_bdf: the model has {len(model.springs)} springs, the template "
                         f"{len(deck.spring_sources)}; write without template=")
    prop_values: dict[int, tuple] = {}

    def prop_for(elem, values: tuple):
        nonlocal next_pid
        pid = elem.pid
        if pid in prop_values and not same(prop_values[pid], values):
            new = copy.deepcopy(bdf.properties[pid])
            new.pid = next_pid
            bdf.properties[next_pid] = new
            elem.pid = next_pid
            pid, next_pid = next_pid, next_pid + 1
        prop_values[pid] = values
        return bdf.properties[pid]

    tr, rot = u.force / u.length, u.moment
    tabs = TableIds(bdf)
    for item, old, (card, ident) in zip(model.springs, tmodel.springs, deck.spring_sources):
        if (item.node_a, item.node_b) != (old.node_a, old.node_b) or not np.allclose(item.frame, old.frame):
            raise ModelError(f"write_bdf: the spring from {card} {ident} changed its nodes or axes")
        scale = np.r_[[tr] * 3, [rot] * 3]
        k = np.asarray(item.stiffness) / scale
        c = np.asarray(item.damping) / scale
        elem = bdf.elements[ident]
        old_pid = getattr(elem, "pid", None)
        scales = tuple(item.table_scale)
        if item.nonlinear:
            k = _linear_rates(item, k, scale)
        if card in ("CELAS1", "CELAS2", "CDAMP1", "CDAMP2"):
            comp = int(elem.c1 or elem.c2) - 1
            if card == "CELAS1":
                prop_for(elem, (k[comp], scales[comp])).k = k[comp]
            elif card == "CELAS2":
                elem.k = k[comp]
            elif card == "CDAMP1":
                prop_for(elem, (c[comp],)).b = c[comp]
            else:
                elem.b = c[comp]
        elif card == "CVISC":
            p = prop_for(elem, (c[0], c[3]))
            p.ce, p.cr = c[0], c[3]
        elif card == "CBUSH1D":
            p = prop_for(elem, (k[0], c[0], scales[0]))
            p.k, p.c = k[0], c[0]
        elif card == "CBUSH":
            p = prop_for(elem, tuple(k) + tuple(c) + scales)
            if "K" in p.vars or np.any(k):
                p.Ki = list(k)
                if "K" not in p.vars:
                    p.vars.append("K")
            if "B" in p.vars or np.any(c):
                p.Bi = list(c)
                if "B" not in p.vars:
                    p.vars.append("B")
        if item.nonlinear:
            _update_tables(bdf, item, card, elem, old_pid, tabs, u)


def write_springs(bdf, model: Model, u: Units, xyz: dict[int, np.ndarray], ids: Numbering) -> None:
    """Every model spring: scalar cards in basic axes, a CVISC along its line, else a CBUSH in a CORD2R."""
    scale = np.r_[[u.force / u.length] * 3, [u.moment] * 3]
    tabs = TableIds(bdf)
    for s in model.springs:
        k = _linear_rates(s, np.asarray(s.stiffness) / scale, scale)
        c = np.asarray(s.damping) / scale
        nodes = [s.node_a, s.node_b]
        if np.allclose(s.frame, np.eye(3), atol=1e-12):
            for comp in range(6):
                if s.tables[comp] is not None:  # F = f(u1 - u2): a two-ended spring's table mirrors
                    tid = tabs.add(s.tables[comp], s.table_scale[comp], comp >= 3, s.node_b is not None, u)
                    bdf.add_pelas(ids.pid, k[comp])
                    bdf.add_pelast(ids.pid, tknid=tid)
                    bdf.add_celas1(ids.eid, ids.pid, nodes, c1=comp + 1, c2=comp + 1 if s.node_b else 0)
                    ids.pid, ids.eid = ids.pid + 1, ids.eid + 1
                elif k[comp]:
                    bdf.add_celas2(ids.eid, k[comp], nodes, c1=comp + 1, c2=comp + 1 if s.node_b else 0)
                    ids.eid += 1
                if c[comp]:
                    bdf.add_cdamp2(ids.eid, c[comp], nodes, c1=comp + 1, c2=comp + 1 if s.node_b else 0)
                    ids.eid += 1
            continue
        F = np.asarray(s.frame)
        line = None if s.node_b is None else xyz[s.node_b] - xyz[s.node_a]
        if line is not None and np.linalg.norm(line) > 1e-9:
            along = abs(F[:, 0] @ line) / np.linalg.norm(line) > 1 - 1e-12
            if along and not np.any(k) and not np.any(c[[1, 2, 4, 5]]):  # a dashpot along the line: CVISC
                bdf.add_pvisc(ids.pid, c[0], c[3])
                bdf.add_cvisc(ids.eid, ids.pid, nodes)
                ids.pid, ids.eid = ids.pid + 1, ids.eid + 1
                continue
            raise ModelError(f"write_bdf: spring between distinct nodes {s.node_a} and {s.node_b} with rotated axes "
                             "has no exact bulk data card (CBUSH needs coincident nodes); use basic axes")
        origin = xyz[s.node_a] / u.length
        bdf.add_cord2r(ids.cid, list(origin), list(origin + F[:, 2]), list(origin + F[:, 0]))
        bdf.add_pbush(ids.pid, list(k), list(c), [None] * 6)
        if s.nonlinear:  # U = U(GB) - U(GA): a grounded CBUSH's tables mirror
            kn = [0 if t is None else tabs.add(t, sc, comp >= 3, s.node_b is None, u)
                  for comp, (t, sc) in enumerate(zip(s.tables, s.table_scale))]
            bdf.add_pbusht(ids.pid, [0] * 6, [0] * 6, [0] * 6, kn)
        bdf.add_cbush(ids.eid, ids.pid, nodes, None, None, cid=ids.cid)
        ids.cid, ids.pid, ids.eid = ids.cid + 1, ids.pid + 1, ids.eid + 1
