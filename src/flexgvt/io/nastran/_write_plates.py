"""Writing shells: CQUAD4/CTRIA3 on PSHELL or PCOMP/PCOMPG with MAT1/MAT2/MAT8, in a compact deck
or into a template deck (changed properties, materials, THETA, ZOFFS and corner thicknesses)."""

from __future__ import annotations

from collections import Counter

import numpy as np

from ...errors import ModelError
from ...model import Material, Model
from ...model.shells import AnisotropicMaterial, ShellGroup, ShellProperty
from ._common import Units
from ._read import BdfDeck
from ._write_beams import _material_values
from ._write_common import Numbering, same


class _MaterialIds:
    """Material -> MAT id: the ``known`` (material, id) pairs reused, new cards after the largest id.
    wtmass: the deck's PARAM,WTMASS (densities are written divided by it)."""

    def __init__(self, bdf, u: Units, known: list, wtmass: float = 1.0) -> None:
        self.bdf, self.u, self.ids, self.wtmass = bdf, u, list(known), wtmass
        self.next = max(list(bdf.materials) + [0]) + 1

    def __call__(self, mat) -> int:
        for m, mid in self.ids:
            if m == mat:
                return mid
        mid, u, w = self.next, self.u, self.wtmass
        self.next += 1
        self.ids.append((mat, mid))
        comment = f"flexgvt material '{mat.name}'"
        if isinstance(mat, Material):
            v = _material_values(mat, u, w)
            self.bdf.add_mat1(mid, v["E"], v["G"] if mat.G is not None else None, v["nu"], rho=v["rho"],
                              comment=comment)
        elif isinstance(mat, AnisotropicMaterial):
            G = [getattr(mat, f) / u.stress for f in ("G11", "G12", "G13", "G22", "G23", "G33")]
            self.bdf.add_mat2(mid, *G, rho=mat.rho / (u.density * w), comment=comment)
        else:
            gz = [None if g is None else g / u.stress for g in (mat.G1z, mat.G2z)]
            self.bdf.add_mat8(mid, mat.E1 / u.stress, mat.E2 / u.stress, mat.nu12, mat.G12 / u.stress, g1z=gz[0],
                              g2z=gz[1], rho=mat.rho / (u.density * w), comment=comment)
        return mid


def _property(bdf, prop, pid: int, mats: _MaterialIds, u: Units, comment: str) -> None:
    area_mass = u.mass * mats.wtmass / u.length**2
    if isinstance(prop, ShellProperty):
        mid = [None if m is None else mats(m) for m in (prop.membrane, prop.bending, prop.shear, prop.coupling)]
        t = None if prop.thickness is None else prop.thickness / u.length
        z = [None if v is None else v / u.length for v in (prop.z1, prop.z2)]
        bdf.add_pshell(pid, mid1=mid[0], t=t, mid2=mid[1], twelveIt3=prop.bending_ratio, mid3=mid[2],
                       tst=prop.shear_ratio, nsm=prop.nsm / area_mass, z1=z[0], z2=z[1], mid4=mid[3],
                       comment=comment)
        return
    mids = [mats(p.material) for p in prop.plies]
    t = [p.thickness / u.length for p in prop.plies]
    theta = [p.theta for p in prop.plies]
    souts = ["YES" if p.sout else "NO" for p in prop.plies]
    z0 = None if prop.z0 is None else prop.z0 / u.length
    lam = prop.lam or None
    if prop.plies[0].ply_id is not None:
        bdf.add_pcompg(pid, [p.ply_id for p in prop.plies], mids, t, thetas=theta, souts=souts,
                       nsm=prop.nsm / area_mass, lam=lam, z0=z0, comment=comment)
    else:
        bdf.add_pcomp(pid, mids, t, thetas=theta, souts=souts, nsm=prop.nsm / area_mass, lam=lam, z0=z0,
                      comment=comment)


def _axis_system(bdf, axis: np.ndarray, ids: Numbering, systems: dict) -> int:
    """A CORD2R whose x axis is ``axis`` (for an element's MCID), one per direction."""
    x = axis / np.linalg.norm(axis)
    key = tuple(np.round(x, 12))
    if key not in systems:
        z = np.cross(x, np.eye(3)[int(np.argmin(np.abs(x)))])
        z /= np.linalg.norm(z)
        bdf.add_cord2r(ids.cid, [0.0, 0.0, 0.0], list(z), list(x), comment="flexgvt shell material axis")
        systems[key] = ids.cid
        ids.cid += 1
    return systems[key]


