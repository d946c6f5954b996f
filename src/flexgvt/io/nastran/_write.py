"""Write flexgvt models as Nastran bulk data: into a copy of the user's deck, or as a compact deck."""

from __future__ import annotations

import contextlib
import copy
import io
import warnings
from pathlib import Path

import numpy as np

from ...errors import ModelError
from ...model import Configuration, Material, Model, RodSection, TaperedSection
from ._common import Units, get_units
from ._elements import scale_section as _scale_section
from ._grids import coord_axes
from ._parse import QuietLog as _QuietLog
from ._read import BdfDeck
from ._sections import library_dims, library_section, to_properties


def _material_values(mat: Material, u: Units, wtmass: float) -> dict:
    out = {"E": mat.E / u.stress, "rho": mat.rho / (u.density * wtmass), "G": None, "nu": mat.nu}
    if mat.G is not None:
        out["G"] = mat.G / u.stress
    elif mat.nu is not None:
        out["G"] = out["E"] / (2 * (1 + mat.nu))
    return out


def vals_rho(group, u: Units) -> float:
    """The group's density in deck units (mass / length^3)."""
    return group.material.rho / u.density


def _same(a, b, rtol=1e-9) -> bool:
    return np.allclose(np.asarray(a, float), np.asarray(b, float), rtol=rtol, atol=0.0)


def _ends(section) -> tuple:
    """The sections at end A and end B (the same one twice for a uniform section)."""
    return (section.end_a, section.end_b) if isinstance(section, TaperedSection) else (section, section)


def _same_section(a, b, rtol=1e-9) -> bool:
    """Equal A, Iy, Iz, J and shear areas at both ends (Ip is not a Nastran property: not compared)."""
    for ea, eb in zip(_ends(a), _ends(b)):
        pa, pb = ea.properties(), eb.properties()
        if not all(np.isclose(pa[k], pb[k], rtol=rtol, atol=0.0) for k in ("A", "Iy", "Iz", "J", "Ay", "Az")):
            return False
    return True


def _library_ends(section, shape: str) -> list[list[float]] | None:
    """The DIMs of each end when both ends are the library ``shape`` exactly (with its shear factor), else None."""
    dims = [library_dims(e) if getattr(e, "shear", False) else None for e in _ends(section)]
    if all(d is not None and d[0] == shape for d in dims):
        return [list(d[1]) for d in dims]
    return None


def _pbeam_ends(section, principal=(0.0, 1.0)) -> tuple[dict, dict, list[str]]:
    """Nastran values (to_properties) at end A and end B, and what a PBEAM cannot hold (one K1, K2)."""
    va, vb = (to_properties(e, principal) for e in _ends(section))
    issues = []
    for k in ("K1", "K2"):
        if not (va[k] == vb[k] or (va[k] is not None and vb[k] is not None and np.isclose(va[k], vb[k], rtol=1e-9))):
            issues.append(f"{k} differs between the ends ({va[k]} at A, {vb[k]} at B; end A's is written)")
    return va, vb, issues


def _quiet_write(bdf, path: Path, size: int) -> None:
    with contextlib.redirect_stdout(io.StringIO()):
        bdf.write_bdf(str(path), size=size, is_double=False, enddata=True)


# --------------------------------------------------------------------------- template
_EDITED = ("materials", "properties", "elements", "masses")  # the card groups the template writer edits


def _copy_deck(bdf):
    """A copy of a pyNastran deck to write into: the deck object and the card groups the template
    writer edits or adds to are deep copies; every other card group (loads, aero, monitor points,
    plot elements...) is shared, untouched. pyNastran cannot deep-copy some cards (PLOTEL, TLOAD2
    with an integer phase, MONPNT1 with a long label: the glider deck fmondsp.dat has them all)."""
    other = {name: value for name, value in vars(bdf).items()
             if isinstance(value, (dict, list)) and name not in _EDITED}
    for name in other:
        setattr(bdf, name, {})
    try:
        new = copy.deepcopy(bdf)
    finally:
        for name, value in other.items():
            setattr(bdf, name, value)
    for name, value in other.items():
        setattr(new, name, copy.copy(value))
    return new


