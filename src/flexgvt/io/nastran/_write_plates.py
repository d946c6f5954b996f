"""Writing shells: CQUAD4/CTRIA3 on PSHELL or PCOMP/PCOMPG with MAT1/MAT2/MAT8 in a compact deck;
a template deck's shells are checked unchanged (their values are not yet written back)."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import Material, Model
from ...model.shells import AnisotropicMaterial, ShellGroup, ShellProperty
from ._common import Units
from ._read import BdfDeck
from ._write_beams import _material_values
from ._write_common import Numbering, same


class _MaterialIds:
    """Material -> MAT id of a compact deck: the beams' MAT1s (numbered 1.. in beam order by
    write_beams) reused, new ones after the largest id."""

    def __init__(self, bdf, model: Model, u: Units) -> None:
        self.bdf, self.u, self.ids = bdf, u, []
        for g in model.beams:
            if not any(m == g.material for m, _ in self.ids):
                self.ids.append((g.material, len(self.ids) + 1))
        self.next = max(list(bdf.materials) + [0]) + 1

    def __call__(self, mat) -> int:
        for m, mid in self.ids:
            if m == mat:
                return mid
        mid, u = self.next, self.u
        self.next += 1
        self.ids.append((mat, mid))
        comment = f"flexgvt material '{mat.name}'"
        if isinstance(mat, Material):
            v = _material_values(mat, u, 1.0)
            self.bdf.add_mat1(mid, v["E"], v["G"] if mat.G is not None else None, v["nu"], rho=v["rho"],
                              comment=comment)
        elif isinstance(mat, AnisotropicMaterial):
            G = [getattr(mat, f) / u.stress for f in ("G11", "G12", "G13", "G22", "G23", "G33")]
            self.bdf.add_mat2(mid, *G, rho=mat.rho / u.density, comment=comment)
        else:
            gz = [None if g is None else g / u.stress for g in (mat.G1z, mat.G2z)]
            self.bdf.add_mat8(mid, mat.E1 / u.stress, mat.E2 / u.stress, mat.nu12, mat.G12 / u.stress, g1z=gz[0],
                              g2z=gz[1], rho=mat.rho / u.density, comment=comment)
        return mid


def _property(bdf, prop, pid: int, mats: _MaterialIds, u: Units, comment: str) -> None:
    area_mass = u.mass / u.length**2
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
    (TFLAG 0); PARAM,COUPMASS for consistent shell mass (it must agree with the beams')."""
    if not model.shells:
        return
    shell_mass = {g.mass for g in model.shells}
    beam_lumped = {g.mass == "lumped" for g in model.beams}
    if len(shell_mass) > 1 or (beam_lumped and beam_lumped != {shell_mass == {"lumped"}}):
        raise ModelError("write_bdf: shell and beam groups mix lumped and consistent mass; Nastran's "
                         "PARAM,COUPMASS is global. Use one formulation")
    if shell_mass == {"consistent"} and "COUPMASS" not in bdf.params:
        bdf.add_param("COUPMASS", [1])
    mats = _MaterialIds(bdf, model, u)
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


def check_plates(model: Model, deck: BdfDeck) -> None:
    """A template deck keeps its shell cards: the model's shell groups must be the deck's. Changed
    shell values are not written back yet (a ModelError says so rather than writing stale values)."""
    old = deck.model.shells
    if len(model.shells) != len(old):
        raise ModelError(f"write_bdf: the model has {len(model.shells)} shell groups, the template {len(old)}; write "
                         "without template=")
    for new, was in zip(model.shells, old):
        a, b = _group_values(new), _group_values(was)
        equal = a[0] == b[0] and a[5] == b[5] and new.property == was.property and all(
            (x is None and y is None) or (x is not None and y is not None and same(x, y)) for x, y in zip(a[1:5],
                                                                                                      b[1:5]))
        if not equal:
            raise ModelError(f"write_bdf: shell group '{new.name}' differs from the template deck's; shell values are "
                             "not yet written into a template: write without template= (a compact deck)")

