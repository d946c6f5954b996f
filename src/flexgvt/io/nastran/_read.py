"""Read a Nastran bulk data deck (pyNastran) into a flexgvt Model and one Configuration per subcase."""

from __future__ import annotations

import contextlib
import io
import math
import re
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ...errors import FileFormatError, FlexGVTError, ModelError
from ...model import Configuration, DistributedLoad, GeneralSection, Material, Model, NodalLoad, RodSection
from ._common import (CardIndex, EigenMethod, UnsupportedCardsError, Units, absolute_include_lines, coord_axes, get_units,
                      split_first_fields, where_prefix)
from ._sections import SectionData, from_properties, library_section

BEAM_CARDS = ("CBAR", "CBEAM")
ROD_CARDS = ("CROD", "CONROD")
BEAM_PROPERTIES = ("PBAR", "PBARL", "PBEAM", "PBEAML")
SUPPORTED_ELEMENTS = BEAM_CARDS + ROD_CARDS + ("CONM2", "CONM1", "CELAS1", "CELAS2", "CDAMP1", "CDAMP2", "CVISC", "CBUSH", "RBE2", "RBE3", "RBAR")
SUPPORTED_PROPERTIES = BEAM_PROPERTIES + ("PROD", "PELAS", "PDAMP", "PVISC", "PBUSH")
SUPPORTED_LOADS = ("FORCE", "MOMENT", "GRAV", "PLOAD1", "SPCD")
# Cards that carry no structure or are read through the case control (methods, solution controls).
IGNORED_CARDS = {"ENDDATA", "PARAM", "EIGRL", "EIGR", "NLPARM", "NLPCI", "MDLPRM", "DTI", "TSTEPNL", "TSTEP", "FREQ",
                 "FREQ1", "FREQ2", "NLSTEP", "USET", "USET1"}
# Cards that do not change the structure, its constraints or static loads (aerodynamics, design
# optimisation, dynamic loading, output): ignored with one note naming them.
NON_STRUCTURAL = {"AERO", "AEROS", "CAERO1", "CAERO2", "CAERO3", "CAERO4", "CAERO5", "PAERO1", "PAERO2", "PAERO3",
                  "PAERO4", "PAERO5", "SPLINE1", "SPLINE2", "SPLINE3", "SPLINE4", "SPLINE5", "SET1", "SET2", "SET3",
                  "AELIST", "AESURF", "AESURFS", "AESTAT", "AELINK", "AEPARM", "AEFACT", "TRIM", "TRIM2", "FLUTTER",
                  "FLFACT", "MKAERO1", "MKAERO2", "MONPNT1", "MONPNT2", "MONPNT3", "CSSCHD", "GUST", "DIVERG",
                  "DESVAR", "DVPREL1", "DVPREL2", "DVMREL1", "DVMREL2", "DVCREL1", "DVCREL2", "DVGRID", "DRESP1",
                  "DRESP2", "DRESP3", "DCONSTR", "DCONADD", "DOPTPRM", "DEQATN", "DTABLE", "DLINK", "DSCREEN",
                  "DLOAD", "TLOAD1", "TLOAD2", "RLOAD1", "RLOAD2", "TABLED1", "TABLED2", "TABLED3", "TABLED4",
                  "TABDMP1", "TABRND1", "TABRNDG", "DAREA", "DELAY", "DPHASE", "RANDPS", "NLCNTLG", "MONDSP1", "EPOINT", "AECOMP",
                  "AECOMPL", "PLOTEL", "UXVEC", "AEDW", "AEFORCE", "AEPRESS", "SPLINRB"}
# Static (Guyan) reduction sets: flexgvt solves the full model (named in a note).
REDUCTION_CARDS = {"ASET", "ASET1", "OMIT", "OMIT1"}
# Bulk cards flexgvt reads (anything else present in the deck is reported as unsupported).
READ_CARDS = set(SUPPORTED_ELEMENTS + SUPPORTED_PROPERTIES + SUPPORTED_LOADS) | {
    "GRID", "GRDSET", "MAT1", "CORD2R", "CORD2C", "CORD2S", "CORD1R", "CORD1C", "CORD1S", "SPC", "SPC1", "SPCADD", "LOAD",
    "MPC", "MPCADD", "SUPORT", "SUPORT1", "CMASS1", "CMASS2", "PMASS"}
# Cards read by pyNastran into dictionaries we inspect, mapped to where unsupported ones are listed.
# Id namespaces as pyNastran keeps them (Nastran accepts, e.g., an RBAR and a CONM2 with the same id).
ELEMENT_NAMESPACE = ("CBAR", "CBEAM", "CROD", "CONROD", "CTUBE", "CQUAD4", "CTRIA3", "CQUAD8", "CTRIA6", "CQUADR",
                     "CTRIAR", "CSHEAR", "CHEXA", "CPENTA", "CTETRA", "CELAS1", "CELAS2", "CELAS3", "CELAS4", "CDAMP1",
                     "CDAMP2", "CDAMP3", "CDAMP4", "CVISC", "CBUSH", "CBUSH1D", "CGAP")
MASS_NAMESPACE = ("CONM1", "CONM2", "CMASS1", "CMASS2", "CMASS3", "CMASS4")
RIGID_NAMESPACE = ("RBE2", "RBE3", "RBAR", "RBE1", "RROD", "RSPLINE")
PROPERTY_NAMESPACE = ("PBAR", "PBARL", "PBEAM", "PBEAML", "PROD", "PTUBE", "PSHELL", "PCOMP", "PCOMPG", "PSHEAR",
                      "PSOLID", "PELAS", "PDAMP", "PVISC", "PBUSH", "PBUSH1D", "PGAP", "PMASS")
MATERIAL_NAMESPACE = ("MAT1", "MAT2", "MAT8", "MAT9")
COORD_NAMESPACE = ("CORD2R", "CORD2C", "CORD2S", "CORD1R", "CORD1C", "CORD1S")
STRUCTURAL_PARAMS_IGNORED = {"G": "structural damping (PARAM,G) is not modelled",
                             "W3": "PARAM,W3 (structural damping reference) is not modelled",
                             "W4": "PARAM,W4 (element damping reference) is not modelled"}


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