def _write_into_template(model: Model, path: Path, deck: BdfDeck, size: int) -> list[str]:
    bdf = _copy_deck(deck.bdf)
    bdf.log = _QuietLog()
    u, w = deck.units, deck.wtmass
    notes: list[str] = []
    tmodel = deck.model
    if sorted(model.node_ids.tolist()) != sorted(tmodel.node_ids.tolist()):
        raise ModelError("write_bdf: the model's node ids differ from the template deck's; write without template= "
                         "for a model with a different mesh")
    if not np.allclose(model.xyz[np.argsort(model.node_ids)], tmodel.xyz[np.argsort(tmodel.node_ids)],
                       rtol=0, atol=1e-9 * max(1.0, float(np.abs(tmodel.xyz).max()))):
        raise ModelError("write_bdf: node coordinates differ from the template deck; geometry changes are not "
                         "written into a template (write without template=)")
    next_mid = max(list(bdf.materials) + [0]) + 1
    next_pid = max(list(bdf.properties) + [0]) + 1
    mat_values: dict[int, dict] = {}

    def material_id(mid: int, mat: Material) -> int:
        nonlocal next_mid
        vals = _material_values(mat, u, w)
        if mid in mat_values and not all(_same(mat_values[mid][k] or 0.0, vals[k] or 0.0) for k in vals):
            for other, ov in mat_values.items():  # an already split copy with the same values
                if all(_same(ov[k] or 0.0, vals[k] or 0.0) for k in vals):
                    return other
            src = bdf.materials[mid]
            new = copy.deepcopy(src)
            new.mid = next_mid
            new.comment = f"copy of MAT1 {mid} with values updated by flexgvt"
            bdf.materials[next_mid] = new
            mid, next_mid = next_mid, next_mid + 1
        mat_values[mid] = vals
        card = bdf.materials[mid]
        card.e, card.rho = vals["E"], vals["rho"]
        card.g, card.nu = vals["G"], vals["nu"]
        return mid

    names = {g.name for g in model.beams}
    missing = sorted(set(deck.beams) - names)
    extra = sorted(names - set(deck.beams))
    if missing or extra:
        raise ModelError(f"write_bdf: beam groups differ from the template (missing {missing}, not in the deck "
                         f"{extra}); write without template=")
    for group in model.beams:
        src = deck.beams[group.name]
        if len(group.ids) != len(src.eids):
            raise ModelError(f"write_bdf: beam group '{group.name}' has {len(group.ids)} elements, the template "
                             f"{len(src.eids)}")
        section = _scale_section(group.section, 1.0 / u.length)
        if src.ptype == "CONROD":  # the element carries material and section
            for eid in src.eids:
                elem = bdf.elements[eid]
                elem.mid = material_id(src.mid, group.material)
                elem.A, elem.j = section.A, section.J
            continue
        prop = bdf.properties[src.pid]
        prop.mid = material_id(src.mid, group.material)
        if src.ptype == "PROD":
            prop.A, prop.j = section.A, section.J
            continue
        _update_beam_property(bdf, prop, section, src, notes)

    # concentrated masses
    if len(model.masses) != len(deck.mass_sources):
        raise ModelError(f"write_bdf: the model has {len(model.masses)} concentrated masses, the template "
                         f"{len(deck.mass_sources)}; write without template=")
    for item, old, (card, ident) in zip(model.masses, tmodel.masses, deck.mass_sources):
        if item.node != old.node:
            raise ModelError(f"write_bdf: concentrated mass from {card} {ident} moved from node {old.node} to "
                             f"{item.node}")
        if _same(item.mass, old.mass) and _same(item.offset, old.offset) and _same(item.inertia, old.inertia):
            continue
        if card.startswith("NSM"):
            notes.append(f"mass lumped from the NSM of {card[4:]} {ident} changed; NSM is not written back")
            continue
        elem = bdf.masses[ident]
        node_xyz = deck.model.xyz[deck.model.index_of([item.node])[0]] / u.length
        m = item.mass / (u.mass * w)
        r = np.asarray(item.offset) / u.length
        J = np.asarray(item.inertia) / (u.inertia * w)
        if card == "CONM2":
            if elem.cid == -1:
                elem.X = node_xyz + r
                T = np.eye(3)
            else:
                T = coord_axes(bdf, elem.cid, node_xyz, f"CONM2 {ident}")
                elem.X = T.T @ r
            Jl = T.T @ J @ T
            elem.mass = m
            elem.I = np.array([Jl[0, 0], -Jl[1, 0], Jl[1, 1], -Jl[2, 0], -Jl[2, 1], Jl[2, 2]])
        else:  # CONM1
            T = coord_axes(bdf, elem.cid, node_xyz, f"CONM1 {ident}")
            S = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
            M = np.zeros((6, 6))
            M[:3, :3] = m * np.eye(3)
            M[:3, 3:] = -m * S
            M[3:, :3] = m * S
            M[3:, 3:] = J - m * S @ S
            T6 = np.zeros((6, 6))
            T6[:3, :3] = T6[3:, 3:] = T
            elem.mass_matrix = T6.T @ M @ T6

    # springs and dampers
    if len(model.springs) != len(deck.spring_sources):
        raise ModelError(f"write_bdf: the model has {len(model.springs)} springs, the template "
                         f"{len(deck.spring_sources)}; write without template=")
    prop_values: dict[int, tuple] = {}

    def prop_for(elem, values: tuple):
        nonlocal next_pid
        pid = elem.pid
        if pid in prop_values and not _same(prop_values[pid], values):
            new = copy.deepcopy(bdf.properties[pid])
            new.pid = next_pid
            bdf.properties[next_pid] = new
            elem.pid = next_pid
            pid, next_pid = next_pid, next_pid + 1
        prop_values[pid] = values
        return bdf.properties[pid]

    tr, rot = u.force / u.length, u.moment
    for item, old, (card, ident) in zip(model.springs, tmodel.springs, deck.spring_sources):
        if (item.node_a, item.node_b) != (old.node_a, old.node_b) or not np.allclose(item.frame, old.frame):
            raise ModelError(f"write_bdf: the spring from {card} {ident} changed its nodes or axes")
        scale = np.r_[[tr] * 3, [rot] * 3]
        k = np.asarray(item.stiffness) / scale
        c = np.asarray(item.damping) / scale
        elem = bdf.elements[ident]
        if card in ("CELAS1", "CELAS2", "CDAMP1", "CDAMP2"):
            comp = int(elem.c1 or elem.c2) - 1
            if card == "CELAS1":
                prop_for(elem, (k[comp],)).k = k[comp]
            elif card == "CELAS2":
                elem.k = k[comp]
            elif card == "CDAMP1":
                prop_for(elem, (c[comp],)).b = c[comp]
            else:
                elem.b = c[comp]
        elif card == "CVISC":
            p = prop_for(elem, (c[0], c[3]))
            p.ce, p.cr = c[0], c[3]
        elif card == "CBUSH":
            p = prop_for(elem, tuple(k) + tuple(c))
            if "K" in p.vars or np.any(k):
                p.Ki = list(k)
                if "K" not in p.vars:
                    p.vars.append("K")
            if "B" in p.vars or np.any(c):
                p.Bi = list(c)
                if "B" not in p.vars:
                    p.vars.append("B")
    if len(model.rigid_links) != len(deck.rigid_sources) or \
            len(model.interpolations) != len(deck.interpolation_sources) or \
            len(model.constraints) != len(deck.constraint_sources):
        raise ModelError("write_bdf: rigid links or interpolations (RBE3) differ from the template; write without "
                         "template=")
    _quiet_write(bdf, path, size)
    return notes


