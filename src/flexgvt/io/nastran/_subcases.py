"""Subcases: one Configuration per SUBCASE, with SPC/MPC/SUPORT, loads (LOAD, FORCE, MOMENT, GRAV,
PLOAD1, SPCD) and the eigenvalue METHOD (EIGRL/EIGR); the MPC set all subcases select becomes model
constraints."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import FileFormatError, ModelError
from ...model import Configuration, DistributedLoad, Model, NodalLoad, RodSection
from ._common import EigenMethod
from ._deck import Deck, Findings, Parts
from ._grids import basic_dofs, coord_axes
from ._limits import MAX_ENFORCED_SIZES
from ._plates import membrane_rotation_fixes

CARDS = ("SPC", "SPC1", "SPCADD", "MPC", "MPCADD", "SUPORT", "SUPORT1", "LOAD", "FORCE", "MOMENT", "GRAV", "PLOAD1",
         "SPCD")


@dataclass(frozen=True)
class Cases:
    """What the subcases give BdfDeck: configuration name -> Configuration, subcase id, EigenMethod
    and its ND; the MPC set id behind each model constraint."""

    configurations: dict[str, Configuration]
    subcases: dict[str, int]
    methods: dict[str, EigenMethod | None]
    n_modes: dict[str, int | None]
    constraint_sources: tuple[int, ...]


def _label(sub) -> str:
    """A case control subcase's LABEL text ('' when none)."""
    if sub is None or "LABEL" not in sub.params:
        return ""
    value = sub.get_parameter("LABEL")[0]
    return str(value).strip() if value is not None else ""


def subcase_names(labels: dict[int, str], inherited: str = "") -> dict[int, str]:
    """Configuration name per subcase id: the subcase's own LABEL (one the global LABEL, which every
    subcase inherits, does not explain), else 'subcase_<id>'. A LABEL two subcases share, or one
    that is another subcase's 'subcase_<id>', falls back to 'subcase_<id>': names stay unique."""
    own = {sid: lab for sid, lab in labels.items() if lab and lab != inherited}
    taken = [lab for lab in own.values()]
    fallback = {f"subcase_{sid}" for sid in labels}
    return {sid: own[sid] if sid in own and taken.count(own[sid]) == 1 and own[sid] not in fallback
            else f"subcase_{sid}" for sid in labels}


class Named(dict):
    """A dict keyed by configuration name that also answers a labelled subcase's old name
    'subcase_<id>' (with a DeprecationWarning naming the new one)."""

    def __init__(self, items=(), aliases: dict[str, str] | None = None):
        super().__init__(items)
        self.aliases = dict(aliases or {})

    def _new(self, key):
        name = self.aliases.get(key) if isinstance(key, str) else None
        if name is not None and name in self.keys():
            import warnings
            warnings.warn(f"configuration '{key}' is now named after its subcase's LABEL: '{name}'",
                          DeprecationWarning, stacklevel=3)
        return name

    def __missing__(self, key):
        name = self._new(key)
        if name is None:
            raise KeyError(key)
        return self[name]

    def __contains__(self, key) -> bool:
        return super().__contains__(key) or (isinstance(key, str) and self.aliases.get(key) in self.keys())

    def get(self, key, default=None):
        return self[key] if key in self else default


def read_subcases(deck: Deck, model: Model, log: Findings, parts: Parts) -> Cases:
    """The configurations of a model all structure families have read (AUTOSPC needs its elements)."""
    reader = _Subcases(deck, model, log, parts.element_ids)
    reader.read()
    aliases = {f"subcase_{sid}": name for name, sid in reader.subcases.items() if name != f"subcase_{sid}"}
    return Cases(*(Named(d, aliases) for d in (reader.configurations, reader.subcases, reader.methods,
                                               reader.n_modes)), tuple(reader.constraint_sources))


