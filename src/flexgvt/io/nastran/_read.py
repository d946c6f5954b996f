"""Read a Nastran bulk data deck (pyNastran) into a flexgvt Model and one Configuration per subcase."""

from __future__ import annotations

import contextlib
import io
import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import FileFormatError, FlexGVTError, ModelError
from ...model import Configuration, Material, Model
from ._cards import (
    BEAM_PROPERTIES,
    COORD_NAMESPACE,
    ELEMENT_NAMESPACE,
    MASS_NAMESPACE,
    MATERIAL_NAMESPACE,
    PROPERTY_NAMESPACE,
    RIGID_NAMESPACE,
    STRUCTURAL_PARAMS_IGNORED,
    CardsMixin,
)
from ._common import (
    CardIndex,
    EigenMethod,
    Units,
    UnsupportedCardsError,
    absolute_include_lines,
    get_units,
    split_first_fields,
    where_prefix,
)
from ._limits import MAX_COORDINATE_M, MAX_ID, MAX_VALUE, bad_reals, field_label
from ._read_beams import BeamsMixin, BeamSource, _frame_from_x, _scale_section  # noqa: F401
from ._read_configs import ConfigurationsMixin
from ._read_masses import MassesMixin, _rigid_mass  # noqa: F401


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
    model.constraints (the one set all subcases select); n_modes: configuration -> EIGRL ND of its METHOD (None if
    not given);
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


def _safe_str(value) -> str:
    try:
        return str(value)
    except Exception:  # noqa: BLE001 - pyNastran objects whose str needs cross-referencing
        return type(value).__name__


class _QuietLog:
    """Logger handed to pyNastran: keeps its messages (for error context) instead of printing them."""

    level = "error"

    def __init__(self):
        self.messages: list[str] = []

    def _keep(self, msg, *args, **kwargs):
        self.messages.append(_exception_text(msg) if isinstance(msg, BaseException) else _safe_str(msg))

    debug = info = warning = error = exception = critical = _keep

    def __getattr__(self, name):  # any other cpylog method
        if name.startswith("__"):
            raise AttributeError(name)
        return self._keep

    def __deepcopy__(self, memo):
        return _QuietLog()


def _is_begin_bulk(line: str) -> bool:
    return line.split("$", 1)[0].strip().upper().replace(" ", "") == "BEGINBULK"


def _open_bdf(path: Path, index: CardIndex, notes: list[str]):
    """pyNastran BDF of ``path`` (with or without executive/case control), errors as FileFormatError.
    A plain BEGIN BULK repeated inside the bulk data (a pasted deck) is ignored and noted."""
    from pyNastran.bdf.bdf import BDF

    if index.bad_includes:  # pyNastran would dump the deck to ./pyNastran_crash.bdf and fail
        f, ln, text = index.bad_includes[0]
        raise FileFormatError(f"{f}:{ln}: {text!r} is not an INCLUDE statement flexgvt reads; write INCLUDE 'path' "
                              "on one line, the path in single quotes")
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
    for k in [i for i, line in enumerate(lines) if _is_begin_bulk(line)][1:]:
        lines[k] = "$" + lines[k]  # a comment keeps the line numbers
        notes.append(f"{path}:{k + 1}: BEGIN BULK repeated inside the bulk data: ignored")
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


_CARD_IN_MSG = re.compile(r"card\s*=\s*\[\s*'([A-Za-z0-9*]+)'\s*,\s*'?([^',\]]*)'?")


def _exception_text(exc: BaseException) -> str:
    """str(exc), or its class name when pyNastran's message itself fails (it prints cards)."""
    try:
        return str(exc).strip()
    except Exception:  # noqa: BLE001 - e.g. a LOAD card whose repr needs cross-referencing
        return type(exc).__name__


def _card_in_traceback(exc: BaseException) -> tuple[str, str]:
    """(card name, first field) of the card pyNastran was adding when ``exc`` was raised, from the
    innermost frame of its card parser (its own message may name none, or fail to print)."""
    name, ident, tb = "", "", exc.__traceback__
    while tb is not None:
        lines = tb.tb_frame.f_locals.get("card_lines")
        if isinstance(lines, list) and lines and isinstance(lines[0], str):
            name, ident = split_first_fields(lines[0])
        tb = tb.tb_next
    return name, ident


def _parse_error(path: Path, index: CardIndex, exc: Exception, log: _QuietLog) -> FileFormatError:
    text = _exception_text(exc)
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
    else:
        name, ident = _card_in_traceback(exc)
    if name:
        place = index.where(name, ident)
        where = place or where
        card = f" in {name} {ident}"
    first = text.splitlines()[0] if text else type(exc).__name__
    hint = "fix the field named above (see the Nastran Quick Reference Guide for the card's format)"
    if first == type(exc).__name__:  # pyNastran gave no message (a bare assert) or one that fails to print
        first = f"pyNastran refused the card ({first})"
        hint = "check its fields against the Nastran Quick Reference Guide (ids above 0, references, real or integer)"
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


