"""Rods: CROD + PROD (one group per property) and CONROD (one group per set of equal values)."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import Model
from ._deck import Deck, Family, Findings, Parts
from ._elements import BeamSource, lumped_nsm


def read_rods(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """Rod groups (axial and torsion stiffness) on the MAT1s read before; NSM lumped at the ends."""
    bdf, u = deck.bdf, deck.units
    beams: dict[str, BeamSource] = {}
    element_ids: dict[int, int] = {}
    mass_sources: list[tuple[str, int]] = []
    groups: dict[tuple, list] = {}
    for eid, elem in sorted(bdf.elements.items()):
        if elem.type == "CROD":
            prop = bdf.properties[elem.pid]
            if prop.type != "PROD":
                log.skip(f"CROD with {prop.type}", eid)
                continue
            groups.setdefault(("PROD", prop.pid, prop.mid, prop.A, prop.j, prop.nsm), []).append(elem)
        elif elem.type == "CONROD":
            groups.setdefault(("CONROD", 0, elem.mid, elem.A, elem.j, elem.nsm), []).append(elem)
    for (ptype, pid, mid, area, j, nsm), elems in groups.items():
        where = deck.at(ptype, pid) if ptype == "PROD" else deck.at("CONROD", elems[0].eid)
        mat = parts.materials.get(mid)
        if mat is None:
            for e in elems:
                log.skip(f"{e.type} on {bdf.materials[mid].type}", e.eid)
            continue
        pairs = np.array([e.node_ids[:2] for e in elems], int)
        name = f"PROD_{pid}" if ptype == "PROD" else f"CONROD_{elems[0].eid}"
        try:
            ids = model.add_rods(pairs, mat, float(area) * u.length ** 2,
                                 torsion_constant=float(j or 0.0) * u.length ** 4, mass=deck.mass, name=name)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        eids = tuple(int(e.eid) for e in elems)
        element_ids.update(dict(zip(eids, (int(i) for i in ids))))
        beams[name] = BeamSource(name, elems[0].type, ptype, int(pid), int(mid), eids, (0.0, 1.0))
        if nsm:
            mass_sources += lumped_nsm(deck, model, log, deck.xyz.__getitem__, pairs, (float(nsm),) * 2, ptype, pid)
    return Parts(beams=beams, element_ids=element_ids, mass_sources=tuple(mass_sources))


FAMILY = Family("rods", ("CROD", "CONROD", "PROD"), read_rods, needs_property=("CROD",),
                needs_material=("CONROD", "PROD"))