@dataclass
class BdfDeck:
    """A bulk data deck read into flexgvt.

    model: the structural model; configurations: one per SUBCASE (or one named after the file);
    bdf: the pyNastran BDF object (kept for writing back); units: the deck's unit system; wtmass:
    PARAM,WTMASS; mass: 'lumped' or 'consistent' (PARAM,COUPMASS); beams: beam group name ->
    BeamSource; element_ids: Nastran beam element id -> flexgvt element id; mass_sources and
    spring_sources: (card, id) per entry of model.masses / model.springs; rigid_sources: RBE2 ids
    per model.rigid_links, or (card, element id, end) for the link of an end node; end_nodes:
    (card, element id, end 'A'/'B') -> the node flexgvt added for a CBAR/CBEAM offset or pin
    flag, or the CBUSH end's arm to the spring location (ids above the deck's grids);
    interpolation_sources: RBE3 id per model.interpolations; constraint_sources: MPC set id per
    model.constraints (the one set all subcases select); n_modes: configuration -> EIGRL ND of its METHOD (None if not given);
    methods: configuration -> its EigenMethod (EIGRL/EIGR: ND, window, normalisation) or None;
    subcases: configuration -> subcase id; unsupported: card (feature) -> ids that were not read;
    notes: things read with an approximation or ignored on purpose.
    """

    path: Path
    model: Model
    configurations: dict[str, Configuration]
    bdf: object
    units: Units
    wtmass: float
    mass: str
    beams: dict[str, BeamSource] = field(default_factory=dict)
    element_ids: dict[int, int] = field(default_factory=dict)
    mass_sources: list[tuple[str, int]] = field(default_factory=list)
    spring_sources: list[tuple[str, int]] = field(default_factory=list)
    rigid_sources: list[tuple] = field(default_factory=list)
    end_nodes: dict[tuple[str, int, str], int] = field(default_factory=dict)
    interpolation_sources: list[int] = field(default_factory=list)
    constraint_sources: list[int] = field(default_factory=list)
    materials: dict[int, Material] = field(default_factory=dict)
    n_modes: dict[str, int | None] = field(default_factory=dict)
    methods: dict[str, EigenMethod | None] = field(default_factory=dict)
    subcases: dict[str, int] = field(default_factory=dict)
    unsupported: dict[str, list] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def __repr__(self) -> str:
        return (f"BdfDeck('{self.path.name}': {self.model!r}, configurations={list(self.configurations)}, "
                f"units={self.units.name}, wtmass={self.wtmass}, mass='{self.mass}')")


class _QuietLog:
    """Logger handed to pyNastran: keeps its messages (for error context) instead of printing them."""

    level = "error"

    def __init__(self):
        self.messages: list[str] = []

    def _keep(self, msg, *args, **kwargs):
        self.messages.append(str(msg))

    debug = info = warning = error = exception = critical = _keep

    def __getattr__(self, name):  # any other cpylog method
        if name.startswith("__"):
            raise AttributeError(name)
        return self._keep

    def __deepcopy__(self, memo):
        return _QuietLog()


def _open_bdf(path: Path, index: CardIndex):
    """pyNastran BDF of ``path`` (with or without executive/case control), errors as FileFormatError."""
    from pyNastran.bdf.bdf import BDF

    if index.missing_includes:
        f, ln, target = index.missing_includes[0]
        raise FileFormatError(f"{f}:{ln}: INCLUDE file {target} does not exist; fix the path (relative paths are "
                              "taken from the main deck's folder)")
    with open(path, "r", errors="replace") as handle:
        lines = handle.readlines()
    if not any(line.strip() and not line.lstrip().startswith("$") for line in lines):
        raise FileFormatError(f"{path}: the file is empty; give a Nastran bulk data deck")
    has_cend = any(line.strip().upper().startswith("CEND") for line in lines)
    has_begin = any(line.strip().upper().replace(" ", "").startswith("BEGINBULK") for line in lines)
    lines = absolute_include_lines(lines, path.resolve().parent)
    punch = False
    if not has_cend:
        if has_begin:
            lines = ["CEND\n"] + lines
        else:
            punch = True
    log = _QuietLog()
    bdf = BDF(log=log)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            bdf.read_bdf(io.StringIO("".join(lines)), xref=False, punch=punch, validate=True)
    except FlexGVTError:
        raise
    except Exception as exc:  # pyNastran raises many kinds; translate them into one message
        raise _parse_error(path, index, exc, log) from None
    bdf.bdf_filename = str(path)
    return bdf


_CARD_IN_MSG = re.compile(r"card\s*=\s*\[\s*'([A-Za-z0-9*]+)'\s*,\s*'?([^',\]]*)'?")


def _parse_error(path: Path, index: CardIndex, exc: Exception, log: _QuietLog) -> FileFormatError:
    text = str(exc).strip()
    where = str(path)
    card = ""
    found = _CARD_IN_MSG.search(text) or next((m for m in (_CARD_IN_MSG.search(x) for x in log.messages[::-1]) if m),
                                              None)
    if found is None:
        for msg in log.messages[::-1]:
            if msg.startswith("problem adding"):
                found = re.search(r"\[\s*'([A-Za-z0-9*]+)'\s*,\s*'?([^',\]]*)'?", msg)
                if found:
                    break
    if found is not None:
        name, ident = found.group(1).upper().rstrip("*"), found.group(2).strip()
        place = index.where(name, ident)
        where = place or where
        card = f" in {name} {ident}"
    first = text.splitlines()[0] if text else type(exc).__name__
    hint = "fix the field named above (see the Nastran Quick Reference Guide for the card's format)"
    if isinstance(exc, (AssertionError,)) and ("old_" in text or "duplicate" in text.lower()):
        return FileFormatError(f"{where}: duplicate id{card}: {first}; give every card a unique id")
    return FileFormatError(f"{where}: cannot read the deck{card}: {first}; {hint}")


def _check_duplicates(path: Path, index: CardIndex) -> None:
    problems = []
    for label, names in (("node", ("GRID",)), ("element", ELEMENT_NAMESPACE), ("mass element", MASS_NAMESPACE),
                         ("rigid element", RIGID_NAMESPACE), ("property", PROPERTY_NAMESPACE),
                         ("material", MATERIAL_NAMESPACE), ("coordinate system", COORD_NAMESPACE)):
        for ident, hits in index.duplicates(names).items():
            places = ", ".join(f"{card} at {f}:{ln}" for card, f, ln in hits[:4])
            problems.append(f"{label} id {ident} is defined {len(hits)} times ({places})")
    if problems:
        raise ModelError(f"{path}: duplicate ids: " + "; ".join(problems[:10]) +
                         ("; ..." if len(problems) > 10 else "") + ". Give every node, element, property, material "
                         "and coordinate system a unique id")