def _update_beam_property(bdf, prop, section, src, notes: list[str]) -> None:
    """Write a (deck-unit) flexgvt section, uniform or tapered, into a PBAR/PBARL/PBEAM/PBEAML card."""
    where = f"{prop.type} {prop.pid}"
    tapered = isinstance(section, TaperedSection)
    if tapered and prop.type in ("PBAR", "PBARL"):
        raise ModelError(f"write_bdf: beam group '{src.name}' ({where}, CBAR) has a TaperedSection; a CBAR cannot "
                         "taper. Write without template= (tapered groups become CBEAM + PBEAM/PBEAML)")
    if prop.type in ("PBARL", "PBEAML"):
        shape = prop.Type if prop.type == "PBARL" else prop.beam_type
        x = np.atleast_1d(np.asarray(getattr(prop, "xxb", [0.0]), float))
        dims = _library_ends(section, shape)
        if dims is not None and (not tapered or len(x) == 2):
            if prop.type == "PBARL":
                prop.dim = dims[0]
            else:  # every station of a uniform section, or end A and end B
                prop.dim = np.array([dims[0]] * (len(x) - 1) + [dims[1]], float)
            return
        old = [prop.dim] if prop.type == "PBARL" else [prop.dim[int(np.argmin(x))], prop.dim[int(np.argmax(x))]]
        ref = [library_section(where, shape, d).section for d in old]
        if _same_section(section, ref[0] if len(ref) == 1 or _same_section(ref[0], ref[1]) else
                         TaperedSection(*ref)):
            return  # unchanged
        # Values no longer match the shape: replace by an equivalent PBAR / PBEAM.
        va, vb, issues = _pbeam_ends(section, src.principal)
        nsm = prop.nsm if prop.type == "PBARL" else np.atleast_1d(prop.nsm if prop.nsm is not None else [0.0])
        del bdf.properties[prop.pid]
        if prop.type == "PBARL":
            bdf.add_pbar(prop.pid, prop.mid, A=va["A"], i1=va["I1"], i2=va["I2"], i12=va["I12"], j=va["J"],
                         nsm=nsm or 0.0, k1=va["K1"], k2=va["K2"],
                         comment=f"PBARL {prop.pid} ({shape}) replaced by flexgvt: updated section values")
        else:
            st = [va, vb] if tapered else [va]
            bdf.add_pbeam(prop.pid, prop.mid, [0.0, 1.0][:len(st)], ["YES"] * len(st), *[[v[k] for v in st] for k in
                          ("A", "I1", "I2", "I12", "J")], nsm=[float(nsm[int(np.argmin(x))]),
                                                              float(nsm[int(np.argmax(x))])][:len(st)],
                          k1=va["K1"] or 0.0, k2=va["K2"] or 0.0,
                          comment=f"PBEAML {prop.pid} ({shape}) replaced by flexgvt: updated section values")
            notes.extend(f"{where}: {i}" for i in issues)
        notes.append(f"{where} ({shape}) was replaced by an equivalent "
                     f"{'PBAR' if prop.type == 'PBARL' else 'PBEAM'}: its updated values are not those of a {shape}")
        return
    va, vb, issues = _pbeam_ends(section, src.principal)
    if prop.type == "PBAR":
        prop.A, prop.i1, prop.i2, prop.i12, prop.j = va["A"], va["I1"], va["I2"], va["I12"], va["J"]
        prop.k1, prop.k2 = va["K1"], va["K2"]
    else:  # PBEAM: every station on the line between the end values (constant when uniform)
        x = np.atleast_1d(np.asarray(prop.xxb, float))
        t = (x - x.min()) / (x.max() - x.min()) if x.max() > x.min() else np.zeros_like(x)
        prop.A, prop.i1, prop.i2, prop.i12, prop.j = ([va[k] + (vb[k] - va[k]) * ti for ti in t]
                                                      for k in ("A", "I1", "I2", "I12", "J"))
        prop.k1 = va["K1"] or 0.0
        prop.k2 = va["K2"] or 0.0
        notes.extend(f"{where}: {i}" for i in issues)