def write_plates(bdf, model: Model, u: Units, ids: Numbering) -> None:
    """Shell groups of a compact deck: one property (PSHELL/PCOMP/PCOMPG) per distinct property,
    CQUAD4/CTRIA3 with the model's element ids, THETA or an MCID system, ZOFFS, corner thicknesses
    (TFLAG 0); PARAM,COUPMASS for consistent shell mass (the caller has checked that beams, rods and
    shells agree: check_one_mass_formulation)."""
    if not model.shells:
        return
    shell_mass = {g.mass for g in model.shells}
    if shell_mass == {"consistent"} and "COUPMASS" not in bdf.params:
        bdf.add_param("COUPMASS", [1])
    beam_mats: list = []  # write_beams numbers the beams' MAT1s 1.. in beam order
    for g in model.beams:
        if not any(m == g.material for m, _ in beam_mats):
            beam_mats.append((g.material, len(beam_mats) + 1))
    mats = _MaterialIds(bdf, u, beam_mats)
    pids: list[tuple[object, int]] = []
    systems: dict = {}
    for group in model.shells:
        pid = next((p for prop, p in pids if prop == group.property), None)
        if pid is None:
            pid = ids.pid
            ids.pid += 1
            pids.append((group.property, pid))
            _property(bdf, group.property, pid, mats, u, f"flexgvt shell group '{group.name}'" if group.name else "")
        _elements(bdf, group, pid, u, ids, systems)


def _elements(bdf, group: ShellGroup, pid: int, u: Units, ids: Numbering, systems: dict) -> None:
    quad = group.nodes.shape[1] == 4
    for k, (eid, nodes) in enumerate(zip(group.ids.tolist(), group.nodes.tolist())):
        if group.material_axis is not None:
            theta_mcid = _axis_system(bdf, group.material_axis[k], ids, systems)
        else:
            theta_mcid = float(group.theta[k])
        corners = [None] * len(nodes) if group.corner_thickness is None else \
            (group.corner_thickness[k] / u.length).tolist()
        zoffs = float(group.zoffs[k]) / u.length
        if quad:
            bdf.add_cquad4(int(eid), pid, nodes, theta_mcid=theta_mcid, zoffset=zoffs, tflag=0, T1=corners[0],
                           T2=corners[1], T3=corners[2], T4=corners[3])
        else:
            bdf.add_ctria3(int(eid), pid, nodes, theta_mcid=theta_mcid, zoffset=zoffs, tflag=0, T1=corners[0],
                           T2=corners[1], T3=corners[2])


def _group_values(g: ShellGroup) -> tuple:
    return (g.nodes.tolist(), g.theta, g.material_axis, g.zoffs, g.corner_thickness, g.mass)


def add_as_ctria3(bdf, triar: dict) -> None:
    """Add CTRIAR cards to ``bdf`` as CTRIA3 (as read_bdf reads them): pyNastran writes a CTRIAR's
    TFLAG into the field its own reader requires blank, so a written CTRIAR could not be read back."""
    if triar:  # the copy's id map is shallow: a list of its own before adding
        bdf._type_to_id_map["CTRIA3"] = list(bdf._type_to_id_map.get("CTRIA3", []))
    for eid, e in triar.items():
        bdf.add_ctria3(eid, e.pid, list(e.nodes), theta_mcid=e.theta_mcid, zoffset=e.zoffset, tflag=e.tflag,
                       T1=e.T1, T2=e.T2, T3=e.T3, comment=f"CTRIAR {eid} written as CTRIA3")


_MAT_FIELDS = {"MAT1": ("e", "g", "nu", "rho"), "MAT2": ("G11", "G12", "G13", "G22", "G23", "G33", "rho"),
               "MAT8": ("e11", "e22", "nu12", "g12", "g1z", "g2z", "rho")}


def _materials_of(prop) -> list:
    if isinstance(prop, ShellProperty):
        return [prop.membrane, prop.bending, prop.shear, prop.coupling]
    return [p.material for p in prop.plies]


def _mids_of(card) -> list:
    return [card.mid1, card.mid2, card.mid3, card.mid4] if card.type == "PSHELL" else list(card.mids)


