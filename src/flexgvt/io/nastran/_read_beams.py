"""Materials, beam sections and beams (CBAR/CBEAM with offsets and pins), rods, RBE3 and end nodes."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...errors import ModelError
from ...model import GeneralSection, Material, RodSection, TaperedSection
from ._cards import BEAM_CARDS, BEAM_PROPERTIES, _supported_shapes
from ._common import coord_axes
from ._limits import MAX_SECTION_RATIO, MAX_VALUE
from ._sections import SectionData, from_properties, library_section


@dataclass(frozen=True)
class BeamSource:
    """Where a flexgvt beam group came from: one Nastran beam property."""

    name: str
    card: str  # CBAR or CBEAM
    ptype: str  # PBAR, PBARL, PBEAM, PBEAML
    pid: int
    mid: int
    eids: tuple[int, ...]
    principal: tuple[float, float]


def _scale_section(section, L: float):
    """Section in SI from deck length units L [m per unit]."""
    if L == 1.0:
        return section
    from dataclasses import replace

    from ...model import CircularTubeSection, GeneralSection, RectangularSection
    if isinstance(section, RodSection):
        return RodSection(A=section.A * L**2, J=section.J * L**4)
    if isinstance(section, RectangularSection):
        return replace(section, width=section.width * L, height=section.height * L)
    if isinstance(section, CircularTubeSection):
        return replace(section, outer_radius=section.outer_radius * L, inner_radius=section.inner_radius * L)
    if isinstance(section, TaperedSection):
        return TaperedSection(_scale_section(section.end_a, L), _scale_section(section.end_b, L))
    assert isinstance(section, GeneralSection)
    s2, s4 = L**2, L**4
    return GeneralSection(A=section.A * s2, Iy=section.Iy * s4, Iz=section.Iz * s4, J=section.J * s4,
                          Ay=None if section.Ay is None else section.Ay * s2,
                          Az=None if section.Az is None else section.Az * s2,
                          Ip=None if section.Ip is None else section.Ip * s4)


def _frame_from_x(ex: np.ndarray) -> np.ndarray:
    """Orthonormal frame (columns) whose first axis is along ex."""
    x = ex / np.linalg.norm(ex)
    helper = np.eye(3)[int(np.argmin(np.abs(x)))]
    y = np.cross(helper, x)
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])




class BeamsMixin:
    """Part of the bulk data reader (see _read._Reader)."""

    # ----------------------------------------------------------------- materials
    def read_materials(self) -> None:
        u = self.units
        for mid, mat in sorted(self.bdf.materials.items()):
            if mat.type != "MAT1":
                continue
            where = self.at("MAT1", mid)
            E, G, nu, rho = mat.e, mat.g, mat.nu, mat.rho or 0.0
            if not E:
                raise ModelError(f"{where}: E is blank or zero; flexgvt beams need Young's modulus")
            if not G and not nu:
                raise ModelError(f"{where}: G and NU are both blank, which Nastran reads as G = 0 (no torsional or "
                                 "shear stiffness); give G or NU")
            consistent = G and nu is not None and nu != -1 and math.isclose(G, E / (2 * (1 + nu)), rel_tol=1e-6)
            # E and G given with NU blank: Nastran takes NU = E/2G - 1 whatever its value (a beam's
            # equivalent properties often give NU outside (-1, 0.5); only E and G act on a beam).
            use_nu = not G or (consistent and -1 < nu < 0.5)
            kwargs = {"nu": float(nu)} if use_nu else {"G": float(G) * u.stress}
            if G and nu is not None and not consistent and -1 < nu < 0.5:
                kwargs["nu"] = float(nu)
            if getattr(mat, "ge", 0.0):
                self.notes.append(f"{where}: structural damping GE={mat.ge} is not modelled")
            try:
                self.deck.materials[mid] = Material(f"MAT1_{mid}", E=float(E) * u.stress,
                                                    rho=float(rho) * u.density * self.wtmass, **kwargs)
            except ModelError as exc:
                raise ModelError(f"{where}: {exc}") from None

    # ----------------------------------------------------------------- beams
    def beam_section(self, prop) -> tuple[SectionData, tuple[float, float]] | None:
        """(section, NSM per length at end A and end B in deck units) of a beam property, or None if
        unsupported (recorded). A PBEAM/PBEAML whose end B differs from end A gives a TaperedSection."""
        where = self.at(prop.type, prop.pid)
        if prop.type == "PBAR":
            sdata = from_properties(where, prop.A, prop.i1, prop.i2, prop.i12, prop.j, prop.k1, prop.k2)
            return sdata, (prop.nsm or 0.0,) * 2
        if prop.type == "PBARL":
            if prop.Type not in _supported_shapes():
                self.skip(f"PBARL TYPE {prop.Type}", prop.pid)
                return None
            return library_section(where, prop.Type, prop.dim), (prop.nsm or 0.0,) * 2
        if prop.type == "PBEAM":
            offsets = [getattr(prop, n, None) for n in ("m1a", "m2a", "m1b", "m2b", "n1a", "n2a", "n1b", "n2b")]
            if any(np.any(np.asarray(o, float) != 0) for o in offsets if o is not None):
                self.skip("PBEAM (neutral-axis/NSM offsets)", prop.pid)
                return None
            names = ("A", "i1", "i2", "i12", "j", "nsm")
            stations = self._stations(prop, [np.atleast_1d(np.asarray(getattr(prop, n), float)) for n in names])
            if stations is None:
                return None
            (A, I1, I2, I12, J, nsm) = zip(*stations)
            ends = [from_properties(where, A[e], I1[e], I2[e], I12[e], J[e], prop.k1, prop.k2) for e in (0, 1)]
            nsi = [float(v or 0.0) for v in (prop.nsia, prop.nsib)]
            if any(nsi):
                rho = self.bdf.materials[prop.mid].rho or 0.0
                if not rho:
                    self.skip("PBEAM (NSI on a massless material)", prop.pid)
                    return None
                # NSI: extra mass moment of inertia per length; flexgvt keeps it in rho * Ip.
                ends = [replace(d, section=replace(d.section, Ip=d.section.polar + v / rho)) for d, v in zip(ends, nsi)]
            sdata = self._tapered(prop, *ends)
            return None if sdata is None else (sdata, (nsm[0], nsm[1]))
        if prop.type == "PBEAML":
            if prop.beam_type not in _supported_shapes():
                self.skip(f"PBEAML TYPE {prop.beam_type}", prop.pid)
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
                self.skip(f"{prop.type} (intermediate stations off the linear taper between the ends)", prop.pid)
                return None
        return [tuple(float(v[k]) for v in values) for k in (a, b)]

    def _tapered(self, prop, a: SectionData, b: SectionData) -> SectionData | None:
        """SectionData of end A, or a TaperedSection when end B differs."""
        pa, pb = a.section.properties(), b.section.properties()
        if all(math.isclose(pa[k], pb[k], rel_tol=1e-12, abs_tol=0.0) for k in pa) and a.principal == b.principal:
            return a
        if not np.allclose(a.principal, b.principal, rtol=0.0, atol=1e-9):
            self.skip(f"{prop.type} (tapered, principal axes turning between end A and end B)", prop.pid)
            return None
        try:
            return SectionData(TaperedSection(a.section, b.section), a.principal)
        except ModelError as exc:
            raise ModelError(f"{self.at(prop.type, prop.pid)}: {exc}") from None

    def orientation_vector(self, elem) -> np.ndarray:
        """Nastran v vector of a CBAR/CBEAM/CBUSH in basic axes (deck length units)."""
        ga = elem.nodes[0] if hasattr(elem, "nodes") else elem.ga
        if elem.g0 not in (None, 0):
            return self.xyz_deck[elem.g0] - self.xyz_deck[ga]
        if elem.x is None or np.shape(elem.x) != (3,):
            given = "G0 = 0 (an integer in the X1 field is read as the node id G0)" if elem.g0 == 0 else \
                f"X1-X3 = {elem.x!r}"
            raise ModelError(f"{self.at(elem.type, elem.eid)}: orientation {given} defines no direction; give X1, X2, "
                             "X3 as real numbers (0.0, not 0) or G0 as the id of a grid off the element axis")
        x = np.asarray(elem.x, float)
        offt = (getattr(elem, "offt", None) or "GGG") if elem.type != "CBUSH" else "GGG"
        if isinstance(offt, str) and offt[0] == "G":
            cd = self.bdf.nodes[ga].cd
            x = coord_axes(self.bdf, cd, self.xyz_deck[ga], self.at(elem.type, elem.eid)) @ x
        return x

    def read_beams(self) -> None:
        bdf, model, u = self.bdf, self.model, self.units
        groups: dict[int, list] = {}
        for eid, elem in sorted(bdf.elements.items()):
            if elem.type not in BEAM_CARDS:
                continue
            if any(pin and set(str(pin)) != set("456") for pin in (elem.pa, elem.pb)):
                self.skip(f"{elem.type} (pin flags other than 456)", eid)
                continue
            offt = getattr(elem, "offt", None) or "GGG"
            offsets = [w is not None and np.any(np.asarray(w, float) != 0) for w in (elem.wa, elem.wb)]
            if isinstance(offt, str) and any(o and offt[k + 1] == "O" for k, o in enumerate(offsets)):
                self.skip(f"{elem.type} (offsets in the element system, OFFT {offt})", eid)
                continue
            if elem.type == "CBEAM" and (getattr(elem, "sa", 0) or getattr(elem, "sb", 0)):
                self.skip("CBEAM (warping scalar points SA/SB)", eid)
                continue
            if elem.type == "CBEAM" and getattr(elem, "bit", None) is not None:
                self.skip("CBEAM (BIT field)", eid)
                continue
            if isinstance(offt, str) and offt[0] not in "GB":
                self.skip(f"{elem.type} (OFFT {offt})", eid)
                continue
            groups.setdefault(elem.pid, []).append(elem)
        for pid, elems in sorted(groups.items()):
            prop = bdf.properties[pid]
            if prop.type not in BEAM_PROPERTIES:
                for e in elems:
                    self.skip(f"{e.type} with {prop.type}", e.eid)
                continue
            mat = self.deck.materials.get(prop.mid)
            if mat is None:
                kind = bdf.materials[prop.mid].type
                self.skip(f"{kind} on beam property {prop.type}", prop.pid)
                continue
            cards = {e.type for e in elems}
            if len(cards) > 1:
                raise ModelError(f"{self.at(prop.type, pid)} is used by both CBAR and CBEAM elements; give each its "
                                 "own property")
            got = self.beam_section(prop)
            if got is None:
                for e in elems:
                    self.skip(f"{e.type} on unsupported {prop.type}", e.eid)
                continue
            sdata, nsm = got
            section = _scale_section(sdata.section, u.length)
            self._check_section_size(section, prop)
            if not self.cbar_torsional_inertia and elems[0].type == "CBAR":  # Nastran's CBAR: no rho*Ip
                p = section.properties()
                section = GeneralSection(A=p["A"], Iy=p["Iy"], Iz=p["Iz"], J=p["J"], Ay=p["Ay"] or None,
                                         Az=p["Az"] or None, Ip=0.0)
            pairs = np.array([[self._beam_end(e, 0), self._beam_end(e, 1)] for e in elems], int)
            ga = np.array([self.xyz[p[0]] for p in pairs])
            gb = np.array([self.xyz[p[1]] for p in pairs])
            ex = gb - ga
            length = np.linalg.norm(ex, axis=1)
            if np.any(length == 0):
                k = int(np.flatnonzero(length == 0)[0])
                raise ModelError(f"{self.at(elems[k].type, elems[k].eid)}: GA and GB coincide; a beam needs two "
                                 "distinct nodes")
            ex /= length[:, None]
            v = np.array([self.orientation_vector(e) for e in elems], float)
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
            mass = "consistent-bending" if self.mass == "consistent" and elems[0].type == "CBEAM" else self.mass
            try:
                ids = model.add_beams(pairs, mat, section, orientation=orient, rotary_inertia=self.rotary_inertia,
                                      mass=mass, name=name)
            except ModelError as exc:
                raise ModelError(f"{self.at(prop.type, pid)}: {exc}") from None
            eids = tuple(int(e.eid) for e in elems)
            self.deck.element_ids.update(dict(zip(eids, (int(i) for i in ids))))
            self.deck.beams[name] = BeamSource(name, elems[0].type, prop.type, int(pid), int(prop.mid), eids,
                                               sdata.principal)
            if any(nsm):  # Nastran's lumped mass: int NSM N_i dx at each end (translations only)
                self._lumped_nsm(pairs, nsm, prop.type, pid)

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
            w = coord_axes(self.bdf, self.bdf.nodes[grid].cd, self.xyz_deck[grid], self.at(elem.type, elem.eid)) @ w
        return self._end_node(grid, self.xyz_deck[grid] + w, "123" if pinned else "123456",
                              (elem.type, int(elem.eid), "AB"[end]))

    def _end_node(self, grid: int, position_deck: np.ndarray, components: str, source: tuple) -> int:
        """A new node at position_deck [deck length] tied to ``grid`` by a rigid link (added after
        the RBE2s, see attach_end_nodes). Ids follow the deck's largest grid id."""
        nid = max(max(self.bdf.nodes), max(self.deck.end_nodes.values(), default=0)) + 1
        self.xyz_deck[nid] = np.asarray(position_deck, float)
        self.xyz[nid] = self.xyz_deck[nid] * self.units.length
        self.model.add_nodes([self.xyz[nid]], ids=[nid])
        self.deck.end_nodes[source] = nid
        self.pending_links.append((grid, nid, components, source))
        return nid

    def _pending_rbe3(self, elem) -> None:
        """Check an RBE3 and keep it for read_interpolations (after the rigid links exist)."""
        eid = int(elem.eid)
        if elem.Gmi:
            self.skip("RBE3 (UM dependent DOFs)", eid)
            return
        refc = "".join(sorted(set(str(elem.refc))))
        if refc not in ("123", "123456"):
            self.skip("RBE3 (REFC other than 123456 or 123)", eid)
            return
        if any("".join(sorted(set(str(c)))) != "123" for c in elem.comps):
            self.skip("RBE3 (independent components other than 123)", eid)
            return
        weights: dict[int, float] = {}
        for wt, nodes in zip(elem.weights, elem.Gijs):
            if wt is None or not math.isfinite(float(wt)) or float(wt) <= 0:
                raise ModelError(f"{self.at('RBE3', eid)}: weight {wt!r} must be a positive number")
            for n in nodes:
                weights[int(n)] = weights.get(int(n), 0.0) + float(wt)
        self.pending_rbe3.append((eid, int(elem.refgrid), refc, weights))

    def read_interpolations(self) -> None:
        """RBE3 (C = 123 at the nodes) -> interpolation links."""
        for eid, ref, refc, weights in self.pending_rbe3:
            try:
                self.model.add_interpolation(ref, list(weights), list(weights.values()), components=refc)
            except ModelError as exc:
                raise ModelError(f"{self.at('RBE3', eid)}: {exc}") from None
            self.deck.interpolation_sources.append(eid)

    def attach_end_nodes(self) -> None:
        """Rigid links of the beam-end and bush-location nodes, on the root of any RBE2 chain."""
        owner = {d: link for link in self.model.rigid_links for d in link.dependents}
        for grid, nid, components, source in self.pending_links:
            root = grid
            if grid in owner:
                link = owner[grid]
                if link.components != "123456":
                    raise ModelError(f"{source[0]} {source[1]}: end {source[2]} sits on node {grid}, a dependent of an "
                                     f"RBE2 with components {link.components}; an offset, pin or bush location cannot "
                                     "hang on a partial RBE2. Use a full RBE2 or attach the element to its independent")
                root = link.independent
            self.model.add_rigid_link(root, [nid], components=components)
            self.deck.rigid_sources.append(source)

    # ----------------------------------------------------------------- rods
    def read_rods(self) -> None:
        """CROD + PROD (one group per property) and CONROD (one group per set of equal values)."""
        bdf, u = self.bdf, self.units
        groups: dict[tuple, list] = {}
        for eid, elem in sorted(bdf.elements.items()):
            if elem.type == "CROD":
                prop = bdf.properties[elem.pid]
                if prop.type != "PROD":
                    self.skip(f"CROD with {prop.type}", eid)
                    continue
                groups.setdefault(("PROD", prop.pid, prop.mid, prop.A, prop.j, prop.nsm), []).append(elem)
            elif elem.type == "CONROD":
                groups.setdefault(("CONROD", 0, elem.mid, elem.A, elem.j, elem.nsm), []).append(elem)
        for (ptype, pid, mid, area, j, nsm), elems in groups.items():
            where = self.at(ptype, pid) if ptype == "PROD" else self.at("CONROD", elems[0].eid)
            mat = self.deck.materials.get(mid)
            if mat is None:
                for e in elems:
                    self.skip(f"{e.type} on {bdf.materials[mid].type}", e.eid)
                continue
            pairs = np.array([e.node_ids[:2] for e in elems], int)
            name = f"PROD_{pid}" if ptype == "PROD" else f"CONROD_{elems[0].eid}"
            try:
                ids = self.model.add_rods(pairs, mat, float(area) * u.length ** 2,
                                          torsion_constant=float(j or 0.0) * u.length ** 4, mass=self.mass, name=name)
            except ModelError as exc:
                raise ModelError(f"{where}: {exc}") from None
            eids = tuple(int(e.eid) for e in elems)
            self.deck.element_ids.update(dict(zip(eids, (int(i) for i in ids))))
            self.deck.beams[name] = BeamSource(name, elems[0].type, ptype, int(pid), int(mid), eids, (0.0, 1.0))
            if nsm:
                self._lumped_nsm(pairs, (float(nsm),) * 2, ptype, pid)

    def _lumped_nsm(self, pairs: np.ndarray, nsm: tuple[float, float], card: str, ident) -> None:
        """Non-structural mass per length NSM (deck units) at end A and end B, linear between them, as
        point masses int NSM N_i dx at the element ends (NSM L / 2 each when uniform)."""
        u = self.units
        na, nb = (v * u.mass / u.length * self.wtmass for v in nsm)
        ends: dict[int, float] = {}
        for p in pairs:
            L = float(np.linalg.norm(self.xyz[p[1]] - self.xyz[p[0]]))
            for n, m in zip(p, (L * (na / 3 + nb / 6), L * (na / 6 + nb / 3)) if na != nb else (0.5 * na * L,) * 2):
                ends[int(n)] = ends.get(int(n), 0.0) + m
        for n, m in ends.items():
            self.model.add_mass(n, m)
            self.deck.mass_sources.append((f"NSM:{card}", int(ident)))
        if self.mass == "consistent":
            self.notes.append(f"{self.at(card, ident)}: NSM={nsm[0] if nsm[0] == nsm[1] else list(nsm)} lumped at the "
                              "element ends (Nastran distributes it consistently under COUPMASS)")