# --------------------------------------------------------------------------- compact
def _write_compact(model: Model, path: Path, configurations, u: Units, size: int, n_modes: int) -> list[str]:
    from pyNastran.bdf.bdf import BDF

    notes: list[str] = []
    bdf = BDF(log=_QuietLog())
    bdf.sol = 103
    bdf.executive_control_lines = ["SOL 103"]
    node_ids = model.node_ids
    for nid, x in zip(node_ids.tolist(), model.xyz / u.length):
        bdf.add_grid(int(nid), [float(v) for v in x])
    xyz = dict(zip(node_ids.tolist(), model.xyz))
    mats: list[Material] = []
    lumped = {g.mass == "lumped" for g in model.beams}
    if len(lumped) > 1:
        raise ModelError("write_bdf: beam groups mix lumped and consistent mass; Nastran's PARAM,COUPMASS is "
                         "global. Use one formulation")
    if lumped == {False}:
        bdf.add_param("COUPMASS", [1])
    if any(g.rotary_inertia for g in model.beams):
        notes.append("beam rotary inertia (rotary_inertia=True) has no bulk data equivalent and is not written")
    eid_used = set()
    inexact: dict[str, list[str]] = {}  # groups whose mass formulation the written card does not have
    for pid, group in enumerate(model.beams, start=1):
        try:
            mid = next(i for i, m in enumerate(mats, start=1) if m == group.material)
        except StopIteration:
            mats.append(group.material)
            mid = len(mats)
            vals = _material_values(group.material, u, 1.0)
            bdf.add_mat1(mid, vals["E"], vals["G"] if group.material.G is not None else None, vals["nu"],
                         rho=vals["rho"], comment=f"flexgvt material '{group.material.name}'")
        section = _scale_section(group.section, 1.0 / u.length)
        comment = f"flexgvt beam group '{group.name}'" if group.name else ""
        if isinstance(section, RodSection):
            bdf.add_prod(pid, mid, section.A, j=section.J, comment=comment)
            for eid, (na, nb) in zip(group.ids.tolist(), group.nodes.tolist()):
                bdf.add_crod(int(eid), pid, [int(na), int(nb)])
                eid_used.add(int(eid))
            continue
        # CBEAM keeps rho*Ip in Nastran's mass, CBAR has none (read_bdf follows Nastran): a uniform
        # section without torsional inertia is a CBAR + PBAR, any other a CBEAM + PBEAML/PBEAM (a
        # tapered one with its end A and end B stations).
        tapered = isinstance(section, TaperedSection)
        ends = _ends(section)
        props = [e.properties() for e in ends]
        beam = tapered or props[0]["Ip"] > 0.0
        if group.mass != "lumped" and (group.mass == "consistent-bending") != beam:
            inexact.setdefault("CBEAM" if beam else "CBAR", []).append(group.name or str(pid))
        library = library_dims(ends[0])
        dims = _library_ends(section, library[0]) if library is not None else None
        if dims is not None:
            x, so = ([0.0, 1.0], ["YES", "YES"]) if tapered else ([1.0], ["YES"])
            bdf.add_pbeaml(pid, mid, library[0], x, dims[:len(x)], so=so, nsm=[0.0] * len(x), comment=comment)
        elif beam:
            va, vb, issues = _pbeam_ends(section)
            notes.extend(f"beam group '{group.name or pid}': {i}" for i in issues)
            # A polar mass moment other than rho (I1 + I2): PBEAM's NSI carries the difference
            # (mass moment of inertia per length), which read_bdf adds back.
            nsi = [float(vals_rho(group, u) * (p["Ip"] - p["Iy"] - p["Iz"])) for p in props]
            nsi = [0.0 if abs(p["Ip"] - (p["Iy"] + p["Iz"])) <= 1e-12 * (p["Iy"] + p["Iz"]) else v
                   for p, v in zip(props, nsi)]
            st = [va, vb] if tapered else [va]
            bdf.add_pbeam(pid, mid, [0.0, 1.0][:len(st)], ["YES"] * len(st), *[[v[k] for v in st] for k in
                          ("A", "I1", "I2", "I12", "J")], nsm=[0.0] * len(st), k1=va["K1"] or 0.0,
                          k2=va["K2"] or 0.0, nsia=nsi[0], nsib=nsi[1],
                          comment=comment)  # K = 0: no shear flexibility (PBEAM blank is 1.0)
        else:
            vals = to_properties(section)
            bdf.add_pbar(pid, mid, A=vals["A"], i1=vals["I1"], i2=vals["I2"], i12=0.0, j=vals["J"],
                         k1=vals["K1"], k2=vals["K2"], comment=comment)
        a = np.array([xyz[n] for n in group.nodes[:, 0].tolist()])
        b = np.array([xyz[n] for n in group.nodes[:, 1].tolist()])
        ex = (b - a) / np.linalg.norm(b - a, axis=1, keepdims=True)
        z = group.orientation - np.sum(group.orientation * ex, axis=1, keepdims=True) * ex
        z /= np.linalg.norm(z, axis=1, keepdims=True)
        v = np.cross(z, ex)  # Nastran v = element y, so that Nastran z = x cross v = flexgvt z
        for eid, (na, nb), vv in zip(group.ids.tolist(), group.nodes.tolist(), v):
            add = bdf.add_cbeam if beam else bdf.add_cbar
            add(int(eid), pid, [int(na), int(nb)], [float(c) for c in vv], None)
            eid_used.add(int(eid))
    for card, names in inexact.items():
        notes.append(f"beam groups {', '.join(names)} are written as {card}s, whose coupled mass (COUPMASS) Nastran "
                     "forms with " + ("the axial and torsional terms lumped" if card == "CBEAM" else
                                      "linear axial terms and no torsional inertia") +
                     ": the deck's axial and torsion modes differ slightly from the model's")
    next_eid = max(eid_used | {0}) + 1
    next_pid = len(model.beams) + 1
    next_cid = 1
    for item in model.masses:
        J = np.asarray(item.inertia) / u.inertia
        bdf.add_conm2(next_eid, item.node, item.mass / u.mass, cid=0, X=list(np.asarray(item.offset) / u.length),
                      I=[J[0, 0], -J[1, 0], J[1, 1], -J[2, 0], -J[2, 1], J[2, 2]])
        next_eid += 1
    scale = np.r_[[u.force / u.length] * 3, [u.moment] * 3]
    for s in model.springs:
        k = np.asarray(s.stiffness) / scale
        c = np.asarray(s.damping) / scale
        nodes = [s.node_a, s.node_b]
        if np.allclose(s.frame, np.eye(3), atol=1e-12):
            for comp in range(6):
                if k[comp]:
                    bdf.add_celas2(next_eid, k[comp], nodes, c1=comp + 1, c2=comp + 1 if s.node_b else 0)
                    next_eid += 1
                if c[comp]:
                    bdf.add_cdamp2(next_eid, c[comp], nodes, c1=comp + 1, c2=comp + 1 if s.node_b else 0)
                    next_eid += 1
            continue
        F = np.asarray(s.frame)
        line = None if s.node_b is None else xyz[s.node_b] - xyz[s.node_a]
        if line is not None and np.linalg.norm(line) > 1e-9:
            along = abs(F[:, 0] @ line) / np.linalg.norm(line) > 1 - 1e-12
            if along and not np.any(k) and not np.any(c[[1, 2, 4, 5]]):  # a dashpot along the line: CVISC
                bdf.add_pvisc(next_pid, c[0], c[3])
                bdf.add_cvisc(next_eid, next_pid, nodes)
                next_pid, next_eid = next_pid + 1, next_eid + 1
                continue
            raise ModelError(f"write_bdf: spring between distinct nodes {s.node_a} and {s.node_b} with rotated axes "
                             "has no exact bulk data card (CBUSH needs coincident nodes); use basic axes")
        origin = xyz[s.node_a] / u.length
        bdf.add_cord2r(next_cid, list(origin), list(origin + F[:, 2]), list(origin + F[:, 0]))
        bdf.add_pbush(next_pid, list(k), list(c), [None] * 6)
        bdf.add_cbush(next_eid, next_pid, nodes, None, None, cid=next_cid)
        next_cid, next_pid, next_eid = next_cid + 1, next_pid + 1, next_eid + 1
    for link in model.rigid_links:
        bdf.add_rbe2(next_eid, link.independent, link.components, list(link.dependents))
        next_eid += 1
    for con in model.constraints:  # MPC set 1, selected by every subcase
        nodes, comps, coefs = zip(*con.terms)  # rotation terms scale with the length unit (see the reader)
        bdf.add_mpc(1, list(nodes), [str(c) for c in comps],
                    [a / (u.length if c > 3 else 1.0) for c, a in zip(comps, coefs)])
    for ip in model.interpolations:  # one weight group per distinct weight
        groups: dict[float, list[int]] = {}
        for node, w in zip(ip.nodes, ip.weights):
            groups.setdefault(float(w), []).append(int(node))
        bdf.add_rbe3(next_eid, ip.reference, ip.components, list(groups), ["123"] * len(groups), list(groups.values()))
        next_eid += 1
    elem_nodes = {int(e): (int(a), int(b)) for g in model.beams for e, (a, b) in zip(g.ids, g.nodes)}
    _write_configurations(bdf, list(configurations or []), u, n_modes, elem_nodes, bool(model.constraints))
    _quiet_write(bdf, path, size)
    return notes