def update_plates(bdf, model: Model, deck: BdfDeck, notes: list[str]) -> None:
    """Write the model's shell groups into the template's cards (after the beams: a MAT1 the beam
    writer changed is not the shells' any more). A changed property is written into its card when
    only this group uses it, else into a new card the group's elements take; new materials get new
    MAT cards; THETA, ZOFFS and corner thicknesses are written into the elements. The mesh, the
    material axes (MCID) and the mass formulation (PARAM,COUPMASS) must be the template's."""
    old = deck.model.shells
    if len(model.shells) != len(old):
        raise ModelError(f"write_bdf: the model has {len(model.shells)} shell groups, the template {len(old)}; write "
                         "without template=")
    u = deck.units
    ids_map = bdf._type_to_id_map  # shallow copy of the template's: give the lists this copy adds to their own
    for key in list(ids_map):
        ids_map[key] = list(ids_map[key])

    def intact(mid) -> bool:  # the template's card still holds the values read (G of a MAT1: computed or not)
        a, b = bdf.materials.get(mid), deck.bdf.materials.get(mid)
        if a is None or b is None or a.type != b.type:
            return False
        for f in _MAT_FIELDS.get(a.type, ()):
            x, y = getattr(a, f, None), getattr(b, f, None)
            if (x is None or y is None) and (f == "g" or x is y):
                continue
            if x is None or y is None or not same(x, y):
                return False
        return True

    known = []
    for g in old:
        card = deck.bdf.properties[deck.shells[g.name].pid]
        known += [(m, mid) for m, mid in zip(_materials_of(g.property), _mids_of(card))
                  if m is not None and mid not in (None, 0) and intact(mid)]
    mats = _MaterialIds(bdf, u, known, deck.wtmass)
    users = Counter(deck.shells[g.name].pid for g in old)
    next_pid = max(list(bdf.properties) + [0]) + 1
    for new, was in zip(model.shells, old):
        src = deck.shells[was.name]
        where = f"write_bdf: shell group '{new.name}'"
        if new.nodes.shape != was.nodes.shape or not np.array_equal(new.nodes, was.nodes):
            raise ModelError(f"{where}: its elements differ from the template deck's; write without template=")
        if new.mass != was.mass:
            raise ModelError(f"{where}: mass '{new.mass}' differs from the template's '{was.mass}' (PARAM,COUPMASS is "
                             "global); write without template=")
        if (new.material_axis is None) != (was.material_axis is None) or (
                new.material_axis is not None and not same(new.material_axis, was.material_axis)):
            raise ModelError(f"{where}: its material axes (MCID) differ from the template's; write without template=")
        card = deck.bdf.properties[src.pid]
        if new.property != was.property or not all(intact(mid) for mid in _mids_of(card) if mid not in (None, 0)):
            if users[src.pid] == 1:
                pid = src.pid
                del bdf.properties[pid]
            else:
                pid, next_pid = next_pid, next_pid + 1
                notes.append(f"{card.type} {src.pid} is shared by shell groups that now differ: group '{new.name}' "
                             f"takes a new {card.type} {pid}")
            _property(bdf, new.property, pid, mats, u, f"flexgvt shell group '{new.name}' (was {card.type} {src.pid})")
            for eid in src.eids:
                bdf.elements[eid].pid = pid
        # corner thicknesses are absolute in the model: a blank Ti or TFLAG 1 follows the card's T
        _update_elements(bdf, new, was, src.eids, u, new.property.thickness != was.property.thickness)


def _update_elements(bdf, new: ShellGroup, was: ShellGroup, eids, u: Units, new_t: bool) -> None:
    names = ("T1", "T2", "T3", "T4")[:new.nodes.shape[1]]
    for k, eid in enumerate(eids):
        e = bdf.elements[eid]
        if new.material_axis is None and new.theta[k] != was.theta[k]:
            e.theta_mcid = float(new.theta[k])
        if new.zoffs[k] != was.zoffs[k]:
            e.zoffset = float(new.zoffs[k]) / u.length
        a, b = new.corner_thickness, was.corner_thickness
        if (a is None) != (b is None) or (a is not None and (new_t or not same(a[k], b[k]))):
            e.tflag = 0
            for j, f in enumerate(names):
                setattr(e, f, None if a is None else float(a[k, j]) / u.length)