class _Reader:
    def __init__(self, path: Path, units: Units, mass: str | None, rotary_inertia: bool,
                 cbar_torsional_inertia: bool = False):
        self.cbar_torsional_inertia = cbar_torsional_inertia
        self.path = path
        self.units = units
        self.index = CardIndex(path)
        _check_duplicates(path, self.index)
        self.bdf = _open_bdf(path, self.index)
        self.rotary_inertia = rotary_inertia
        self.mass_override = mass
        self.unsupported: dict[str, list] = {}
        self.notes: list[str] = []
        self.missing: list[str] = []
        self.pending_links: list[tuple] = []  # (grid, end node, components, source) for attach_end_nodes
        self.pending_rbe3: list[tuple] = []  # (eid, reference, REFC, {node: weight}) for read_interpolations

    # ----------------------------------------------------------------- helpers
    def at(self, name: str, ident) -> str:
        return where_prefix(self.index, name, ident)

    def skip(self, what: str, ident) -> None:
        self.unsupported.setdefault(what, []).append(ident)

    def param(self, name: str, default):
        p = self.bdf.params.get(name)
        if p is None:
            return default
        values = getattr(p, "values", None) or [default]
        return values[0] if values[0] is not None else default

    # ----------------------------------------------------------------- references
    def check_references(self) -> None:
        bdf, miss = self.bdf, self.missing
        nodes, coords = bdf.nodes, bdf.coords
        for nid, node in nodes.items():
            for label, cid in (("CP", node.cp), ("CD", node.cd)):
                if cid not in (None, 0, -1) and cid not in coords:
                    miss.append(f"{self.at('GRID', nid)} uses {label}={cid} but coordinate system {cid} is not defined")
        for cid, coord in coords.items():
            rid = getattr(coord, "rid", 0)
            if rid not in (None, 0) and rid not in coords:
                miss.append(f"{self.at(coord.type, cid)} refers to RID={rid}, which is not defined")
            for g in (getattr(coord, "g1", None), getattr(coord, "g2", None), getattr(coord, "g3", None)):
                if coord.type.startswith("CORD1") and g is not None and g not in nodes:
                    miss.append(f"{self.at(coord.type, cid)} refers to node {g}, which is not defined")
        for eid, elem in bdf.elements.items():
            ids = [n for n in (elem.node_ids if hasattr(elem, "node_ids") else []) if n not in (None, 0)]
            for n in ids:
                if n not in nodes:
                    miss.append(f"{self.at(elem.type, eid)} refers to node {n}, which is not defined")
            pid = getattr(elem, "pid", None)
            if elem.type in ("CBAR", "CBEAM", "CROD", "CELAS1", "CDAMP1", "CVISC", "CBUSH") and pid not in bdf.properties:
                miss.append(f"{self.at(elem.type, eid)} refers to property {pid}, which is not defined")
            g0 = getattr(elem, "g0", None)
            if elem.type in ("CBAR", "CBEAM", "CBUSH") and g0 not in (None, 0) and g0 not in nodes:
                miss.append(f"{self.at(elem.type, eid)} orientation node G0={g0} is not defined")
            if elem.type == "CONROD" and elem.mid not in bdf.materials:
                miss.append(f"{self.at(elem.type, eid)} refers to material {elem.mid}, which is not defined")
            cid = getattr(elem, "cid", None)
            if elem.type in ("CBUSH",) and cid not in (None, -1, 0) and cid not in coords:
                miss.append(f"{self.at(elem.type, eid)} refers to coordinate system {cid}, which is not defined")
        for eid, elem in bdf.masses.items():
            refs = [elem.nid] if hasattr(elem, "nid") else [n for n in getattr(elem, "nodes", []) if n not in (None, 0)]
            for n in refs:
                if n not in nodes:
                    miss.append(f"{self.at(elem.type, eid)} refers to node {n}, which is not defined")
            if getattr(elem, "cid", 0) not in (None, -1, 0) and elem.cid not in coords:
                miss.append(f"{self.at(elem.type, eid)} refers to coordinate system {elem.cid}, which is not defined")
        for eid, elem in bdf.rigid_elements.items():
            for n in elem.independent_nodes + elem.dependent_nodes:
                if n not in nodes:
                    miss.append(f"{self.at(elem.type, eid)} refers to node {n}, which is not defined")
        for pid, prop in bdf.properties.items():
            mid = getattr(prop, "mid", None)
            if (prop.type in BEAM_PROPERTIES or prop.type == "PROD") and mid not in bdf.materials:
                miss.append(f"{self.at(prop.type, pid)} refers to material {mid}, which is not defined")
        if miss:
            raise ModelError(f"{self.path}: missing references: " + "; ".join(miss[:12]) +
                             ("; ..." if len(miss) > 12 else "") + ". Add the missing cards or fix the ids")

    # ----------------------------------------------------------------- main
    def read(self) -> BdfDeck:
        bdf = self.bdf
        grdset = getattr(bdf, "grdset", None)
        if grdset is not None:  # GRDSET defaults for blank GRID fields (pyNastran reads blanks as 0)
            for node in bdf.nodes.values():
                node.cp = node.cp or (grdset.cp or 0)
                node.cd = node.cd or (grdset.cd or 0)
                node.ps = node.ps or (grdset.ps or "")
            bdf.grdset = None
            self.notes.append("GRDSET defaults applied to GRID fields that are blank or 0")
        self.check_references()
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                bdf.cross_reference(xref=True, xref_nodes=True, xref_elements=False, xref_nodes_with_elements=False,
                                    xref_properties=False, xref_masses=False, xref_materials=False, xref_loads=False,
                                    xref_constraints=False, xref_aero=False, xref_sets=False, xref_optimization=False)
        except FlexGVTError:
            raise
        except Exception as exc:
            raise ModelError(f"{self.path}: coordinate systems or grids could not be resolved: "
                             f"{str(exc).splitlines()[0] if str(exc) else type(exc).__name__}; check CORD/GRID cards")
        u = self.units
        self.wtmass = float(self.param("WTMASS", 1.0))
        if not (math.isfinite(self.wtmass) and self.wtmass > 0):
            raise ModelError(f"{self.path}: PARAM,WTMASS={self.wtmass} must be a positive number")
        coupmass = self.param("COUPMASS", -1)
        if isinstance(coupmass, str):
            coupmass = 1 if coupmass.upper() in ("ON", "YES") else -1
        self.mass = self.mass_override or ("consistent" if coupmass > 0 else "lumped")
        for name, why in STRUCTURAL_PARAMS_IGNORED.items():
            if name in bdf.params:
                self.notes.append(why)

        model = Model(self.path.stem)
        self.model = model
        nids = sorted(bdf.nodes)
        if not nids:
            raise ModelError(f"{self.path}: the deck has no GRID cards; a model needs nodes")
        xyz = np.array([bdf.nodes[n].get_position() for n in nids], float).reshape(-1, 3) * u.length
        bad = np.flatnonzero(~np.all(np.isfinite(xyz), axis=1))
        if len(bad):
            raise ModelError(f"{self.at('GRID', nids[bad[0]])}: coordinates {xyz[bad[0]] / u.length} are not finite "
                             f"({len(bad)} grid(s)); give real numbers for X1-X3")
        self.xyz = dict(zip(nids, xyz))
        self.xyz_deck = {n: x / u.length for n, x in self.xyz.items()}
        model.add_nodes(xyz, ids=nids)
        self.deck = BdfDeck(self.path, model, {}, bdf, u, self.wtmass, self.mass)
        self.read_materials()
        self.read_beams()
        self.read_rods()
        self.read_masses()
        self.read_springs()
        self.read_rigid()
        self.attach_end_nodes()
        self.read_interpolations()
        self.list_other_cards()
        self.read_configurations()
        self.deck.unsupported = self.unsupported
        self.deck.notes = self.notes
        return self.deck

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
            consistent = G and nu is not None and math.isclose(G, E / (2 * (1 + nu)), rel_tol=1e-6)
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
    def beam_section(self, prop) -> tuple[SectionData, float] | None:
        """(section, nsm per length in deck units) of a beam property, or None if unsupported (recorded)."""
        where = self.at(prop.type, prop.pid)
        if prop.type == "PBAR":
            return from_properties(where, prop.A, prop.i1, prop.i2, prop.i12, prop.j, prop.k1, prop.k2), prop.nsm or 0.0
        if prop.type == "PBARL":
            if prop.Type not in _supported_shapes():
                self.skip(f"PBARL TYPE {prop.Type}", prop.pid)
                return None
            return library_section(where, prop.Type, prop.dim), prop.nsm or 0.0
        if prop.type == "PBEAM":
            for name in ("A", "i1", "i2", "i12", "j", "nsm"):
                vals = np.atleast_1d(np.asarray(getattr(prop, name), float))
                if not np.allclose(vals, vals[0], rtol=1e-9, atol=0.0):
                    self.skip("PBEAM (tapered: stations differ)", prop.pid)
                    return None
            offsets = [getattr(prop, n, None) for n in ("m1a", "m2a", "m1b", "m2b", "n1a", "n2a", "n1b", "n2b")]
            if any(np.any(np.asarray(o, float) != 0) for o in offsets if o is not None):
                self.skip("PBEAM (neutral-axis/NSM offsets)", prop.pid)
                return None
            first = (lambda v: float(np.atleast_1d(v)[0]))
            sdata = from_properties(where, first(prop.A), first(prop.i1), first(prop.i2), first(prop.i12),
                                    first(prop.j), prop.k1, prop.k2)
            nsi = [float(v) for v in (prop.nsia, prop.nsib) if v is not None]
            if nsi and any(nsi):
                if not np.allclose(nsi, nsi[0], rtol=1e-9, atol=0.0):
                    self.skip("PBEAM (NSIA != NSIB: tapered torsional inertia)", prop.pid)
                    return None
                rho = self.bdf.materials[prop.mid].rho or 0.0
                if not rho:
                    self.skip("PBEAM (NSI on a massless material)", prop.pid)
                    return None
                # NSI: extra mass moment of inertia per length; flexgvt keeps it in rho * Ip.
                sec = sdata.section
                sdata = replace(sdata, section=replace(sec, Ip=sec.polar + nsi[0] / rho))
            return sdata, first(prop.nsm)
        if prop.type == "PBEAML":
            dims = [list(map(float, d)) for d in prop.dim]
            if any(not np.allclose(d, dims[0]) for d in dims):
                self.skip("PBEAML (tapered: stations differ)", prop.pid)
                return None
            if prop.beam_type not in _supported_shapes():
                self.skip(f"PBEAML TYPE {prop.beam_type}", prop.pid)
                return None
            nsm = float(np.atleast_1d(prop.nsm)[0]) if prop.nsm is not None else 0.0
            return library_section(where, prop.beam_type, dims[0]), nsm
        return None

    def orientation_vector(self, elem) -> np.ndarray:
        """Nastran v vector of a CBAR/CBEAM/CBUSH in basic axes (deck length units)."""
        ga = elem.nodes[0] if hasattr(elem, "nodes") else elem.ga
        if elem.g0 not in (None, 0):
            return self.xyz_deck[elem.g0] - self.xyz_deck[ga]
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
            where = self.at(elem.type, eid)
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
            try:
                ids = model.add_beams(pairs, mat, section, orientation=orient, rotary_inertia=self.rotary_inertia,
                                      mass=self.mass, name=name)
            except ModelError as exc:
                raise ModelError(f"{self.at(prop.type, pid)}: {exc}") from None
            eids = tuple(int(e.eid) for e in elems)
            self.deck.element_ids.update(dict(zip(eids, (int(i) for i in ids))))
            self.deck.beams[name] = BeamSource(name, elems[0].type, prop.type, int(pid), int(prop.mid), eids,
                                               sdata.principal)
            if nsm:  # Nastran's lumped mass puts NSM*L/2 on each end (translations only): exact for lumped mass
                self._lumped_nsm(pairs, nsm, prop.type, pid)

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
                self._lumped_nsm(pairs, float(nsm), ptype, pid)

    def _lumped_nsm(self, pairs: np.ndarray, nsm: float, card: str, ident) -> None:
        """Non-structural mass per length NSM (deck units) as point masses NSM L / 2 at the element ends."""
        u = self.units
        nsm_si = nsm * u.mass / u.length * self.wtmass
        ends: dict[int, float] = {}
        for p in pairs:
            L = float(np.linalg.norm(self.xyz[p[1]] - self.xyz[p[0]]))
            for n in p:
                ends[int(n)] = ends.get(int(n), 0.0) + 0.5 * nsm_si * L
        for n, m in ends.items():
            self.model.add_mass(n, m)
            self.deck.mass_sources.append((f"NSM:{card}", int(ident)))
        if self.mass == "consistent":
            self.notes.append(f"{self.at(card, ident)}: NSM={nsm} lumped at the element ends (Nastran distributes "
                              "it consistently under COUPMASS)")

    # ----------------------------------------------------------------- masses
    def read_masses(self) -> None:
        bdf, model, u, w = self.bdf, self.model, self.units, self.wtmass
        for eid, elem in sorted(bdf.masses.items()):
            where = self.at(elem.type, eid)
            if elem.type == "CONM2":
                cid = elem.cid
                x = np.asarray(elem.X, float)
                node_xyz = self.xyz_deck[elem.nid]
                if cid == -1:
                    offset, T = x - node_xyz, np.eye(3)
                else:
                    if cid not in (None, 0) and bdf.coords[cid].Type != "R":
                        self.skip("CONM2 (curvilinear CID)", eid)
                        continue
                    T = coord_axes(bdf, cid, node_xyz, where)
                    offset = T @ x
                I11, I21, I22, I31, I32, I33 = np.asarray(elem.I, float)
                J = np.array([[I11, -I21, -I31], [-I21, I22, -I32], [-I31, -I32, I33]])
                J = T @ J @ T.T
                try:
                    model.add_mass(elem.nid, float(elem.mass) * u.mass * w, offset=offset * u.length,
                                   inertia=J * u.inertia * w)
                except ModelError as exc:
                    raise ModelError(f"{where}: {exc}") from None
                self.deck.mass_sources.append(("CONM2", int(eid)))
            elif elem.type == "CONM1":
                M = np.asarray(elem.mass_matrix, float)
                M = np.tril(M) + np.tril(M, -1).T
                T = coord_axes(bdf, elem.cid, self.xyz_deck[elem.nid], where)
                T6 = np.zeros((6, 6))
                T6[:3, :3] = T6[3:, 3:] = T
                M = T6 @ M @ T6.T
                got = _rigid_mass(M)
                if got is None:
                    self.skip("CONM1 (not a rigid-body mass matrix)", eid)
                    continue
                m, r, J = got
                model.add_mass(elem.nid, m * u.mass * w, offset=r * u.length, inertia=J * u.inertia * w)
                self.deck.mass_sources.append(("CONM1", int(eid)))
            elif elem.type in ("CMASS1", "CMASS2"):
                self._scalar_mass(elem, where)
            else:
                self.skip(elem.type, eid)

    def _scalar_mass(self, elem, where: str) -> None:
        """CMASS1/CMASS2 on one grid's rotational component: an inertia m e e^T about that axis of the
        grid's displacement system (CD). A scalar mass on a translational component (mass in one
        direction only) or between two grids has no flexgvt counterpart and is named unsupported."""
        bdf, u, w = self.bdf, self.units, self.wtmass
        n1, n2 = (list(elem.nodes) + [None, None])[:2]
        c1 = int(getattr(elem, "c1", 0) or 0)
        if n2 not in (None, 0) or n1 in (None, 0):
            self.skip(f"{elem.type} (between two grids or on a scalar point)", elem.eid)
            return
        if not 4 <= c1 <= 6:
            self.skip(f"{elem.type} (translational component: a mass in one direction only)", elem.eid)
            return
        m = float(bdf.properties_mass[elem.pid].mass) if elem.type == "CMASS1" else float(elem.mass)
        axis = coord_axes(bdf, bdf.nodes[n1].cd, self.xyz_deck[n1], where)[:, c1 - 4]
        J = m * np.outer(axis, axis) * u.inertia * w
        try:
            self.model.add_mass(n1, 0.0, inertia=J)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.deck.mass_sources.append((elem.type, int(elem.eid)))

    # ----------------------------------------------------------------- springs and dampers
    def _scalar(self, elem, value_stiff: float, value_damp: float) -> None:
        """CELAS/CDAMP: a scalar spring between (G1, C1) and (G2, C2) in the nodes' displacement axes."""
        bdf, u = self.bdf, self.units
        where = self.at(elem.type, elem.eid)
        n1, n2 = (list(elem.nodes) + [None, None])[:2]
        c1, c2 = int(elem.c1 or 0), int(elem.c2 or 0)
        ends = [(n, c) for n, c in ((n1, c1), (n2, c2)) if n not in (None, 0)]
        if not ends or any(not 1 <= c <= 6 for _, c in ends):
            self.skip(f"{elem.type} (scalar points or component 0)", elem.eid)
            return
        comps = {c for _, c in ends}
        axes = [coord_axes(bdf, bdf.nodes[n].cd, self.xyz_deck[n], where) for n, _ in ends]
        c = ends[0][1]
        if len(comps) > 1 or (len(ends) == 2 and not np.allclose(axes[0][:, (c - 1) % 3], axes[1][:, (c - 1) % 3],
                                                                 atol=1e-9)):
            self.skip(f"{elem.type} (components along different directions)", elem.eid)
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
            self.model.add_spring(a, b, stiffness=k, damping=d, frame=frame)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.deck.spring_sources.append(source)

    def read_springs(self) -> None:
        bdf, u = self.bdf, self.units
        for eid, elem in sorted(bdf.elements.items()):
            t = elem.type
            where = self.at(t, eid)
            if t in ("CELAS1", "CELAS2"):
                prop = bdf.properties[elem.pid] if t == "CELAS1" else None
                k = prop.k if prop is not None else elem.k
                ge = prop.ge if prop is not None else elem.ge
                if ge:
                    self.notes.append(f"{where}: structural damping GE={ge} is not modelled")
                self._scalar(elem, float(k), 0.0)
            elif t in ("CDAMP1", "CDAMP2"):
                b = bdf.properties[elem.pid].b if t == "CDAMP1" else elem.b
                self._scalar(elem, 0.0, float(b))
            elif t == "CVISC":
                prop = bdf.properties[elem.pid]
                n1, n2 = elem.nodes
                ex = self.xyz[n2] - self.xyz[n1]
                if np.linalg.norm(ex) == 0:
                    raise ModelError(f"{where}: the two nodes of a CVISC coincide; its line of action is undefined")
                frame = _frame_from_x(ex)
                d = np.array([prop.ce * u.force / u.length, 0, 0, (prop.cr or 0.0) * u.moment, 0, 0])
                self._add_spring(where, n1, n2, np.zeros(6), d, frame, ("CVISC", int(eid)))
            elif t == "CBUSH":
                self.read_cbush(elem, where)

    def read_cbush(self, elem, where) -> None:
        bdf, u = self.bdf, self.units
        prop = bdf.properties[elem.pid]
        ga, gb = (list(elem.nodes) + [None])[:2]
        gb = None if gb in (None, 0) else gb
        coincident = gb is None or np.linalg.norm(self.xyz_deck[gb] - self.xyz_deck[ga]) <= 1e-4
        if not coincident and getattr(elem, "ocid", -1) not in (None, -1):
            self.skip("CBUSH (spring location given in OCID)", elem.eid)
            return
        if elem.cid not in (None, -1):
            frame = coord_axes(bdf, elem.cid, self.xyz_deck[ga], where)
        elif coincident:
            raise ModelError(f"{where}: a CBUSH on coincident nodes (or grounded) needs CID; Nastran rejects it too. "
                             "Give CID = 0 for basic axes")
        else:  # element axes: x from GA to GB, y from the orientation vector
            v = None if elem.g0 in (None, 0) and (elem.x is None or any(c is None for c in elem.x)) \
                else self.orientation_vector(elem)
            ex = self.xyz_deck[gb] - self.xyz_deck[ga]
            ex = ex / np.linalg.norm(ex)
            ez = None if v is None else np.cross(ex, v)
            if ez is None or np.linalg.norm(ez) <= 1e-8 * np.linalg.norm(v):
                raise ModelError(f"{where}: a CBUSH between distinct points without CID needs an orientation vector "
                                 "(X1-X3 or G0) off the line GA-GB")
            ez = ez / np.linalg.norm(ez)
            frame = np.column_stack([ex, np.cross(ez, ex), ez])
        if not coincident:  # rigid arms from GA and GB to the spring location, S along GA-GB
            s_loc = 0.5 if getattr(elem, "s", None) is None else float(elem.s)
            at = self.xyz_deck[ga] + s_loc * (self.xyz_deck[gb] - self.xyz_deck[ga])
            ga = self._end_node(int(ga), at, "123456", ("CBUSH", int(elem.eid), "A"))
            gb = self._end_node(int(gb), at, "123456", ("CBUSH", int(elem.eid), "B"))
        def six(values):
            vals = list(values or [])
            return np.array([float(v) if v is not None else 0.0 for v in (vals + [0.0] * 6)[:6]])
        k = six(getattr(prop, "Ki", None))
        b = six(getattr(prop, "Bi", None))
        if any(getattr(prop, "GEi", None) or []):
            if any(v for v in prop.GEi if v):
                self.notes.append(f"{where}: structural damping GE of PBUSH {prop.pid} is not modelled")
        scale = np.r_[[u.force / u.length] * 3, [u.moment] * 3]
        self._add_spring(where, ga, gb, k * scale, b * scale, frame, ("CBUSH", int(elem.eid)))

    # ----------------------------------------------------------------- rigid elements
    def read_rigid(self) -> None:
        """RBE2 -> rigid links (components 123456, or translations with all or none of 456)."""
        links: dict[tuple[int, str], list[int]] = {}
        sources: dict[tuple[int, str], list[int]] = {}
        owner: dict[int, int] = {}
        for eid, elem in sorted(self.bdf.rigid_elements.items()):
            if elem.type == "RBE3":
                self._pending_rbe3(elem)
                continue
            if elem.type == "RBAR":  # all six DOFs of one end independent: an RBE2 with one dependent
                norm = {k: "".join(sorted(set(str(getattr(elem, k) or "").strip()))) for k in ("cna", "cnb", "cma", "cmb")}
                if norm["cna"] == "123456" and not norm["cnb"] and not norm["cma"] and norm["cmb"]:
                    gn, cm, gmi = elem.ga, norm["cmb"], [elem.gb]
                elif norm["cnb"] == "123456" and not norm["cna"] and not norm["cmb"] and norm["cma"]:
                    gn, cm, gmi = elem.gb, norm["cma"], [elem.ga]
                else:
                    self.skip("RBAR (independent DOFs at both ends)", eid)
                    continue
            elif elem.type == "RBE2":
                gn, cm, gmi = elem.gn, "".join(sorted(set(str(elem.cm)))), elem.Gmi
            else:
                self.skip(elem.type, eid)
                continue
            if set(cm) & set("456") not in (set(), set("456")):
                self.skip(f"{elem.type} (some of the rotations 456 only)", eid)
                continue
            deps = [int(n) for n in gmi]
            for d in deps:
                if d in owner:
                    raise ModelError(f"{self.at(elem.type, eid)}: node {d} is already a dependent of rigid element "
                                     f"{owner[d]}; a node can depend on one rigid element only (Nastran rejects this too)")
                owner[d] = eid
            key = (int(gn), cm)
            links[key] = links.get(key, []) + deps
            sources.setdefault(key, []).append(int(eid))
        # Chains (an independent node that is a dependent of a full RBE2) hang on the chain's root:
        # a node that moves rigidly with the root carries its dependents' offsets along.
        changed = True
        while changed:
            changed = False
            for key in list(links):
                parent = next((p for p, deps in links.items() if key[0] in deps and p[0] != key[0]), None)
                if parent is None:
                    continue
                if parent[1] != "123456":
                    raise ModelError(f"RBE2 {sources[key]}: its independent node {key[0]} is a dependent of RBE2 "
                                     f"{sources[parent]} with components {parent[1]}; chains through partial RBE2s "
                                     "are not supported. Make the first RBE2 depend on the chain's root directly")
                new = (parent[0], key[1])
                links[new] = links.get(new, []) + links.pop(key)
                sources[new] = sources.get(new, []) + sources.pop(key)
                changed = True
                break
        for (ind, cm), deps in links.items():
            if ind in deps:
                raise ModelError(f"RBE2 {sources[(ind, cm)]}: the rigid elements form a loop through node {ind}")
            self.model.add_rigid_link(ind, deps, components=cm)
            self.deck.rigid_sources.append(tuple(sources[(ind, cm)]))

    # ----------------------------------------------------------------- everything else
    def list_other_cards(self) -> None:
        bdf = self.bdf
        used_pids = {getattr(e, "pid", None) for e in list(bdf.elements.values()) + list(bdf.masses.values())}
        used_mids = {getattr(p, "mid", None) for p in bdf.properties.values() if getattr(p, "pid", None) in used_pids}
        for p in bdf.properties.values():
            used_mids.update(getattr(p, "mids", []) or [])
        reduced = sorted(name for name in bdf.card_count if name in REDUCTION_CARDS)
        if reduced:
            self.notes.append(f"{'/'.join(reduced)} (Guyan reduction to an analysis set) not applied: flexgvt solves "
                              "the full model, so the higher modes will differ from Nastran's (the reduced model is "
                              "stiffer; the lowest modes agree when the set is well chosen)")
        skipped = sorted(name for name in bdf.card_count if name in NON_STRUCTURAL)
        if skipped:
            self.notes.append(f"non-structural cards ignored: {', '.join(skipped)}")
        for name, count in bdf.card_count.items():
            if name in READ_CARDS or name in IGNORED_CARDS or name in NON_STRUCTURAL or name in REDUCTION_CARDS or \
                    name in self.unsupported:
                continue
            ids = sorted({ident for (n, ident) in self.index.places if n == name}, key=_natural)
            if name in PROPERTY_NAMESPACE or name in MATERIAL_NAMESPACE:
                used = used_pids if name in PROPERTY_NAMESPACE else used_mids
                unused = [i for i in ids if i.isdigit() and int(i) not in used]
                if unused:
                    self.notes.append(f"{name} {', '.join(unused)} not used by any element: ignored")
                ids = [i for i in ids if i not in unused]
                if not ids:
                    continue
            self.unsupported.setdefault(name, []).extend(ids or [f"{count} card(s)"])
        for card in getattr(self.bdf, "reject_cards", []) or []:
            name = str(card[0]).upper().rstrip("*") if card else "?"
            self.unsupported.setdefault(name, []).append(str(card[1]) if len(card) > 1 else "?")

    # ----------------------------------------------------------------- configurations
    def _subcases(self) -> list[tuple[str, object, int]]:
        """(configuration name, case control subcase or None, subcase id) in reading order."""
        ccd = self.bdf.case_control_deck
        subcases = {} if ccd is None else dict(ccd.subcases)
        numbered = {k: v for k, v in subcases.items() if k > 0}
        if numbered:
            return [(f"subcase_{sid}", sub, sid) for sid, sub in sorted(numbered.items())]
        if 0 in subcases and subcases[0].params:
            return [(self.path.stem, subcases[0], 0)]
        return [(self.path.stem, None, 0)]

    def read_constraints(self, cases) -> None:
        """The MPC set every subcase selects -> model linear constraints (translations; components
        in a grid's CD are expanded to basic axes). Different sets per subcase are listed unsupported."""
        ids = {self._get(sub, "MPC") for _, sub, _ in cases}
        self.mpc_set = None
        defined = set(self.bdf.mpcs) | set(self.bdf.mpcadds)
        unselected = sorted(defined - {int(i) for i in ids if i is not None})
        if unselected:
            self.notes.append(f"MPC set(s) {unselected} selected by no subcase: ignored (as Nastran does)")
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
                    self.skip("MPC (scalar-point terms)", card.conid)
                    break
                if n not in self.bdf.nodes:
                    raise ModelError(f"{where} refers to node {n}, which is not defined")
                axes = coord_axes(self.bdf, self.bdf.nodes[n].cd, self.xyz_deck[n], where)
                e = axes[:, (comp - 1) % 3]
                base = 3 if comp > 3 else 0
                if k == 0:
                    big = int(np.argmax(np.abs(e)))
                    if abs(abs(e[big]) - 1.0) > 1e-9:
                        raise ModelError(f"{where}: the dependent term (node {n} component {comp}) lies along no basic "
                                         "axis in the grid's CD; give the grid a CD aligned with basic or make another "
                                         "term the first")
                    dependent = (int(n), base + big + 1)
                scale = float(coef) * (self.units.length if comp > 3 else 1.0)  # rotation terms: deck -> SI units
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
                self.deck.constraint_sources.append(int(card.conid))
        self.mpc_set = int(conid)

    def _mpc_cards(self, conid: int, where: str, seen: set) -> list:
        if conid in seen:
            raise ModelError(f"{where}: MPCADD sets refer to each other in a loop")
        seen.add(conid)
        out = []
        for card in self.bdf.mpcadds.get(conid, []):
            for sub in card.sets:
                out += self._mpc_cards(int(sub), where, seen)
        out += list(self.bdf.mpcs.get(conid, []))
        if not out:
            raise ModelError(f"{where}: the case control selects MPC = {conid} but no MPC or MPCADD card has that id")
        return out

    def read_configurations(self) -> None:
        bdf = self.bdf
        cases = self._subcases()
        self.read_constraints(cases)
        connected = {int(n) for g in self.model.beams for n in g.nodes.ravel()}
        connected |= {t[0] for con in self.model.constraints for t in con.terms}
        connected |= {n for sp in self.model.springs for n in (sp.node_a, sp.node_b) if n is not None}
        connected |= {n for link in self.model.rigid_links for n in (link.independent, *link.dependents)}
        connected |= {n for ip in self.model.interpolations for n in (ip.reference, *ip.nodes)}
        self.autospc = sorted(set(bdf.nodes) - connected)
        # Nodes joined only by rods have no rotational stiffness or inertia: their rotations are fixed.
        rod_nodes = {int(n) for g in self.model.beams if isinstance(g.section, RodSection) for n in g.nodes.ravel()}
        bending = {int(n) for g in self.model.beams if not isinstance(g.section, RodSection) for n in g.nodes.ravel()}
        bending |= {n for sp in self.model.springs for n in (sp.node_a, sp.node_b) if n is not None}
        bending |= {link.independent for link in self.model.rigid_links}
        bending |= {n for link in self.model.rigid_links if "4" in link.components for n in link.dependents}
        bending |= {ip.reference for ip in self.model.interpolations if "4" in ip.components}
        loose = {n for link in self.model.rigid_links if "4" not in link.components for n in link.dependents}
        loose |= {n for ip in self.model.interpolations for n in (*ip.nodes, ip.reference)} - bending
        self.autospc_rotations = sorted((rod_nodes | loose) - bending)
        if str(self.param("AUTOSPC", "YES")).upper() in ("NO", "N", "-1"):
            self.autospc, self.autospc_rotations = [], []
        if self.autospc:
            self.notes.append(f"node(s) {self.autospc[:10]}{' ...' if len(self.autospc) > 10 else ''} have no "
                              "element: fixed in every configuration (as Nastran's AUTOSPC does)")
        if self.autospc_rotations:
            r = self.autospc_rotations
            self.notes.append(f"node(s) {r[:10]}{' ...' if len(r) > 10 else ''} have no rotational stiffness (joined "
                              "only by rods, RBE2s without 456 or RBE3s): their rotations are fixed in every configuration "
                              "(as Nastran's AUTOSPC does)")
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
                raise ModelError(f"{self.path}: case control {key} = {value!r} (SUBCASE {getattr(sub, 'id', 0)}) is not "
                                 "a set id; give the integer id of a bulk data set") from None
        return value

    def configuration(self, name: str, sub, sid: int) -> None:
        bdf = self.bdf
        where = f"{self.path}: subcase {sid}" if sub is not None and sid else f"{self.path}"
        spc_id = self._get(sub, "SPC")
        load_id = self._get(sub, "LOAD")
        if sub is None:  # bulk data only: use the one SPC/load set if unambiguous
            spc_sets = set(bdf.spcs) | set(bdf.spcadds)
            load_sets = set(bdf.load_combinations) or set(bdf.loads)
            if len(spc_sets) == 1:
                spc_id = next(iter(spc_sets))
            elif spc_sets:
                self.notes.append(f"{where}: no case control and several SPC sets {sorted(spc_sets)}: none applied; "
                                  "add a SUBCASE with SPC = ...")
            if len(load_sets) == 1:
                load_id = next(iter(load_sets))
            elif load_sets:
                self.notes.append(f"{where}: no case control and several load sets {sorted(load_sets)}: none applied; "
                                  "add a SUBCASE with LOAD = ...")
        mpc_id = self._get(sub, "MPC")
        if mpc_id is not None and mpc_id != self.mpc_set:
            self.skip("MPC (different MPC sets per subcase)", mpc_id)
        fixed: dict[int, set[int]] = {}
        prescribed: dict[int, dict[int, float]] = {}
        for nid in self.autospc:
            fixed.setdefault(int(nid), set()).update(range(6))
        for nid in self.autospc_rotations:
            fixed.setdefault(int(nid), set()).update(range(3, 6))
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
                    self.skip(card.type, card.conid)
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
        self.deck.configurations[name] = cfg
        self.deck.subcases[name] = sid
        method = self._get(sub, "METHOD")
        eig = self._method(int(method), where) if method is not None else None
        self.deck.methods[name] = eig
        self.deck.n_modes[name] = eig.nd if eig is not None else None

    def _method(self, sid: int, where: str) -> EigenMethod | None:
        """EIGRL/EIGR ``sid`` as an EigenMethod (None, with a note, if the deck lacks it)."""
        eig = self.bdf.methods.get(sid)
        if eig is None:
            self.notes.append(f"{where}: METHOD = {sid} names no EIGRL/EIGR in the bulk data; 10 modes are computed")
            return None
        where = self.at(eig.type, sid)

        def num(v):
            return None if v is None or v == "" else float(v)
        nd = int(eig.nd) if getattr(eig, "nd", None) not in (None, "", 0) else None
        norm = (getattr(eig, "norm", None) or "MASS").upper()
        if norm not in ("MASS", "MAX", "POINT"):
            raise ModelError(f"{where}: NORM = {norm}; Nastran's real eigenvalue normalisations are MASS, MAX and "
                             "POINT")
        point = None
        if norm == "POINT":
            g, c = getattr(eig, "G", None), getattr(eig, "C", None)
            if not g or not c or int(g) not in self.bdf.nodes:
                raise ModelError(f"{where}: NORM = POINT needs the grid G and component C of an existing grid")
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
        cards = list(getattr(self.bdf, "suport", []) or [])
        sid = self._get(sub, "SUPORT1")
        if sid is not None:
            found = getattr(self.bdf, "suport1", {}).get(int(sid))
            if found is None:
                raise ModelError(f"{self.path}: the case control asks for SUPORT1 = {sid}, which the bulk data lacks; add "
                                 "the SUPORT1 set or remove the request")
            cards.append(found)
        for card in cards:
            for node, comps in zip(card.nodes, card.Cs):
                dofs.setdefault(int(node), set()).update(str(comps or ""))
        return {n: "".join(sorted(c)) for n, c in sorted(dofs.items()) if c}

    def _spc_cards(self, sid: int, where: str, depth: int = 0):
        bdf = self.bdf
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
        bdf = self.bdf
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
        if nid not in self.bdf.nodes:
            raise ModelError(f"{where} refers to node {nid}, which is not defined")
        comps = comps.strip()
        if comps in ("", "0"):
            return
        dofs = sorted({int(c) for c in comps})
        if any(not 1 <= d <= 6 for d in dofs):
            raise FileFormatError(f"{where}: components {comps!r} must be digits 1-6")
        cd = self.bdf.nodes[nid].cd
        out = fixed.setdefault(int(nid), set())
        if cd in (None, 0):
            out.update(d - 1 for d in dofs)
            return
        T = coord_axes(self.bdf, cd, self.xyz_deck[nid], f"{where} at node {nid}")
        for base, group in ((0, [d - 1 for d in dofs if d <= 3]), (3, [d - 4 for d in dofs if d > 3])):
            if not group:
                continue
            P = T[:, group] @ T[:, group].T  # projector on the constrained directions, basic axes
            diag = np.diag(P)
            if not (np.allclose(P, np.diag(diag), atol=1e-9) and np.allclose(diag, np.round(diag), atol=1e-9)):
                raise ModelError(f"{where}: node {nid} has CD={cd} and its constrained components "
                                 f"{''.join(str(base + g + 1) for g in group)} do not line up with basic axes; "
                                 "flexgvt fixes DOFs in basic axes. Constrain all three translations/rotations, use "
                                 "a CD aligned with basic, or replace the SPC by a stiff CBUSH in that system")
            out.update(base + i for i in np.flatnonzero(np.round(diag) == 1))

    def _prescribe(self, prescribed: dict, nid: int, comps: str, value: float, where: str) -> None:
        """Enforced value [deck units] on components of a node (basic axes only)."""
        if nid not in self.bdf.nodes:
            raise ModelError(f"{where} refers to node {nid}, which is not defined")
        if self.bdf.nodes[nid].cd not in (None, 0):
            raise ModelError(f"{where}: enforced values on node {nid}, whose CD is not basic, are not supported; "
                             "give the grid CD = 0 or enforce the motion with a stiff spring and a force")
        for c in comps.strip():
            d = int(c)
            prescribed.setdefault(int(nid), {})[d] = value * (self.units.length if d <= 3 else 1.0)

    def _load(self, card, scale: float, forces: list, distributed: list, gravity_terms: list) -> None:
        bdf, u = self.bdf, self.units
        where = self.at(card.type, card.sid)
        if card.type in ("FORCE", "MOMENT"):
            nid = card.node
            if nid not in bdf.nodes:
                raise ModelError(f"{where} refers to node {nid}, which is not defined")
            T = coord_axes(bdf, card.cid, self.xyz_deck[nid], where)
            vec = scale * card.mag * (T @ np.asarray(card.xyz, float))
            if card.type == "FORCE":
                forces.append(NodalLoad(int(nid), force=tuple(vec * u.force)))
            else:
                forces.append(NodalLoad(int(nid), moment=tuple(vec * u.moment)))
        elif card.type == "GRAV":
            if card.cid not in (None, 0) and bdf.coords[card.cid].Type != "R":
                self.skip("GRAV (curvilinear CID)", card.sid)
                return
            if getattr(card, "mb", 0):
                self.skip("GRAV (MB = -1: main bulk only)", card.sid)
            T = coord_axes(bdf, card.cid, np.zeros(3), where)
            a = card.scale * (T @ np.asarray(card.N, float)) * u.length
            gravity_terms.append((scale, a))
        elif card.type == "PLOAD1":
            self._pload1(card, scale, distributed, where)
        else:
            self.skip(card.type, card.sid)

    def _pload1(self, card, scale, distributed, where) -> None:
        u = self.units
        eid = card.eid
        if eid not in self.deck.element_ids:
            if eid not in self.bdf.elements:
                raise ModelError(f"{where} refers to element {eid}, which is not defined")
            self.skip("PLOAD1 (on an element that was not read as a beam)", card.sid)
            return
        if card.load_type not in ("FX", "FY", "FZ"):
            self.skip(f"PLOAD1 (TYPE {card.load_type}: only FX, FY, FZ in basic axes)", card.sid)
            return
        elem = self.bdf.elements[eid]
        n1, n2 = elem.node_ids[:2]
        axis = self.xyz_deck[n2] - self.xyz_deck[n1]
        L = float(np.linalg.norm(axis))
        x1, x2 = card.x1, card.x2
        p1, p2 = card.p1, card.p2 if card.p2 is not None else card.p1
        full = x2 is not None and math.isclose(x1 or 0.0, 0.0, abs_tol=1e-9) and (
            math.isclose(x2, 1.0, rel_tol=1e-6) if card.scale in ("FR", "FRPR") else math.isclose(x2, L, rel_tol=1e-6))
        if not full or not math.isclose(p1, p2, rel_tol=1e-9, abs_tol=0.0):
            self.skip("PLOAD1 (not uniform over the whole element)", card.sid)
            return
        direction = np.eye(3)["XYZ".index(card.load_type[1])]
        w = p1
        if card.scale in ("LEPR", "FRPR"):
            w = p1 * math.sqrt(max(0.0, 1.0 - (axis @ direction / L) ** 2))
        distributed.append(DistributedLoad((self.deck.element_ids[eid],),
                                           tuple(scale * w * direction * u.force / u.length)))


