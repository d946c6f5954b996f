"""Springs and dampers: CELAS1/2, CDAMP1/2 (scalar, in the grids' displacement axes), CVISC (along
the line of its nodes), CBUSH (in CID or element axes; rigid arms to the spring location), CBUSH1D
(axial, along GA-GB or CID's x). Nonlinear springs: PELAST TKNID (CELAS1), PBUSHT KN (CBUSH) and
PBUSH1D SPRING TABLE (CBUSH1D) force-deflection TABLED1s (see _spring_tables)."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import Model
from ._deck import Deck, Family, Findings, Parts
from ._elements import EndNodes
from ._grids import coord_axes, frame_from_x, orientation_vector
from ._spring_tables import linear_rate, read_table

CARDS = ("CELAS1", "CELAS2", "CDAMP1", "CDAMP2", "CVISC", "CBUSH", "CBUSH1D", "PELAS", "PDAMP", "PVISC", "PBUSH",
         "PBUSH1D", "PBUSHT", "PELAST", "TABLED1")


def read_springs(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """Every spring and damper element as a model spring (6 stiffness and damping values in a frame)."""
    reader = _Springs(deck, model, log)
    reader.read()
    reader.note_unused_tables()
    return Parts(spring_sources=tuple(reader.sources), end_nodes=reader.ends.nodes,
                 end_links=tuple(reader.ends.links))


class _Springs:
    """The spring family's reading of one deck."""

    def __init__(self, deck: Deck, model: Model, log: Findings) -> None:
        self.deck, self.model, self.log = deck, model, log
        self.ends = EndNodes(deck, model)
        self.sources: list[tuple[str, int]] = []
        self.used_tables: set[int] = set()

    def at(self, name: str, ident) -> str:
        return self.deck.at(name, ident)

    def _table(self, tid: int, component: int, mirror: bool, where: str, rate: float | None):
        """TABLED1 ``tid`` for spring component ``component`` (1..6); rate: the card's linear rate
        [SI] (noted when it is not the table's slope at zero, which a linear Nastran solution uses)."""
        table = read_table(self.deck, int(tid), component > 3, mirror, where)
        self.used_tables.add(int(tid))
        slope = linear_rate(table, 1.0)
        sides = table.evaluate(np.array([-1e-12, 1e-12]) * max(np.abs(table.x).max(), 1.0))[1]  # a knot at 0
        if rate is not None and not np.any(np.isclose(rate, sides, rtol=1e-6, atol=0)):
            self.log.note(f"{where}: component {component}'s linear rate {rate:g} (SI) is not its force-deflection "
                          f"table's slope at zero deflection ({slope:g}): flexgvt follows the table; Nastran's "
                          "linear solutions use the rate")
        return table

    def note_unused_tables(self) -> None:
        tables = getattr(self.deck.bdf, "tables_d", None) or {}
        unused = sorted(t for t, table in tables.items() if table.type == "TABLED1" and t not in self.used_tables)
        if unused:
            self.log.note(f"TABLED1 {', '.join(map(str, unused))} not used by a spring: ignored (dynamic loads "
                          "are not read)")

    def _scalar(self, elem, value_stiff: float, value_damp: float, table_id: int = 0) -> None:
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
        tables = None
        if table_id:  # CELAS1's F = f(u1 - u2): flexgvt's deflection u2 - u1, so two ends mirror the table
            tables = {c: self._table(table_id, c, b is not None, where, k[c - 1])}
            k[c - 1] = 0.0
        self._add_spring(where, a, b, k, d, axes[0], (elem.type, int(elem.eid)), tables)

    def _add_spring(self, where, a, b, k, d, frame, source, tables=None) -> None:
        try:
            self.model.add_spring(a, b, stiffness=k, damping=d, frame=frame, id=source[1], tables=tables)
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
                self._scalar(elem, float(k), 0.0, self._pelast(elem, where) if t == "CELAS1" else 0)
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
            elif t == "CBUSH1D":
                self.read_cbush1d(elem, where)

    def _pelast(self, elem, where) -> int:
        """TKNID of the PELAST of CELAS1 ``elem``'s property (0: none); TKID/TGEID noted."""
        pelast = (getattr(self.deck.bdf, "pelast", None) or {}).get(elem.pid)
        if pelast is None:
            return 0
        if pelast.tkid or pelast.tgeid:
            self.log.note(f"{where}: PELAST {elem.pid}'s frequency-dependent TKID/TGEID tables are for frequency "
                          "response; the modes use PELAS K, as Nastran's do")
        return int(pelast.tknid or 0)

    def read_cbush1d(self, elem, where) -> None:
        """CBUSH1D + PBUSH1D: an axial spring and damper along GA-GB (or CID's x axis), U = U(GB) - U(GA);
        SPRING TABLE IDT its force-deflection table."""
        bdf, u = self.deck.bdf, self.deck.units
        prop = bdf.properties[elem.pid]
        pwhere = self.at("PBUSH1D", prop.pid)
        ga, gb = int(elem.ga), (None if elem.gb in (None, 0) else int(elem.gb))
        other = [v for v in getattr(prop, "vars", []) or [] if v != "SPRING"]
        if other or (getattr(prop, "spring_type", None) not in (None, "TABLE")):
            self.log.skip(f"PBUSH1D ({'/'.join(other) or 'SPRING ' + str(prop.spring_type)}: only linear K, B and "
                          "SPRING TABLE are read)", prop.pid)
            return
        if prop.m:
            raise ModelError(f"{pwhere}: the element mass M={prop.m:g} is not read; model it with CONM2s on GA "
                             "and GB and set M blank")
        if elem.cid not in (None, -1):
            axis = coord_axes(bdf, elem.cid, self.deck.xyz_deck[ga], where)[:, 0]
        else:
            line = None if gb is None else self.deck.xyz_deck[gb] - self.deck.xyz_deck[ga]
            if line is None or np.linalg.norm(line) <= 1e-12:
                raise ModelError(f"{where}: a CBUSH1D on coincident grids (or grounded) needs CID for its axis")
            axis = line
        frame = frame_from_x(axis)
        k = np.zeros(6)
        c = np.zeros(6)
        k[0] = float(prop.k or 0.0) * u.force / u.length
        c[0] = float(prop.c or 0.0) * u.force / u.length
        tables = None
        idt, idc = getattr(prop, "spring_idt", None), getattr(prop, "spring_idc", None)
        if "SPRING" in (getattr(prop, "vars", []) or []):
            if idc not in (None, 0, idt):
                raise ModelError(f"{pwhere}: SPRING TABLE with a compression table IDC={idc} other than IDT={idt} "
                                 "is not read; give one TABLED1 over tension and compression as IDT")
            tables = {1: self._table(int(idt), 1, gb is None, where, k[0] if k[0] else None)}
            k[0] = 0.0
        self._add_spring(where, ga, gb, k, c, frame, ("CBUSH1D", int(elem.eid)), tables)

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
        k = k * scale
        tables = None
        pbusht = (getattr(bdf, "pbusht", None) or {}).get(prop.pid)
        if pbusht is not None:
            if any(t for name in ("k_tables", "b_tables", "ge_tables") for t in (getattr(pbusht, name) or [])):
                self.log.note(f"{where}: PBUSHT {prop.pid}'s frequency-dependent K/B/GE tables are for frequency "
                              "response; the modes use PBUSH's values, as Nastran's do")
            # U = U(GB) - U(GA): a grounded CBUSH (GB blank) deflects by -U(GA), so its tables mirror.
            tables = {c + 1: self._table(int(tid), c + 1, gb is None, where, k[c] if k[c] else None)
                      for c, tid in enumerate(getattr(pbusht, "kn_tables", None) or []) if tid}
            for c in tables:
                k[c - 1] = 0.0
        self._add_spring(where, ga, gb, k, b * scale, frame, ("CBUSH", int(elem.eid)), tables)


FAMILY = Family("springs", CARDS, read_springs, needs_property=("CELAS1", "CDAMP1", "CVISC", "CBUSH", "CBUSH1D"))
