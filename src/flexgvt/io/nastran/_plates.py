"""Plates: CQUAD4/CTRIA3 (and CQUADR/CTRIAR read as them) on PSHELL or PCOMP/PCOMPG, with MAT1
(read by the materials family), MAT2 and MAT8. One shell group per (property, node count, THETA
or MCID). Units as every family: lengths, thicknesses, offsets by the length unit, moduli by the
stress unit, densities and NSM by the mass unit (and PARAM,WTMASS).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ...errors import ModelError
from ...model import Model
from ...model.shells import AnisotropicMaterial, Laminate, OrthotropicMaterial, Ply, ShellProperty
from ._deck import Deck, Family, Findings, Parts
from ._grids import coord_axes

SHELL_CARDS = ("CQUAD4", "CTRIA3", "CQUADR", "CTRIAR")
AS_CARD = {"CQUADR": "CQUAD4", "CTRIAR": "CTRIA3"}
# pyNastran fills a blank MAT8 G1Z/G2Z with this value (Nastran: blank is rigid transverse shear).
PYNASTRAN_BLANK_GZ = 1.0e8


@dataclass(frozen=True)
class ShellSource:
    """The cards behind one shell group: element card (CQUAD4/CTRIA3/...), property card and id,
    and the Nastran element ids in group order."""

    name: str
    element_card: str
    property_card: str
    pid: int
    eids: tuple[int, ...]


class _Materials:
    """MAT1 (from the materials family), MAT2 and MAT8 of the deck in SI, each made once."""

    def __init__(self, deck: Deck, parts: Parts) -> None:
        self.deck, self.parts, self.made = deck, parts, {}

    def get(self, mid, user: str, allowed: tuple[str, ...]):
        if mid in (None, 0):
            return None
        bdf, u, w = self.deck.bdf, self.deck.units, self.deck.wtmass
        card = bdf.materials.get(mid)
        if card is None:
            raise ModelError(f"{user} refers to material {mid}, which is not defined; add the MAT card or fix the id")
        if card.type not in allowed:
            raise ModelError(f"{user} refers to {card.type} {mid}; this field takes {'/'.join(allowed)}: "
                             "use one of them")
        if mid in self.made:
            return self.made[mid]
        where = self.deck.at(card.type, mid)
        try:
            if card.type == "MAT1":
                mat = self.parts.materials[mid]
            elif card.type == "MAT2":
                mat = AnisotropicMaterial(f"MAT2_{mid}", *(float(getattr(card, f) or 0.0) * u.stress for f in
                                                           ("G11", "G12", "G13", "G22", "G23", "G33")),
                                          rho=float(card.rho or 0.0) * u.density * w)
            else:
                gz = [None if g in (None, PYNASTRAN_BLANK_GZ) else float(g) * u.stress for g in (card.g1z, card.g2z)]
                mat = OrthotropicMaterial(f"MAT8_{mid}", float(card.e11) * u.stress, float(card.e22) * u.stress,
                                          float(card.nu12 or 0.0), float(card.g12) * u.stress, gz[0], gz[1],
                                          rho=float(card.rho or 0.0) * u.density * w)
        except (ModelError, TypeError) as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.made[mid] = mat
        return mat


def _pshell(deck: Deck, prop, mats: _Materials) -> ShellProperty:
    u, where = deck.units, deck.at("PSHELL", prop.pid)
    iso = ("MAT1", "MAT2")
    if prop.mid2 is not None and prop.mid2 < 0:
        raise ModelError(f"{where}: MID2 = {prop.mid2} (plane strain) is not supported; give a MAT1/MAT2 id or blank")
    membrane = mats.get(prop.mid1, f"{where} MID1", iso)
    bending = mats.get(prop.mid2, f"{where} MID2", iso)
    shear = mats.get(prop.mid3, f"{where} MID3", iso)
    coupling = mats.get(prop.mid4, f"{where} MID4", iso)
    t = None if prop.t is None else float(prop.t) * u.length
    if t is not None and t <= 0:
        raise ModelError(f"{where}: T = {prop.t} must be positive; give the plate thickness")
    z = [None if v is None else float(v) * u.length for v in (prop.z1, prop.z2)]
    if t is not None and prop.t is not None and z[0] is not None and np.isclose(prop.z1, -0.5 * prop.t) and \
            np.isclose(prop.z2, 0.5 * prop.t):
        z = [None, None]  # pyNastran's default fibres: keep them as "not given"
    try:
        return ShellProperty(f"PSHELL_{prop.pid}", t, membrane, bending,
                             float(prop.twelveIt3 if prop.twelveIt3 is not None else 1.0), shear,
                             float(prop.tst if prop.tst is not None else 5.0 / 6.0), coupling,
                             float(prop.nsm or 0.0) * u.mass * deck.wtmass / u.length**2, z[0], z[1])
    except ModelError as exc:
        raise ModelError(f"{where}: {exc}") from None


def _pcomp(deck: Deck, prop, mats: _Materials, log: Findings) -> Laminate:
    u, where = deck.units, deck.at(prop.type, prop.pid)
    plies = []
    gids = getattr(prop, "global_ply_ids", None)
    if not prop.mids:
        raise ModelError(f"{where}: the laminate has no plies; give at least one ply (MID, T, THETA)")
    for k, (mid, t, theta, sout) in enumerate(zip(prop.mids, prop.thicknesses, prop.thetas, prop.souts)):
        if mid in (None, 0):
            raise ModelError(f"{where}: ply {k + 1} has no material (MID blank or 0); give every ply a MAT1/MAT2/"
                             "MAT8 id")
        if t is None or not t > 0:
            raise ModelError(f"{where}: ply {k + 1} has thickness {t}; ply thicknesses must be positive")
        mat = mats.get(mid, f"{where} ply {k + 1}", ("MAT1", "MAT2", "MAT8"))
        plies.append(Ply(mat, float(t) * u.length, float(theta or 0.0), str(sout).upper() == "YES",
                         int(gids[k]) if gids is not None else None))
    lam = (prop.lam or "").strip().upper()
    total = sum(prop.thicknesses) * (2 if lam == "SYM" else 1)
    # pyNastran fills a blank Z0 with -T/2: keep it as "not given" (the same plane)
    z0 = None if prop.z0 is None or math.isclose(prop.z0, -0.5 * total, rel_tol=1e-9) else float(prop.z0) * u.length
    if getattr(prop, "ft", None):
        log.note(f"{where}: failure theory FT={prop.ft} is not used (no strength analysis)")
    try:
        return Laminate(f"{prop.type}_{prop.pid}", tuple(plies), z0,
                        float(prop.nsm or 0.0) * u.mass * deck.wtmass / u.length**2, lam)
    except ModelError as exc:
        raise ModelError(f"{where}: {exc}") from None


def read_plates(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """Shell groups from CQUAD4/CTRIA3/CQUADR/CTRIAR with their PSHELL/PCOMP/PCOMPG properties."""
    bdf, u = deck.bdf, deck.units
    mats = _Materials(deck, parts)
    props: dict[int, object] = {}
    groups: dict[tuple, list] = {}
    for eid, elem in sorted(bdf.elements.items()):
        if elem.type not in SHELL_CARDS:
            continue
        prop = bdf.properties.get(elem.pid)
        if prop is None:
            raise ModelError(f"{deck.at(elem.type, eid)} refers to property {elem.pid}, which is not defined; add "
                             "the PSHELL/PCOMP card or fix PID")
        if prop.type not in ("PSHELL", "PCOMP", "PCOMPG"):
            raise ModelError(f"{deck.at(elem.type, eid)} refers to {prop.type} {elem.pid}; a plate element takes a "
                             "PSHELL, PCOMP or PCOMPG")
        mcid = elem.theta_mcid if isinstance(elem.theta_mcid, (int, np.integer)) and \
            not isinstance(elem.theta_mcid, bool) else None
        groups.setdefault((prop.pid, AS_CARD.get(elem.type, elem.type), mcid is not None), []).append(elem)
    if not groups:
        return Parts()
    shells: dict[str, ShellSource] = {}
    element_ids: dict[int, int] = {}
    for pid in sorted({key[0] for key in groups}):
        prop = bdf.properties[pid]
        props[pid] = _pshell(deck, prop, mats) if prop.type == "PSHELL" else _pcomp(deck, prop, mats, log)
    renamed = sorted({e.type for elems in groups.values() for e in elems if e.type in AS_CARD})
    if renamed:
        log.note(f"{'/'.join(renamed)} read as {'/'.join(AS_CARD[r] for r in renamed)} (flexgvt's shells have "
                 "their own drilling stiffness)")
    for (pid, card, by_mcid), elems in sorted(groups.items()):
        prop = props[pid]
        p = 4 if card == "CQUAD4" else 3
        nodes = np.array([list(e.nodes)[:p] for e in elems], int)
        theta = np.zeros(len(elems)) if by_mcid else np.array([float(e.theta_mcid or 0.0) for e in elems])
        axis = None
        if by_mcid:
            axis = np.array([coord_axes(bdf, int(e.theta_mcid), np.mean([deck.xyz_deck[n] for n in row], axis=0),
                                        deck.at(e.type, e.eid))[:, 0] for e, row in zip(elems, nodes.tolist())])
        zoffs = np.array([float(e.zoffset or 0.0) for e in elems]) * u.length
        corners = _corner_thickness(deck, elems, prop, p)
        name = f"{prop.name}_{card}" + ("_MCID" if by_mcid else "")
        try:
            ids = model.add_shells(nodes, prop, name=name, theta=theta, material_axis=axis, zoffs=zoffs,
                                   corner_thickness=corners, mass=deck.mass)
        except ModelError as exc:
            raise ModelError(f"{_first_element(deck, elems, str(exc))}: {exc}") from None
        eids = tuple(int(e.eid) for e in elems)
        element_ids.update(dict(zip(eids, (int(i) for i in ids))))
        shells[name] = ShellSource(name, card, bdf.properties[pid].type, int(pid), eids)
    if deck.mass == "consistent":
        log.note("PARAM,COUPMASS: shell groups take the consistent mass (Nastran's coupled plate mass)")
    k6rot = deck.param("K6ROT", None)
    options = {} if k6rot is None else {"K6ROT": float(k6rot)}
    if k6rot is not None:
        log.note(f"PARAM,K6ROT={k6rot} (Nastran's CQUAD4/CTRIA3 drilling stiffness) kept in BdfDeck.options; "
                 "flexgvt's shells use their own drilling stiffness")
    return Parts(element_ids=element_ids, shells=shells, options=options)


def _corner_thickness(deck: Deck, elems, prop, p: int) -> np.ndarray | None:
    """(n, p) corner thicknesses [m] when any element gives one (TFLAG 0: values, 1: factors of T)."""
    names = ("T1", "T2", "T3", "T4")[:p]
    if not any(getattr(e, f, None) is not None for e in elems for f in names):
        return None
    t_prop = prop.thickness
    out = np.empty((len(elems), p))
    for k, e in enumerate(elems):
        for j, f in enumerate(names):
            v = getattr(e, f, None)
            if v is None:
                if t_prop is None:
                    raise ModelError(f"{deck.at(e.type, e.eid)}: {f} is blank and property {e.pid} has no T; "
                                     "give the corner thickness or the property's T")
                out[k, j] = t_prop
            elif getattr(e, "tflag", 0) == 1:
                if t_prop is None:
                    raise ModelError(f"{deck.at(e.type, e.eid)}: TFLAG=1 (relative corner thicknesses) needs the "
                                     f"property's T; give T on property {e.pid}")
                out[k, j] = float(v) * t_prop
            else:
                out[k, j] = float(v) * deck.units.length
    return out


def membrane_rotation_fixes(model: Model) -> dict[int, set[int]]:
    """Rotations (DOF indices 3-5, basic axes) that no element stiffens at the nodes of membrane-only
    shells (PSHELL without MID2): those about the axes orthogonal to every membrane normal at the
    node. The rotation about a membrane's normal is its drilling DOF, part of flexgvt's membrane
    field: holding it (as Nastran's AUTOSPC may, its membrane having no drilling coupling) would
    stiffen the membrane. Where those axes do not line up with basic axes, all three rotations are
    returned (held, as for rods)."""
    xyz = dict(zip(model.node_ids.tolist(), model.xyz))
    normals: dict[int, list[np.ndarray]] = {}
    for g in model.shells:
        if getattr(g.property, "bending", True) is not None:
            continue
        for row in g.nodes.tolist():
            X = np.array([xyz[n] for n in row])
            n = np.cross(X[2] - X[0], X[3] - X[1]) if len(row) == 4 else np.cross(X[1] - X[0], X[2] - X[0])
            for node in row:
                normals.setdefault(int(node), []).append(n / np.linalg.norm(n))
    out: dict[int, set[int]] = {}
    for node, ns in normals.items():
        _, sv, vt = np.linalg.svd(np.array(ns))
        span = vt[: int(np.sum(sv > 1e-6 * sv[0]))]
        Q = np.eye(3) - span.T @ span  # projector on the axes no membrane turns about
        diag = np.diag(Q)
        aligned = np.allclose(Q, np.diag(diag), atol=1e-9) and np.allclose(diag, np.round(diag), atol=1e-9)
        out[node] = {3 + int(i) for i in np.flatnonzero(np.round(diag) == 1)} if aligned else {3, 4, 5}
    return out


def _first_element(deck: Deck, elems, message: str) -> str:
    """'file:line: CARD eid' of the element a model message names ('element k (nodes ...)')."""
    m = re.search(r"element (\d+) \(nodes", message)
    e = elems[int(m.group(1)) - 1] if m and int(m.group(1)) <= len(elems) else elems[0]
    return deck.at(e.type, e.eid)


FAMILY = Family("plates", SHELL_CARDS + ("PSHELL", "PCOMP", "PCOMPG", "MAT2", "MAT8"), read_plates,
                needs_property=SHELL_CARDS)