class _Reader(BeamsMixin, MassesMixin, CardsMixin, ConfigurationsMixin):
    def __init__(self, path: Path, units: Units, mass: str | None, rotary_inertia: bool,
                 cbar_torsional_inertia: bool = False):
        self.cbar_torsional_inertia = cbar_torsional_inertia
        self.path = path
        self.units = units
        self.index = CardIndex(path)
        _check_duplicates(path, self.index)
        self.notes: list[str] = []
        self.bdf = _open_bdf(path, self.index, self.notes)
        self.rotary_inertia = rotary_inertia
        self.mass_override = mass
        self.unsupported: dict[str, list] = {}
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

    # ----------------------------------------------------------------- ids and values
    def _tables(self):
        bdf = self.bdf
        return (("node", {k: v for k, v in bdf.nodes.items()}), ("element", bdf.elements), ("mass element", bdf.masses),
                ("rigid element", bdf.rigid_elements), ("property", bdf.properties),
                ("property", getattr(bdf, "properties_mass", {}) or {}), ("material", bdf.materials),
                ("coordinate system", {k: v for k, v in bdf.coords.items() if k != 0}))

    def _listing(self, problems: list[str]) -> str:
        text = "; ".join(problems[:8]) + ("; ..." if len(problems) > 8 else "")
        return text if text.startswith(str(self.path)) else f"{self.path}: {text}"

    def check_ids_and_values(self) -> None:
        """Ids within Nastran's 1..99999999 and real fields finite and within MAX_VALUE, on every card
        flexgvt reads (before any is used: an id of 1e20 or a field of 1e300 would otherwise fail
        far from the card, or overflow in the eigensolver)."""
        bdf, problems = self.bdf, []
        for label, table in self._tables():
            for ident, card in table.items():
                if not isinstance(ident, int) or not 0 < ident <= MAX_ID:
                    name = getattr(card, "type", "?")
                    problems.append(f"{self.at(name, ident)}: {label} id {ident} is outside Nastran's range 1 to "
                                    f"{MAX_ID}; renumber it")
        if problems:
            raise ModelError(self._listing(problems))
        cards = [c for _, table in self._tables() for c in table.values()]
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
                problems.append(f"{self.at(card.type, ident)}: {field_label(card, k)} = {v!r} {why}")
        if problems:
            raise ModelError(self._listing(problems) + ". Fix the value (or the deck's unit system)")

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
            ids = _element_nodes(elem)
            if elem.type in TWO_NODE_CARDS and (len(ids) < 2 or any(n in (None, 0) for n in ids[:2])):
                miss.append(f"{self.at(elem.type, eid)} has GA/GB = {ids[:2]}; give both end grids (ids above 0)")
                continue
            if ids and all(n in (None, 0) for n in ids):
                miss.append(f"{self.at(elem.type, eid)} connects no grid (all node fields blank or 0)")
                continue
            for n in (n for n in ids if n not in (None, 0)):
                if n not in nodes:
                    miss.append(f"{self.at(elem.type, eid)} refers to node {n}, which is not defined")
            pid = getattr(elem, "pid", None)
            if (elem.type in ("CBAR", "CBEAM", "CROD", "CELAS1", "CDAMP1", "CVISC", "CBUSH")
                    and pid not in bdf.properties):
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
            try:
                refs = list(elem.independent_nodes) + list(elem.dependent_nodes)
            except Exception as exc:  # noqa: BLE001 - pyNastran asserts on blank or 0 node fields
                miss.append(f"{self.at(elem.type, eid)} has a blank or invalid node field ({type(exc).__name__}: "
                            f"{(str(exc).splitlines() or [''])[0][:80]})")
                continue
            for n in refs:
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
        self.check_ids_and_values()
        self.check_references()
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                bdf.cross_reference(xref=True, xref_nodes=True, xref_elements=False, xref_nodes_with_elements=False,
                                    xref_properties=False, xref_masses=False, xref_materials=False, xref_loads=False,
                                    xref_constraints=False, xref_aero=False, xref_sets=False, xref_optimization=False)
        except FlexGVTError:
            raise
        except Exception as exc:
            text = _exception_text(exc)
            raise ModelError(f"{self.path}: coordinate systems or grids could not be resolved: "
                             f"{text.splitlines()[0] if text else type(exc).__name__}; check CORD/GRID cards")
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
        far = np.flatnonzero(np.abs(xyz).max(axis=1) > MAX_COORDINATE_M)
        if len(far):
            raise ModelError(f"{self.at('GRID', nids[far[0]])}: basic coordinates {xyz[far[0]] / u.length} lie "
                             f"more than {MAX_COORDINATE_M:g} m from the origin ({len(far)} grid(s)); element lengths "
                             "of that size overflow the stiffness and mass products. Fix the coordinates, their CP "
                             "system or the deck's units")
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



def read_bdf(path, *, units: str | Units = "SI", unsupported: str = "error", mass: str | None = None,
             rotary_inertia: bool = False, cbar_torsional_inertia: bool = False) -> BdfDeck:
    """Read a Nastran bulk data deck into a flexgvt Model and Configurations.

    path: .bdf/.dat/.nas file (INCLUDEs followed; executive and case control optional).
    units: the deck's consistent unit system ('SI', 'mm-N-t-s', 'in-lbf-s' or a Units); everything
    is converted to SI. PARAM,WTMASS scales every mass (density, CONM1/2, NSM).
    unsupported: 'error' raises UnsupportedCardsError listing every card (or card feature) that
    has no flexgvt counterpart, with ids; 'warn' reads the rest and lists them in one warning.
    mass: 'lumped' or 'consistent' beam mass; default from PARAM,COUPMASS (lumped unless > 0).
    'consistent' is Nastran's coupled mass: cubic bending, linear axial for CBAR, lumped axial and
    torsional for CBEAM (group mass 'consistent-bending').
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
