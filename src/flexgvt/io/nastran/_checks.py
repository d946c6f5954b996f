"""Checks of a parsed deck before any card is translated: ids in Nastran's range, real fields finite
and bounded, and every reference (grid, property, material, coordinate system) defined. The cards
whose property or material must exist come from the card families (see _registry)."""

from __future__ import annotations

import math
from pathlib import Path

from ...errors import ModelError
from ._limits import MAX_ID, MAX_VALUE, bad_reals, field_label
from ._parse import CardIndex
from ._parse import where_prefix as at

TWO_NODE_CARDS = ("CBAR", "CBEAM", "CROD", "CONROD", "CTUBE")


def _element_nodes(elem) -> list:
    """Node fields of an element as given (pyNastran's node_ids asserts on a blank or 0 one)."""
    nodes = getattr(elem, "nodes", None)
    if nodes is None:
        try:
            nodes = elem.node_ids
        except Exception:  # noqa: BLE001
            nodes = []
    return [n if isinstance(n, int) or n is None else getattr(n, "nid", n) for n in list(nodes)]



def _tables(bdf):
    return (("node", {k: v for k, v in bdf.nodes.items()}), ("element", bdf.elements), ("mass element", bdf.masses),
            ("rigid element", bdf.rigid_elements), ("property", bdf.properties),
            ("property", getattr(bdf, "properties_mass", {}) or {}), ("material", bdf.materials),
            ("coordinate system", {k: v for k, v in bdf.coords.items() if k != 0}))

def _listing(path: Path, problems: list[str]) -> str:
    text = "; ".join(problems[:8]) + ("; ..." if len(problems) > 8 else "")
    return text if text.startswith(str(path)) else f"{path}: {text}"

def check_ids_and_values(bdf, index: CardIndex, path: Path) -> None:
    """Ids within Nastran's 1..99999999 and real fields finite and within MAX_VALUE, on every card
    flexgvt reads (before any is used: an id of 1e20 or a field of 1e300 would otherwise fail
    far from the card, or overflow in the eigensolver)."""
    problems = []
    for label, table in _tables(bdf):
        for ident, card in table.items():
            if not isinstance(ident, int) or not 0 < ident <= MAX_ID:
                name = getattr(card, "type", "?")
                problems.append(f"{at(index, name, ident)}: {label} id {ident} is outside Nastran's range 1 to "
                                f"{MAX_ID}; renumber it")
    if problems:
        raise ModelError(_listing(path, problems))
    cards = [c for _, table in _tables(bdf) for c in table.values()]
    for group in (bdf.spcs, bdf.mpcs, bdf.loads, getattr(bdf, "load_combinations", {}) or {}, bdf.methods,
                  getattr(bdf, "cMethods", {}) or {}):
        for value in group.values():
            cards.extend(value if isinstance(value, list) else [value])
    for card in cards:
        bad = bad_reals(card)
        if bad:
            k, v = bad[0]
            ident = next((getattr(card, a) for a in ("eid", "nid", "pid", "mid", "cid", "sid", "conid")
                          if isinstance(getattr(card, a, None), int)), "?")
            why = "is not a finite number" if not math.isfinite(v) else \
                f"exceeds {MAX_VALUE:g} in magnitude (stiffness and mass products of such values overflow)"
            problems.append(f"{at(index, card.type, ident)}: {field_label(card, k)} = {v!r} {why}")
    if problems:
        raise ModelError(_listing(path, problems) + ". Fix the value (or the deck's unit system)")


def check_references(bdf, index: CardIndex, path: Path, needs_property: frozenset[str],
                     needs_material: frozenset[str]) -> None:
    miss: list[str] = []
    nodes, coords = bdf.nodes, bdf.coords
    for nid, node in nodes.items():
        for label, cid in (("CP", node.cp), ("CD", node.cd)):
            if cid not in (None, 0, -1) and cid not in coords:
                miss.append(f"{at(index, 'GRID', nid)} uses {label}={cid} but coordinate system {cid} is not defined")
    for cid, coord in coords.items():
        rid = getattr(coord, "rid", 0)
        if rid not in (None, 0) and rid not in coords:
            miss.append(f"{at(index, coord.type, cid)} refers to RID={rid}, which is not defined")
        for g in (getattr(coord, "g1", None), getattr(coord, "g2", None), getattr(coord, "g3", None)):
            if coord.type.startswith("CORD1") and g is not None and g not in nodes:
                miss.append(f"{at(index, coord.type, cid)} refers to node {g}, which is not defined")
    for eid, elem in bdf.elements.items():
        ids = _element_nodes(elem)
        if elem.type in TWO_NODE_CARDS and (len(ids) < 2 or any(n in (None, 0) for n in ids[:2])):
            miss.append(f"{at(index, elem.type, eid)} has GA/GB = {ids[:2]}; give both end grids (ids above 0)")
            continue
        if ids and all(n in (None, 0) for n in ids):
            miss.append(f"{at(index, elem.type, eid)} connects no grid (all node fields blank or 0)")
            continue
        for n in (n for n in ids if n not in (None, 0)):
            if n not in nodes:
                miss.append(f"{at(index, elem.type, eid)} refers to node {n}, which is not defined")
        pid = getattr(elem, "pid", None)
        if elem.type in needs_property and pid not in bdf.properties:
            miss.append(f"{at(index, elem.type, eid)} refers to property {pid}, which is not defined")
        g0 = getattr(elem, "g0", None)
        if elem.type in ("CBAR", "CBEAM", "CBUSH") and g0 not in (None, 0) and g0 not in nodes:
            miss.append(f"{at(index, elem.type, eid)} orientation node G0={g0} is not defined")
        if elem.type in needs_material and elem.mid not in bdf.materials:
            miss.append(f"{at(index, elem.type, eid)} refers to material {elem.mid}, which is not defined")
        cid = getattr(elem, "cid", None)
        if elem.type in ("CBUSH",) and cid not in (None, -1, 0) and cid not in coords:
            miss.append(f"{at(index, elem.type, eid)} refers to coordinate system {cid}, which is not defined")
    for eid, elem in bdf.masses.items():
        refs = [elem.nid] if hasattr(elem, "nid") else [n for n in getattr(elem, "nodes", []) if n not in (None, 0)]
        for n in refs:
            if n not in nodes:
                miss.append(f"{at(index, elem.type, eid)} refers to node {n}, which is not defined")
        if getattr(elem, "cid", 0) not in (None, -1, 0) and elem.cid not in coords:
            miss.append(f"{at(index, elem.type, eid)} refers to coordinate system {elem.cid}, which is not defined")
    for eid, elem in bdf.rigid_elements.items():
        try:
            refs = list(elem.independent_nodes) + list(elem.dependent_nodes)
        except Exception as exc:  # noqa: BLE001 - pyNastran asserts on blank or 0 node fields
            miss.append(f"{at(index, elem.type, eid)} has a blank or invalid node field ({type(exc).__name__}: "
                        f"{(str(exc).splitlines() or [''])[0][:80]})")
            continue
        for n in refs:
            if n not in nodes:
                miss.append(f"{at(index, elem.type, eid)} refers to node {n}, which is not defined")
    for pid, prop in bdf.properties.items():
        mid = getattr(prop, "mid", None)
        if prop.type in needs_material and mid not in bdf.materials:
            miss.append(f"{at(index, prop.type, pid)} refers to material {mid}, which is not defined")
    if miss:
        raise ModelError(f"{path}: missing references: " + "; ".join(miss[:12]) +
                         ("; ..." if len(miss) > 12 else "") + ". Add the missing cards or fix the ids")