def _supported_shapes():
    from ._sections import SUPPORTED_SHAPES
    return SUPPORTED_SHAPES


def _natural(x):
    s = str(x)
    return (0, int(s)) if s.isdigit() else (1, s)


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


def _rigid_mass(M: np.ndarray, rtol: float = 1e-6):
    """(m, offset, inertia about the centre) if M (6x6, basic axes) is a rigid-body mass matrix, else None."""
    m = M[0, 0]
    scale = max(np.abs(M).max(), 1e-300)
    if m <= 0 or not np.allclose(M[:3, :3], m * np.eye(3), atol=rtol * scale):
        return None
    S = -M[:3, 3:] / m  # M_tr = -m skew(r)
    if not np.allclose(S, -S.T, atol=rtol * scale / m):
        return None
    r = np.array([S[2, 1], S[0, 2], S[1, 0]])
    Sr = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    if not np.allclose(M[3:, :3], m * Sr, atol=rtol * scale):
        return None
    J = M[3:, 3:] + m * Sr @ Sr
    return m, r, 0.5 * (J + J.T)


def read_bdf(path, *, units: str | Units = "SI", unsupported: str = "error", mass: str | None = None,
             rotary_inertia: bool = False, cbar_torsional_inertia: bool = False) -> BdfDeck:
    """Read a Nastran bulk data deck into a flexgvt Model and Configurations.

    path: .bdf/.dat/.nas file (INCLUDEs followed; executive and case control optional).
    units: the deck's consistent unit system ('SI', 'mm-N-t-s', 'in-lbf-s' or a Units); everything
    is converted to SI. PARAM,WTMASS scales every mass (density, CONM1/2, NSM).
    unsupported: 'error' raises UnsupportedCardsError listing every card (or card feature) that
    has no flexgvt counterpart, with ids; 'warn' reads the rest and lists them in one warning.
    mass: 'lumped' or 'consistent' beam mass; default from PARAM,COUPMASS (lumped unless > 0).
    rotary_inertia: include bending rotary inertia of beams (Nastran's CBAR leaves it out, so the
    default False matches Nastran; torsional inertia: see cbar_torsional_inertia).
    cbar_torsional_inertia: the default False reproduces Nastran's CBAR, whose mass (lumped or
    COUPMASS) has no torsional inertia (measured on the Simcenter beam_modes and MSC pt145 f06);
    True adds the physical rho*Ip to CBARs (torsion modes drop; CBEAM always has it).
    Returns a BdfDeck with .model and .configurations (one per SUBCASE, named 'subcase_<id>', or
    one named after the file when there are no subcases).
    """
    path = Path(path)
    if not path.is_file():
        raise FileFormatError(f"{path}: no such file; give the path of a Nastran bulk data deck")
    if unsupported not in ("error", "warn"):
        raise ModelError(f"read_bdf: unsupported={unsupported!r} must be 'error' or 'warn'")
    if mass not in (None, "lumped", "consistent"):
        raise ModelError(f"read_bdf: mass={mass!r} must be None (from COUPMASS), 'lumped' or 'consistent'")
    reader = _Reader(path, get_units(units), mass, rotary_inertia, cbar_torsional_inertia)
    deck = reader.read()
    if deck.unsupported:
        listing = "; ".join(f"{card}: {', '.join(map(str, ids[:8]))}{', ...' if len(ids) > 8 else ''}"
                            for card, ids in sorted(deck.unsupported.items()))
        message = (f"{path}: {sum(len(v) for v in deck.unsupported.values())} card(s) have no flexgvt counterpart "
                   f"and were not read: {listing}")
        if unsupported == "error":
            raise UnsupportedCardsError(message + ". Remove or replace them, or call read_bdf(..., "
                                        "unsupported='warn') to read the rest", deck.unsupported)
        warnings.warn(message, stacklevel=2)
    if deck.notes:
        warnings.warn(f"{path}: read with these approximations: " + "; ".join(deck.notes), stacklevel=2)
    return deck
