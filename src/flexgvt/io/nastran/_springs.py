"""Springs and dampers: CELAS1/2, CDAMP1/2 (scalar, in the grids' displacement axes), CVISC (along
the line of its nodes), CBUSH (in CID or element axes; rigid arms to the spring location)."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import Model
from ._deck import Deck, Family, Findings, Parts
from ._elements import EndNodes
from ._grids import coord_axes, frame_from_x, orientation_vector

CARDS = ("CELAS1", "CELAS2", "CDAMP1", "CDAMP2", "CVISC", "CBUSH", "PELAS", "PDAMP", "PVISC", "PBUSH")


def read_springs(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """Every spring and damper element as a model spring (6 stiffness and damping values in a frame)."""
    reader = _Springs(deck, model, log)
    reader.read()
    return Parts(spring_sources=tuple(reader.sources), end_nodes=reader.ends.nodes,
                 end_links=tuple(reader.ends.links))


class _Springs:
    """The spring family's reading of one deck."""

    def __init__(self, deck: Deck, model: Model, log: Findings) -> None:
        self.deck, self.model, self.log = deck, model, log
        self.ends = EndNodes(deck, model)
        self.sources: list[tuple[str, int]] = []

    def at(self, name: str, ident) -> str:
        return self.deck.at(name, ident)

    def _scalar(self, elem, value_stiff: float, value_damp: float) -> None:
        """CELAS/CDAMP: a scalar spring between (G1, C1) and (G2, C2) in the nodes' displacement axes."""
        bdf, u = self.deck.bdf, self.deck.units
        where = self.at(elem.type, elem.eid)
        n1, n2 = (list(elem.nodes) + [None, None])[:2]
        c1, c2 = int(elem.c1 or 0), int(elem.c2 or 0)
        ends = [(n, c) for n, c in ((n1, c1), (n2, c2)) if n not in (None, 0)]
        if not ends or any(not 1 <= c <= 6 for _, c in ends):
            self.log.skip(f"{elem.type} (scalar points or component 0)", elem.eid)
            return
        comps = {c for _, c in ends}
        axes = [coord_axes(bdf, bdf.nodes[n].cd, self.deck.xyz_deck[n], where) for n, _ in ends]
        c = ends[0][1]
        if len(comps) > 1 or (len(ends) == 2 and not np.allclose(axes[0][:, (c - 1) % 3], axes[1][:, (c - 1) % 3],
                                                                 atol=1e-9)):
            self.log.skip(f"{elem.type} (components along different directions)", elem.eid)
            return
        rot = c > 3
        k = np.zeros(6)
        d = np.zeros(6)
        k[c - 1] = value_stiff * (u.moment if rot else u.force / u.length)
        d[c - 1] = value_damp * (u.moment if rot else u.force / u.length)
        a, b = (ends[0][0], ends[1][0]) if len(ends) == 2 else (ends[0][0], None)
        self._add_spring(where, a, b, k, d, axes[0], (elem.type, int(elem.eid)))

    def _add_spring(self, where, a, b, k, d, frame, source) -> None:
        try:
            self.model.add_spring(a, b, stiffness=k, damping=d, frame=frame, id=source[1])
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.sources.append(source)

    def read(self) -> None:
        bdf, u = self.deck.bdf, self.deck.units
        for eid, elem in sorted(bdf.elements.items()):
            t = elem.type
            where = self.at(t, eid)
            if t in ("CELAS1", "CELAS2"):
                prop = bdf.properties[elem.pid] if t == "CELAS1" else None
                k = prop.k if prop is not None else elem.k
                ge = prop.ge if prop is not None else elem.ge
                if ge:
                    self.log.note(f"{where}: structural damping GE={ge} is not modelled")
                self._scalar(elem, float(k), 0.0)
            elif t in ("CDAMP1", "CDAMP2"):
                b = bdf.properties[elem.pid].b if t == "CDAMP1" else elem.b
                self._scalar(elem, 0.0, float(b))
            elif t == "CVISC":
                prop = bdf.properties[elem.pid]
                n1, n2 = elem.nodes
                ex = self.deck.xyz[n2] - self.deck.xyz[n1]
                if np.linalg.norm(ex) == 0:
                    raise ModelError(f"{where}: the two nodes of a CVISC coincide; its line of action is undefined")
                frame = frame_from_x(ex)
                d = np.array([prop.ce * u.force / u.length, 0, 0, (prop.cr or 0.0) * u.moment, 0, 0])
                self._add_spring(where, n1, n2, np.zeros(6), d, frame, ("CVISC", int(eid)))
            elif t == "CBUSH":
                self.read_cbush(elem, where)

    def read_cbush(self, elem, where) -> None:
        bdf, u = self.deck.bdf, self.deck.units
        prop = bdf.properties[elem.pid]
        ga, gb = (list(elem.nodes) + [None])[:2]
        gb = None if gb in (None, 0) else gb
        coincident = gb is None or np.linalg.norm(self.deck.xyz_deck[gb] - self.deck.xyz_deck[ga]) <= 1e-4
        if not coincident and getattr(elem, "ocid", -1) not in (None, -1):
            self.log.skip("CBUSH (spring location given in OCID)", elem.eid)
            return
        if elem.cid not in (None, -1):
            frame = coord_axes(bdf, elem.cid, self.deck.xyz_deck[ga], where)
        elif coincident:
            raise ModelError(f"{where}: a CBUSH on coincident nodes (or grounded) needs CID; Nastran rejects it too. "
                             "Give CID = 0 for basic axes")
        else:  # element axes: x from GA to GB, y from the orientation vector
            v = None if elem.g0 in (None, 0) and (elem.x is None or any(c is None for c in elem.x)) \
                else orientation_vector(self.deck, elem)
            ex = self.deck.xyz_deck[gb] - self.deck.xyz_deck[ga]
            ex = ex / np.linalg.norm(ex)
            ez = None if v is None else np.cross(ex, v)
            if ez is None or np.linalg.norm(ez) <= 1e-8 * np.linalg.norm(v):
                raise ModelError(f"{where}: a CBUSH between distinct points without CID needs an orientation vector "
                                 "(X1-X3 or G0) off the line GA-GB")
            ez = ez / np.linalg.norm(ez)
            frame = np.column_stack([ex, np.cross(ez, ex), ez])
        if not coincident:  # rigid arms from GA and GB to the spring location, S along GA-GB
            s_loc = 0.5 if getattr(elem, "s", None) is None else float(elem.s)
            at = self.deck.xyz_deck[ga] + s_loc * (self.deck.xyz_deck[gb] - self.deck.xyz_deck[ga])
            ga = self.ends.add(int(ga), at, "123456", ("CBUSH", int(elem.eid), "A"))
            gb = self.ends.add(int(gb), at, "123456", ("CBUSH", int(elem.eid), "B"))
        def six(values):
            vals = list(values or [])
            return np.array([float(v) if v is not None else 0.0 for v in (vals + [0.0] * 6)[:6]])
        k = six(getattr(prop, "Ki", None))
        b = six(getattr(prop, "Bi", None))
        if any(getattr(prop, "GEi", None) or []):
            if any(v for v in prop.GEi if v):
                self.log.note(f"{where}: structural damping GE of PBUSH {prop.pid} is not modelled")
        scale = np.r_[[u.force / u.length] * 3, [u.moment] * 3]
        self._add_spring(where, ga, gb, k * scale, b * scale, frame, ("CBUSH", int(elem.eid)))


FAMILY = Family("springs", CARDS, read_springs, needs_property=("CELAS1", "CDAMP1", "CVISC", "CBUSH"))