def _write_configurations(bdf, configurations: list[Configuration], u: Units, n_modes: int, elem_nodes,
                          mpc: bool = False) -> None:
    from pyNastran.bdf.case_control_deck import CaseControlDeck

    lines = ["ECHO = NONE", "METHOD = 1"] + (["MPC = 1"] if mpc else [])
    bdf.add_eigrl(1, nd=n_modes)
    for i, cfg in enumerate(configurations, start=1):
        if cfg.suspension or cfg.springs or cfg.masses:
            raise ModelError(f"write_bdf: configuration '{cfg.name}' has cords, springs or masses of its own; bulk "
                             "data has no per-subcase elements. Put them in the model before writing")
        lines += [f"SUBCASE {i}", f"  LABEL = {cfg.name}"]
        by_comp: dict[str, list[int]] = {}
        held = {int(n): set(c) for n, c in cfg.fixed.items()}
        for node, items in cfg.prescribed.items():  # prescribed DOFs are SPC'd, their values are SPCDs
            held.setdefault(int(node), set()).update(str(c) for c in items)
        for node, comps in held.items():
            by_comp.setdefault("".join(sorted(comps)), []).append(int(node))
        for comps, nodes in sorted(by_comp.items()):
            bdf.add_spc1(i, comps, sorted(nodes))
        if by_comp:
            lines.append(f"  SPC = {i}")
        factors, sets = [], []
        if cfg.gravity:
            d = np.asarray(cfg.gravity_direction, float)
            bdf.add_grav(200 + i, cfg.g / u.length, list(d / np.linalg.norm(d)))
            factors.append(cfg.gravity)
            sets.append(200 + i)
        have = False
        for load in cfg.forces:
            f = np.asarray(load.force, float) / u.force
            m = np.asarray(load.moment, float) / u.moment
            if np.any(f):
                bdf.add_force(300 + i, load.node, 1.0, list(f))
                have = True
            if np.any(m):
                bdf.add_moment(300 + i, load.node, 1.0, list(m))
                have = True
        for dist in cfg.distributed:
            w = np.asarray(dist.per_length, float) * u.length / u.force
            for e in dist.elements:
                for k, axis in enumerate("XYZ"):
                    if w[k]:
                        bdf.add_pload1(300 + i, int(e), f"F{axis}", "FR", 0.0, w[k], 1.0, w[k])
                        have = True
        for node, items in cfg.prescribed.items():
            for comp, value in sorted(items.items()):
                bdf.add_spcd(300 + i, [int(node)], [str(comp)], [value / (u.length if comp <= 3 else 1.0)])
                have = True
        if have:
            factors.append(1.0)
            sets.append(300 + i)
        if sets:
            bdf.add_load(100 + i, 1.0, factors, sets)
            lines.append(f"  LOAD = {100 + i}")
    lines.append("BEGIN BULK")
    bdf.case_control_deck = CaseControlDeck(lines, bdf.log)