class _Subcases:
    """The subcase family's reading of one deck."""

    def __init__(self, deck: Deck, model: Model, log: Findings, element_ids: dict[int, int]) -> None:
        self.deck, self.model, self.log, self.element_ids = deck, model, log, element_ids
        self.configurations: dict[str, Configuration] = {}
        self.subcases: dict[str, int] = {}
        self.methods: dict[str, EigenMethod | None] = {}
        self.n_modes: dict[str, int | None] = {}
        self.constraint_sources: list[int] = []
        self.mpc_set: int | None = None  # the MPC set read into model constraints
        self.autospc: list[int] = []  # nodes without elements, fixed in every configuration
        self.autospc_rotations: list[int] = []  # nodes without rotational stiffness: rotations fixed
        self.membrane_rotations: dict[int, set[int]] = {}  # membrane-only shell nodes: the rotations fixed

    def at(self, name: str, ident) -> str:
        return self.deck.at(name, ident)

    def _subcases(self) -> list[tuple[str, object, int]]:
        """(configuration name, case control subcase or None, subcase id) in reading order."""
        ccd = self.deck.bdf.case_control_deck
        subcases = {} if ccd is None else dict(ccd.subcases)
        numbered = {k: v for k, v in subcases.items() if k > 0}
        if numbered:
            names = subcase_names({sid: _label(sub) for sid, sub in numbered.items()}, _label(subcases.get(0)))
            return [(names[sid], sub, sid) for sid, sub in sorted(numbered.items())]
        if 0 in subcases and subcases[0].params:
            return [(self.deck.path.stem, subcases[0], 0)]
        return [(self.deck.path.stem, None, 0)]

    def read_constraints(self, cases) -> None:
        """The MPC set every subcase selects -> model linear constraints (translations; components
        in a grid's CD are expanded to basic axes). Different sets per subcase are listed unsupported."""
        ids = {self._get(sub, "MPC") for _, sub, _ in cases}
        self.mpc_set = None
        defined = set(self.deck.bdf.mpcs) | set(self.deck.bdf.mpcadds)
        unselected = sorted(defined - {int(i) for i in ids if i is not None})
        if unselected:
            self.log.note(f"MPC set(s) {unselected} selected by no subcase: ignored (as Nastran does)")
        if len(ids) != 1 or None in ids:
            return
        (conid,) = ids
        where = self.at("MPC", conid)
        cards = self._mpc_cards(int(conid), where, set())
        for card in cards:
            terms: dict[tuple[int, int], float] = {}
            dependent = None
            for k, (n, comp, coef) in enumerate(zip(card.nodes, card.components, card.coefficients)):
                comp = int(str(comp).strip() or 0)
                if comp not in (1, 2, 3, 4, 5, 6):
                    self.log.skip("MPC (scalar-point terms)", card.conid)
                    break
                if n not in self.deck.bdf.nodes:
                    raise ModelError(f"{where} refers to node {n}, which is not defined")
                axes = coord_axes(self.deck.bdf, self.deck.bdf.nodes[n].cd, self.deck.xyz_deck[n], where)
                e = axes[:, (comp - 1) % 3]
                base = 3 if comp > 3 else 0
                if k == 0:
                    big = int(np.argmax(np.abs(e)))
                    if abs(abs(e[big]) - 1.0) > 1e-9:
                        raise ModelError(f"{where}: the dependent term (node {n} component {comp}) lies along no basic "
                                         "axis in the grid's CD; give the grid a CD aligned with basic or make another "
                                         "term the first")
                    dependent = (int(n), base + big + 1)
                scale = float(coef) * (self.deck.units.length if comp > 3 else 1.0)  # rotation terms: deck -> SI units
                for j in range(3):
                    if abs(e[j]) > 1e-12:
                        key = (int(n), base + j + 1)
                        terms[key] = terms.get(key, 0.0) + scale * e[j]
            else:
                first = (dependent, terms.pop(dependent))
                try:
                    self.model.add_constraint([(*first[0], first[1])] + [(*key, a) for key, a in terms.items()])
                except ModelError as exc:
                    raise ModelError(f"{where}: {exc}") from None
                self.constraint_sources.append(int(card.conid))
        self.mpc_set = int(conid)

    def _mpc_cards(self, conid: int, where: str, seen: set) -> list:
        if conid in seen:
            raise ModelError(f"{where}: MPCADD sets refer to each other in a loop")
        seen.add(conid)
        out = []
        for card in self.deck.bdf.mpcadds.get(conid, []):
            for sub in card.sets:
                out += self._mpc_cards(int(sub), where, seen)
        out += list(self.deck.bdf.mpcs.get(conid, []))
        if not out:
            raise ModelError(f"{where}: the case control selects MPC = {conid} but no MPC or MPCADD card has that id")
        return out

    def read(self) -> None:
        bdf = self.deck.bdf
        cases = self._subcases()
        self.read_constraints(cases)
        connected = {int(n) for g in (*self.model.beams, *self.model.shells) for n in g.nodes.ravel()}
        connected |= {t[0] for con in self.model.constraints for t in con.terms}
        connected |= {n for sp in self.model.springs for n in (sp.node_a, sp.node_b) if n is not None}
        connected |= {n for link in self.model.rigid_links for n in (link.independent, *link.dependents)}
        connected |= {n for ip in self.model.interpolations for n in (ip.reference, *ip.nodes)}
        self.autospc = sorted(set(bdf.nodes) - connected)
        # Nodes joined only by rods have no rotational stiffness or inertia: their rotations are fixed.
        rod_nodes = {int(n) for g in self.model.beams if isinstance(g.section, RodSection) for n in g.nodes.ravel()}
        # a membrane (PSHELL without MID2) turns its nodes only about its normal (the drilling DOF)
        membrane = membrane_rotation_fixes(self.model)
        bending_shells = [g for g in self.model.shells if getattr(g.property, "bending", True) is not None]
        bending = {int(n) for g in self.model.beams if not isinstance(g.section, RodSection) for n in g.nodes.ravel()}
        bending |= {int(n) for g in bending_shells for n in g.nodes.ravel()}
        bending |= {n for sp in self.model.springs for n in (sp.node_a, sp.node_b) if n is not None}
        bending |= {link.independent for link in self.model.rigid_links}
        bending |= {n for link in self.model.rigid_links if "4" in link.components for n in link.dependents}
        bending |= {ip.reference for ip in self.model.interpolations if "4" in ip.components}
        loose = {n for link in self.model.rigid_links if "4" not in link.components for n in link.dependents}
        loose |= {n for ip in self.model.interpolations for n in (*ip.nodes, ip.reference)} - bending
        self.autospc_rotations = sorted((rod_nodes | loose) - bending - set(membrane))
        self.membrane_rotations = {n: dofs for n, dofs in sorted(membrane.items()) if n not in bending and dofs}
        if str(self.deck.param("AUTOSPC", "YES")).upper() in ("NO", "N", "-1"):
            self.autospc, self.autospc_rotations, self.membrane_rotations = [], [], {}
        if self.autospc:
            self.log.note(f"node(s) {self.autospc[:10]}{' ...' if len(self.autospc) > 10 else ''} have no "
                              "element: fixed in every configuration (as Nastran's AUTOSPC does)")
        if self.autospc_rotations:
            r = self.autospc_rotations
            self.log.note(f"node(s) {r[:10]}{' ...' if len(r) > 10 else ''} have no rotational stiffness "
                              "(joined only by rods, RBE2s without 456 or RBE3s): their rotations are fixed in every "
                              "configuration (as Nastran's AUTOSPC does)")
        if self.membrane_rotations:
            r = list(self.membrane_rotations)
            self.log.note(f"node(s) {r[:10]}{' ...' if len(r) > 10 else ''} of membrane-only shells (PSHELL "
                          "without MID2): the rotations about axes in every membrane's plane are fixed in every "
                          "configuration (no element stiffens them); the drilling rotation about a membrane's "
                          "normal stays free (flexgvt's membrane uses it)")
        for name, sub, sid in cases:
            self.configuration(name, sub, sid)

    def _get(self, sub, key):
        if sub is None or key not in sub.params:
            return None
        value = sub.get_parameter(key)[0]
        if key in ("SPC", "LOAD", "MPC", "METHOD", "SUPORT1"):
            try:
                return int(value)
            except (TypeError, ValueError):
                raise ModelError(f"{self.deck.path}: case control {key} = {value!r} (SUBCASE {getattr(sub, 'id', 0)}) "
                                 "is not a set id; give the integer id of a bulk data set") from None
        return value

    def configuration(self, name: str, sub, sid: int) -> None:
        bdf = self.deck.bdf
        where = f"{self.deck.path}: subcase {sid}" if sub is not None and sid else f"{self.deck.path}"
        spc_id = self._get(sub, "SPC")
        load_id = self._get(sub, "LOAD")
        if sub is None:  # bulk data only: use the one SPC/load set if unambiguous
            spc_sets = set(bdf.spcs) | set(bdf.spcadds)
            load_sets = set(bdf.load_combinations) or set(bdf.loads)
            if len(spc_sets) == 1:
                spc_id = next(iter(spc_sets))
            elif spc_sets:
                self.log.note(f"{where}: no case control and several SPC sets {sorted(spc_sets)}: none applied; "
                                  "add a SUBCASE with SPC = ...")
            if len(load_sets) == 1:
                load_id = next(iter(load_sets))
            elif load_sets:
                self.log.note(f"{where}: no case control and several load sets {sorted(load_sets)}: none applied; "
                                  "add a SUBCASE with LOAD = ...")
        mpc_id = self._get(sub, "MPC")
        if mpc_id is not None and mpc_id != self.mpc_set:
            self.log.skip("MPC (different MPC sets per subcase)", mpc_id)
        fixed: dict[int, set[int]] = {}
        prescribed: dict[int, dict[int, float]] = {}
        for nid in self.autospc:
            fixed.setdefault(int(nid), set()).update(range(6))
        for nid in self.autospc_rotations:
            fixed.setdefault(int(nid), set()).update(range(3, 6))
        for nid, dofs in self.membrane_rotations.items():
            fixed.setdefault(int(nid), set()).update(dofs)
        for nid, node in bdf.nodes.items():
            if node.ps:
                self._fix(fixed, nid, str(node.ps), f"{self.at('GRID', nid)} (PS)")
        if spc_id is not None:
            for card in self._spc_cards(int(spc_id), where):
                if card.type == "SPC1":
                    for n in card.node_ids if hasattr(card, "node_ids") else card.nodes:
                        self._fix(fixed, n, str(card.components), self.at("SPC1", card.conid))
                elif card.type == "SPC":
                    for n, comp, val in zip(card.node_ids, card.components, card.enforced):
                        self._fix(fixed, n, str(comp), self.at("SPC", card.conid))
                        if val:
                            self._prescribe(prescribed, n, str(comp), float(val), self.at("SPC", card.conid))
                else:
                    self.log.skip(card.type, card.conid)
        forces, distributed, accel = [], [], np.zeros(3)
        gravity_terms = []
        if load_id is not None:
            for scale, card in self._load_cards(int(load_id), where):
                if card.type == "SPCD":  # enforced values of DOFs the SPC set holds
                    for n, comp, val in zip(card.node_ids, card.components, card.enforced):
                        self._prescribe(prescribed, n, str(comp), scale * float(val), self.at("SPCD", card.sid))
                    continue
                self._load(card, scale, forces, distributed, gravity_terms)
        kwargs = {}
        if gravity_terms:
            if len(gravity_terms) == 1:
                factor, a = gravity_terms[0]
                g = float(np.linalg.norm(a))
                kwargs = dict(gravity=factor, g=g, gravity_direction=tuple(a / g)) if g > 0 else {}
            else:
                accel = sum(f * a for f, a in gravity_terms)
                g = float(np.linalg.norm(accel))
                if g > 0:
                    kwargs = dict(gravity=1.0, g=g, gravity_direction=tuple(accel / g))
        fixed_spec = {n: "".join(str(c + 1) for c in sorted(cs)) for n, cs in sorted(fixed.items()) if cs}
        for n, items in prescribed.items():
            held = fixed.get(n, set())
            loose = sorted(c for c in items if c - 1 not in held)
            if loose:
                raise ModelError(f"{where}: SPCD on node {n} component(s) {''.join(map(str, loose))}, which the "
                                 "subcase's SPC set does not hold; Nastran enforces SPCD values only on SPC'd DOFs")
        support = self._support(sub)
        try:
            cfg = Configuration(name, fixed=fixed_spec, forces=tuple(forces), distributed=tuple(distributed),
                                prescribed=prescribed, support=support, **kwargs)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.configurations[name] = cfg
        self.subcases[name] = sid
        method = self._get(sub, "METHOD")
        eig = self._method(int(method), where) if method is not None else None
        self.methods[name] = eig
        self.n_modes[name] = eig.nd if eig is not None else None

    def _method(self, sid: int, where: str) -> EigenMethod | None:
        """EIGRL/EIGR ``sid`` as an EigenMethod (None, with a note, if the deck lacks it)."""
        eig = self.deck.bdf.methods.get(sid)
        if eig is None:
            self.log.note(f"{where}: METHOD = {sid} names no EIGRL/EIGR in the bulk data; 10 modes are computed")
            return None
        where = self.at(eig.type, sid)

        def num(v):
            return None if v is None or v == "" else float(v)
        nd = int(eig.nd) if getattr(eig, "nd", None) not in (None, "", 0) else None
        if nd is not None and nd < 0:
            raise ModelError(f"{where}: ND = {nd}; give the number of modes (a positive integer) or leave it blank")
        norm = (getattr(eig, "norm", None) or "MASS").upper()
        if norm not in ("MASS", "MAX", "POINT"):
            raise ModelError(f"{where}: NORM = {norm}; Nastran's real eigenvalue normalisations are MASS, MAX and "
                             "POINT")
        point = None
        if norm == "POINT":
            g, c = getattr(eig, "G", None), getattr(eig, "C", None)
            if not g or not c or int(g) not in self.deck.bdf.nodes or str(c).strip() not in tuple("123456"):
                raise ModelError(f"{where}: NORM = POINT needs the grid G (got {g}) and component C (got {c}, one of "
                                 "1-6) of an existing grid")
            point = (int(g), int(c))
        if eig.type == "EIGRL":
            return EigenMethod("EIGRL", sid, "LAN", nd, num(eig.v1), num(eig.v2), norm, point)
        method = str(eig.method or "LAN").upper()
        tridiagonal = method in ("GIV", "MGIV", "HOU", "MHOU", "AHOU")
        return EigenMethod("EIGR", sid, method, nd, num(eig.f1), num(eig.f2), norm, point,
                           window_with_nd=not tridiagonal)

    def _support(self, sub) -> dict[int, str]:
        """SUPORT (bulk data, every subcase) and the subcase's SUPORT1 set: reference DOFs of a free
        structure. Nastran uses them to split rigid-body from elastic motion; flexgvt solves the
        structure free-free (its rigid-body modes at 0 Hz, as Nastran prints them) and keeps them."""
        dofs: dict[int, set] = {}
        cards = list(getattr(self.deck.bdf, "suport", []) or [])
        sid = self._get(sub, "SUPORT1")
        if sid is not None:
            found = getattr(self.deck.bdf, "suport1", {}).get(int(sid))
            if found is None:
                raise ModelError(f"{self.deck.path}: the case control asks for SUPORT1 = {sid}, which the bulk data "
                                 "lacks; add the SUPORT1 set or remove the request")
            cards.append(found)
        for card in cards:
            for node, comps in zip(card.nodes, card.Cs):
                dofs.setdefault(int(node), set()).update(str(comps or ""))
        return {n: "".join(sorted(c)) for n, c in sorted(dofs.items()) if c}

    def _spc_cards(self, sid: int, where: str, depth: int = 0):
        bdf = self.deck.bdf
        if depth > 10:
            raise ModelError(f"{where}: SPCADD sets refer to each other in a loop (set {sid})")
        found = False
        out = []
        for card in bdf.spcadds.get(sid, []):
            found = True
            for s in card.sets if hasattr(card, "sets") else card.spc_ids:
                out += self._spc_cards(int(s), where, depth + 1)
        if sid in bdf.spcs:
            found = True
            out += list(bdf.spcs[sid])
        if not found:
            raise ModelError(f"{where}: SPC = {sid} but no SPC, SPC1 or SPCADD card has set id {sid}; add it or fix "
                             "the case control")
        return out

    def _load_cards(self, sid: int, where: str):
        bdf = self.deck.bdf
        if sid in bdf.load_combinations:
            out = []
            for combo in bdf.load_combinations[sid]:
                for s, lid in zip(combo.scale_factors, combo.load_ids):
                    if int(lid) not in bdf.loads:
                        raise ModelError(f"{self.at('LOAD', sid)} refers to load set {lid}, which has no FORCE, "
                                         "MOMENT, GRAV or PLOAD1 card; add it or fix the LOAD card")
                    out += [(combo.scale * s, card) for card in bdf.loads[int(lid)]]
            return out
        if sid in bdf.loads:
            return [(1.0, card) for card in bdf.loads[sid]]
        raise ModelError(f"{where}: LOAD = {sid} but no LOAD, FORCE, MOMENT, GRAV or PLOAD1 card has set id {sid}; "
                         "add it or fix the case control")

    def _fix(self, fixed: dict, nid: int, comps: str, where: str) -> None:
        if nid not in self.deck.bdf.nodes:
            raise ModelError(f"{where} refers to node {nid}, which is not defined")
        comps = comps.strip()
        if comps in ("", "0"):
            return
        dofs = sorted({int(c) for c in comps})
        if any(not 1 <= d <= 6 for d in dofs):
            raise FileFormatError(f"{where}: components {comps!r} must be digits 1-6")
        fixed.setdefault(int(nid), set()).update(basic_dofs(
            self.deck, nid, [d - 1 for d in dofs], where, "node", "constrained components",
            "flexgvt fixes DOFs in basic axes. Constrain all three translations/rotations, use a CD aligned with "
            "basic, or replace the SPC by a stiff CBUSH in that system"))

    def _prescribe(self, prescribed: dict, nid: int, comps: str, value: float, where: str) -> None:
        """Enforced value [deck units] on components of a node (basic axes only)."""
        if nid not in self.deck.bdf.nodes:
            raise ModelError(f"{where} refers to node {nid}, which is not defined")
        if self.deck.bdf.nodes[nid].cd not in (None, 0):
            raise ModelError(f"{where}: enforced values on node {nid}, whose CD is not basic, are not supported; "
                             "give the grid CD = 0 or enforce the motion with a stiff spring and a force")
        extent = float(np.ptp(self.model.xyz, axis=0).max()) if self.model.n_nodes > 1 else 0.0
        for c in comps.strip():
            d = int(c)
            si = value * (self.deck.units.length if d <= 3 else 1.0)
            # The static solver steps the enforced motion up in increments of a fraction of the
            # structure's size: 10 sizes took 400 steps (1.3 s), 1e8 would never finish.
            if d <= 3 and extent > 0 and abs(si) > MAX_ENFORCED_SIZES * extent:
                raise ModelError(f"{where}: enforced displacement {value:g} on node {nid} component {d} is more than "
                                 f"{MAX_ENFORCED_SIZES:g} times the structure's size "
                                 f"({extent / self.deck.units.length:.4g} in deck units); check the value and "
                                 "its units")
            if d > 3 and abs(si) > 2 * math.pi:
                raise ModelError(f"{where}: enforced rotation {value:g} rad on node {nid} component {d} is more than "
                                 "one turn (2 pi); check the value (rotations are in radians)")
            prescribed.setdefault(int(nid), {})[d] = si

    def _load(self, card, scale: float, forces: list, distributed: list, gravity_terms: list) -> None:
        bdf, u = self.deck.bdf, self.deck.units
        where = self.at(card.type, card.sid)
        if card.type in ("FORCE", "MOMENT"):
            nid = card.node
            if nid not in bdf.nodes:
                raise ModelError(f"{where} refers to node {nid}, which is not defined")
            T = coord_axes(bdf, card.cid, self.deck.xyz_deck[nid], where)
            vec = scale * card.mag * (T @ np.asarray(card.xyz, float))
            if card.type == "FORCE":
                forces.append(NodalLoad(int(nid), force=tuple(vec * u.force)))
            else:
                forces.append(NodalLoad(int(nid), moment=tuple(vec * u.moment)))
        elif card.type == "GRAV":
            if card.cid not in (None, 0) and card.cid not in bdf.coords:
                raise ModelError(f"{where} refers to coordinate system {card.cid}, which is not defined; add its CORD "
                                 "card or fix CID")
            if card.cid not in (None, 0) and bdf.coords[card.cid].Type != "R":
                self.log.skip("GRAV (curvilinear CID)", card.sid)
                return
            if getattr(card, "mb", 0):
                self.log.skip("GRAV (MB = -1: main bulk only)", card.sid)
            T = coord_axes(bdf, card.cid, np.zeros(3), where)
            a = card.scale * (T @ np.asarray(card.N, float)) * u.length
            gravity_terms.append((scale, a))
        elif card.type == "PLOAD1":
            self._pload1(card, scale, distributed, where)
        else:
            self.log.skip(card.type, card.sid)

    def _pload1(self, card, scale, distributed, where) -> None:
        u = self.deck.units
        eid = card.eid
        if eid not in self.element_ids:
            if eid not in self.deck.bdf.elements:
                raise ModelError(f"{where} refers to element {eid}, which is not defined")
            self.log.skip("PLOAD1 (on an element that was not read as a beam)", card.sid)
            return
        if card.load_type not in ("FX", "FY", "FZ"):
            self.log.skip(f"PLOAD1 (TYPE {card.load_type}: only FX, FY, FZ in basic axes)", card.sid)
            return
        elem = self.deck.bdf.elements[eid]
        n1, n2 = elem.node_ids[:2]
        axis = self.deck.xyz_deck[n2] - self.deck.xyz_deck[n1]
        L = float(np.linalg.norm(axis))
        x1, x2 = card.x1, card.x2
        p1, p2 = card.p1, card.p2 if card.p2 is not None else card.p1
        full = x2 is not None and math.isclose(x1 or 0.0, 0.0, abs_tol=1e-9) and (
            math.isclose(x2, 1.0, rel_tol=1e-6) if card.scale in ("FR", "FRPR") else math.isclose(x2, L, rel_tol=1e-6))
        if not full or not math.isclose(p1, p2, rel_tol=1e-9, abs_tol=0.0):
            self.log.skip("PLOAD1 (not uniform over the whole element)", card.sid)
            return
        direction = np.eye(3)["XYZ".index(card.load_type[1])]
        w = p1
        if card.scale in ("LEPR", "FRPR"):
            w = p1 * math.sqrt(max(0.0, 1.0 - (axis @ direction / L) ** 2))
        distributed.append(DistributedLoad((self.element_ids[eid],),
                                           tuple(scale * w * direction * u.force / u.length)))
