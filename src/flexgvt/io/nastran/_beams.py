"""Beams: CBAR/CBEAM with PBAR/PBARL/PBEAM/PBEAML (uniform or tapered sections, offsets and pins
as rigidly linked end nodes, NSM lumped at the ends)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...errors import ModelError
from ...model import GeneralSection, Material, Model, TaperedSection
from ._deck import Deck, Family, Findings, Parts
from ._elements import BeamSource, EndNodes, lumped_nsm, scale_section
from ._grids import coord_axes, orientation_vector
from ._limits import MAX_SECTION_RATIO, MAX_VALUE
from ._sections import SUPPORTED_SHAPES, SectionData, from_properties, library_section

BEAM_CARDS = ("CBAR", "CBEAM")
BEAM_PROPERTIES = ("PBAR", "PBARL", "PBEAM", "PBEAML")


def read_beams(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """One beam group per beam property (its CBARs or its CBEAMs), on the MAT1s read before."""
    reader = _Beams(deck, model, log, parts.materials)
    reader.read()
    return Parts(beams=reader.beams, element_ids=reader.element_ids, mass_sources=tuple(reader.mass_sources),
                 end_nodes=reader.ends.nodes, end_links=tuple(reader.ends.links))


class _Beams:
    """The beam family's reading of one deck: its inputs and what it has read so far."""

    def __init__(self, deck: Deck, model: Model, log: Findings, materials: dict[int, Material]) -> None:
        self.deck, self.model, self.log, self.materials = deck, model, log, materials
        self.ends = EndNodes(deck, model)
        self.beams: dict[str, BeamSource] = {}
        self.element_ids: dict[int, int] = {}
        self.mass_sources: list[tuple[str, int]] = []

    def at(self, name: str, ident) -> str:
        return self.deck.at(name, ident)

    def beam_section(self, prop) -> tuple[SectionData, tuple[float, float]] | None:
        """(section, NSM per length at end A and end B in deck units) of a beam property, or None if
        unsupported (recorded). A PBEAM/PBEAML whose end B differs from end A gives a TaperedSection."""
        where = self.at(prop.type, prop.pid)
        if prop.type == "PBAR":
            sdata = from_properties(where, prop.A, prop.i1, prop.i2, prop.i12, prop.j, prop.k1, prop.k2)
            return sdata, (prop.nsm or 0.0,) * 2
        if prop.type == "PBARL":
            if prop.Type not in SUPPORTED_SHAPES:
                self.log.skip(f"PBARL TYPE {prop.Type}", prop.pid)
                return None
            return library_section(where, prop.Type, prop.dim), (prop.nsm or 0.0,) * 2
        if prop.type == "PBEAM":
            offsets = [getattr(prop, n, None) for n in ("m1a", "m2a", "m1b", "m2b", "n1a", "n2a", "n1b", "n2b")]
            if any(np.any(np.asarray(o, float) != 0) for o in offsets if o is not None):
                self.log.skip("PBEAM (neutral-axis/NSM offsets)", prop.pid)
                return None
            names = ("A", "i1", "i2", "i12", "j", "nsm")
            stations = self._stations(prop, [np.atleast_1d(np.asarray(getattr(prop, n), float)) for n in names])
            if stations is None:
                return None
            (A, I1, I2, I12, J, nsm) = zip(*stations)
            ends = [from_properties(where, A[e], I1[e], I2[e], I12[e], J[e], prop.k1, prop.k2) for e in (0, 1)]
            nsi = [float(v or 0.0) for v in (prop.nsia, prop.nsib)]
            if any(nsi):
                rho = self.deck.bdf.materials[prop.mid].rho or 0.0
                if not rho:
                    self.log.skip("PBEAM (NSI on a massless material)", prop.pid)
                    return None
                # NSI: extra mass moment of inertia per length; flexgvt keeps it in rho * Ip.
                ends = [replace(d, section=replace(d.section, Ip=d.section.polar + v / rho)) for d, v in zip(ends, nsi)]
            sdata = self._tapered(prop, *ends)
            return None if sdata is None else (sdata, (nsm[0], nsm[1]))
        if prop.type == "PBEAML":
            if prop.beam_type not in SUPPORTED_SHAPES:
                self.log.skip(f"PBEAML TYPE {prop.beam_type}", prop.pid)
                return None
            dims = np.atleast_2d(np.asarray(prop.dim, float))
            nsm = np.zeros(len(dims)) if prop.nsm is None else np.atleast_1d(np.asarray(prop.nsm, float))
            sections = [library_section(where, prop.beam_type, d) for d in dims]
            values = [np.array([sd.section.properties()[k] for sd in sections]) for k in ("A", "Iy", "Iz", "J")]
            stations = self._stations(prop, values + [nsm])
            if stations is None:
                return None
            first, last = int(np.argmin(prop.xxb)), int(np.argmax(prop.xxb))
            sdata = self._tapered(prop, sections[first], sections[last])
            return None if sdata is None else (sdata, (float(nsm[first]), float(nsm[last])))
        return None

    def _stations(self, prop, values: list[np.ndarray]) -> list[tuple] | None:
        """The end A and end B values of a PBEAM/PBEAML's per-station ``values``; intermediate stations
        (0 < X/XB < 1) must lie on the linear taper between the ends (what flexgvt models), else
        the property is recorded as unsupported and None returned."""
        x = np.atleast_1d(np.asarray(prop.xxb, float))
        a, b = int(np.argmin(x)), int(np.argmax(x))
        for v in values:
            if len(v) != len(x):  # pyNastran keeps one value per station; anything else is malformed
                raise ModelError(f"{self.at(prop.type, prop.pid)}: {len(v)} values for {len(x)} stations")
            line = v[a] + (v[b] - v[a]) * (x - x[a]) / (x[b] - x[a]) if x[b] > x[a] else np.full_like(v, v[a])
            if not np.allclose(v, line, rtol=1e-6, atol=1e-12 * max(np.abs(v).max(), 1e-300)):
                self.log.skip(f"{prop.type} (intermediate stations off the linear taper between the ends)", prop.pid)
                return None
        return [tuple(float(v[k]) for v in values) for k in (a, b)]

    def _tapered(self, prop, a: SectionData, b: SectionData) -> SectionData | None:
        """SectionData of end A, or a TaperedSection when end B differs."""
        pa, pb = a.section.properties(), b.section.properties()
        if all(math.isclose(pa[k], pb[k], rel_tol=1e-12, abs_tol=0.0) for k in pa) and a.principal == b.principal:
            return a
        if not np.allclose(a.principal, b.principal, rtol=0.0, atol=1e-9):
            self.log.skip(f"{prop.type} (tapered, principal axes turning between end A and end B)", prop.pid)
            return None
        try:
            return SectionData(TaperedSection(a.section, b.section), a.principal)
        except ModelError as exc:
            raise ModelError(f"{self.at(prop.type, prop.pid)}: {exc}") from None

    def read(self) -> None:
        deck, model = self.deck, self.model
        bdf, u = deck.bdf, deck.units
        groups: dict[int, list] = {}
        for eid, elem in sorted(bdf.elements.items()):
            if elem.type not in BEAM_CARDS:
                continue
            if any(pin and set(str(pin)) != set("456") for pin in (elem.pa, elem.pb)):
                self.log.skip(f"{elem.type} (pin flags other than 456)", eid)
                continue
            offt = getattr(elem, "offt", None) or "GGG"
            offsets = [w is not None and np.any(np.asarray(w, float) != 0) for w in (elem.wa, elem.wb)]
            if isinstance(offt, str) and any(o and offt[k + 1] == "O" for k, o in enumerate(offsets)):
                self.log.skip(f"{elem.type} (offsets in the element system, OFFT {offt})", eid)
                continue
            if elem.type == "CBEAM" and (getattr(elem, "sa", 0) or getattr(elem, "sb", 0)):
                self.log.skip("CBEAM (warping scalar points SA/SB)", eid)
                continue
            if elem.type == "CBEAM" and getattr(elem, "bit", None) is not None:
                self.log.skip("CBEAM (BIT field)", eid)
                continue
            if isinstance(offt, str) and offt[0] not in "GB":
                self.log.skip(f"{elem.type} (OFFT {offt})", eid)
                continue
            groups.setdefault(elem.pid, []).append(elem)
        for pid, elems in sorted(groups.items()):
            prop = bdf.properties[pid]
            if prop.type not in BEAM_PROPERTIES:
                for e in elems:
                    self.log.skip(f"{e.type} with {prop.type}", e.eid)
                continue
            mat = self.materials.get(prop.mid)
            if mat is None:
                kind = bdf.materials[prop.mid].type
                self.log.skip(f"{kind} on beam property {prop.type}", prop.pid)
                continue
            cards = {e.type for e in elems}
            if len(cards) > 1:
                raise ModelError(f"{self.at(prop.type, pid)} is used by both CBAR and CBEAM elements; give each its "
                                 "own property")
            got = self.beam_section(prop)
            if got is None:
                for e in elems:
                    self.log.skip(f"{e.type} on unsupported {prop.type}", e.eid)
                continue
            sdata, nsm = got
            section = scale_section(sdata.section, u.length)
            self._check_section_size(section, prop)
            if not self.deck.cbar_torsional_inertia and elems[0].type == "CBAR":  # Nastran's CBAR: no rho*Ip
                p = section.properties()
                section = GeneralSection(A=p["A"], Iy=p["Iy"], Iz=p["Iz"], J=p["J"], Ay=p["Ay"] or None,
                                         Az=p["Az"] or None, Ip=0.0)
            pairs = np.array([[self._beam_end(e, 0), self._beam_end(e, 1)] for e in elems], int)
            ga = np.array([self.ends.position(p[0]) for p in pairs])
            gb = np.array([self.ends.position(p[1]) for p in pairs])
            ex = gb - ga
            length = np.linalg.norm(ex, axis=1)
            if np.any(length == 0):
                k = int(np.flatnonzero(length == 0)[0])
                raise ModelError(f"{self.at(elems[k].type, elems[k].eid)}: GA and GB coincide; a beam needs two "
                                 "distinct nodes")
            ex /= length[:, None]
            v = np.array([orientation_vector(self.deck, e) for e in elems], float)
            zn = np.cross(ex, v)
            nz = np.linalg.norm(zn, axis=1)
            bad = nz <= 1e-8 * np.maximum(np.linalg.norm(v, axis=1), 1e-300)
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                raise ModelError(f"{self.at(elems[k].type, elems[k].eid)}: orientation vector {v[k].tolist()} is "
                                 "parallel to the element axis; give X1-X3 or G0 off the axis")
            zn /= nz[:, None]
            yn = np.cross(zn, ex)
            cy, cz = sdata.principal
            orient = cy * yn + cz * zn
            name = f"{prop.type}_{pid}"
            # Nastran's coupled (COUPMASS) CBEAM mass lumps the axial and torsional terms; its CBAR's is
            # consistent (measured: the strut-braced wing deck, see docs/nastran.md).
            mass = "consistent-bending" if deck.mass == "consistent" and elems[0].type == "CBEAM" else deck.mass
            try:
                ids = model.add_beams(pairs, mat, section, orientation=orient, rotary_inertia=deck.rotary_inertia,
                                      mass=mass, name=name)
            except ModelError as exc:
                raise ModelError(f"{self.at(prop.type, pid)}: {exc}") from None
            eids = tuple(int(e.eid) for e in elems)
            self.element_ids.update(dict(zip(eids, (int(i) for i in ids))))
            self.beams[name] = BeamSource(name, elems[0].type, prop.type, int(pid), int(prop.mid), eids,
                                          sdata.principal)
            if any(nsm):  # Nastran's lumped mass: int NSM N_i dx at each end (translations only)
                self.mass_sources += lumped_nsm(deck, model, self.log, self.ends.position, pairs, nsm, prop.type, pid)

    def _check_section_size(self, section, prop) -> None:
        """Section properties (SI) finite and within MAX_VALUE: PBARL/PBEAML dimensions enter I and J
        to the fourth power, so a dimension of 1e20 (within the field limit) gives I = 1e80."""
        ends = section.end_properties() if isinstance(section, TaperedSection) else (section.properties(),)
        for values in ends:
            bad = {k: v for k, v in values.items() if v is not None and not (math.isfinite(v) and abs(v) <= MAX_VALUE)}
            if bad:
                listing = ", ".join(f"{k} = {v:.3g}" for k, v in bad.items())
                raise ModelError(f"{self.at(prop.type, prop.pid)}: section properties {listing} (SI) exceed "
                                 f"{MAX_VALUE:g} in magnitude (stiffness products of such values overflow); check the "
                                 "dimensions and the deck's units")
            # Bending and torsion stiffness of one section act on the same rotations: beyond a ratio of
            # 1e12 the weaker is lost in double precision (a PBEAM J of 1e16 with I1 = 0.8 gave
            # negative frequencies, 1e20 an eigensolver that ran 97 s before failing).
            moments = {k: abs(values[k]) for k in ("Iy", "Iz", "J") if values.get(k)}
            if len(moments) > 1 and max(moments.values()) > MAX_SECTION_RATIO * min(moments.values()):
                listing = ", ".join(f"{k} = {v:.3g}" for k, v in moments.items())
                raise ModelError(f"{self.at(prop.type, prop.pid)}: section moments {listing} (SI) differ by more "
                                 f"than a factor {MAX_SECTION_RATIO:g}, beyond what double precision resolves in one "
                                 "stiffness matrix; check the value (I1, I2, J)")

    def _beam_end(self, elem, end: int) -> int:
        """Node at end A (0) or B (1) of a CBAR/CBEAM: its grid, or for an offset (WA/WB) or a pin
        flag 456 an end node joined to the grid by a rigid link (all components, or 123 for the pin),
        as Nastran's rigid offset and released end are."""
        grid = int(elem.node_ids[end])
        w = elem.wa if end == 0 else elem.wb
        w = np.zeros(3) if w is None else np.asarray(w, float)
        pinned = bool(elem.pa if end == 0 else elem.pb)
        if not pinned and not np.any(w != 0):
            return grid
        if (getattr(elem, "offt", None) or "GGG")[end + 1] == "G":
            bdf = self.deck.bdf
            w = coord_axes(bdf, bdf.nodes[grid].cd, self.deck.xyz_deck[grid], self.at(elem.type, elem.eid)) @ w
        return self.ends.add(grid, self.deck.xyz_deck[grid] + w, "123" if pinned else "123456",
                             (elem.type, int(elem.eid), "AB"[end]))


FAMILY = Family("beams", BEAM_CARDS + BEAM_PROPERTIES, read_beams, needs_property=BEAM_CARDS,
                needs_material=BEAM_PROPERTIES)