def write_bdf(model: Model, path, template: BdfDeck | None = None, *, configurations=None,
              units: str | Units = "SI", size: int = 16, n_modes: int = 10) -> Path:
    """Write ``model`` as Nastran bulk data to ``path``; returns the path.

    template: a BdfDeck from read_bdf. Its deck is written back (case control, loads, constraints,
    comments and every card flexgvt does not touch kept as pyNastran writes them; INCLUDEs are
    merged into the one file) with the model's material, beam section, concentrated mass and
    spring/damper values. A MAT1 or spring property shared by groups that now differ is split
    into copies with new ids; a PBARL/PBEAML whose values no longer fit its shape becomes an
    equivalent PBAR/PBEAM. The deck's units and PARAM,WTMASS are kept.
    Without template: a compact deck (GRID, CBAR + PBAR/PBARL + MAT1, CONM2, CELAS2/CDAMP2 or
    CBUSH, RBE2, RBE3, MPC) in ``units``, with one SUBCASE per entry of ``configurations`` (SPC1, GRAV,
    FORCE/MOMENT, PLOAD1 combined by LOAD) and an EIGRL for ``n_modes``.
    size: 16 (large field, default: 12 significant digits, so updated values survive) or 8 (small field).
    """
    path = Path(path)
    if template is not None:
        if configurations is not None:
            raise ModelError("write_bdf: configurations= is for compact decks; a template keeps its own case "
                             "control and loads")
        notes = _write_into_template(model, path, template, size)
    else:
        notes = _write_compact(model, path, configurations, get_units(units), size, n_modes)
    if notes:
        warnings.warn(f"{path}: " + "; ".join(notes), stacklevel=2)
    return path
