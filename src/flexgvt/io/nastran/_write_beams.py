"""Writing beams and rods: MAT1, PBAR/PBARL/PBEAM/PBEAML/PROD and CBAR/CBEAM/CROD/CONROD, into a
template deck (values updated in place, shared MAT1s split) or as a compact deck."""

from __future__ import annotations

import copy

import numpy as np

from ...errors import ModelError
from ...model import Material, Model, RodSection, TaperedSection
from ._common import Units
from ._elements import scale_section as _scale_section
from ._read import BdfDeck
from ._sections import library_dims, library_section, to_properties
from ._write_common import same


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


def update_beams(bdf, model: Model, deck: BdfDeck, notes: list[str]) -> None:
    """Write the model's beam and rod groups into the template's cards (same groups, same elements)."""
    u, w = deck.units, deck.wtmass
    next_mid = max(list(bdf.materials) + [0]) + 1
    mat_values: dict[int, dict] = {}

    def material_id(mid: int, mat: Material) -> int:
        nonlocal next_mid
        vals = _material_values(mat, u, w)
        if mid in mat_values and not all(same(mat_values[mid][k] or 0.0, vals[k] or 0.0) for k in vals):
            for other, ov in mat_values.items():  # an already split copy with the same values
                if all(same(ov[k] or 0.0, vals[k] or 0.0) for k in vals):
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


def check_one_mass_formulation(model: Model) -> None:
    """A compact deck has one PARAM,COUPMASS for every beam, rod and shell: refuse a model whose
    groups mix lumped and consistent mass, naming the groups and what to pass."""
    groups: dict[str, list[str]] = {"lumped": [], "consistent": []}
    named = [("rod" if isinstance(g.section, RodSection) else "beam", k, g) for k, g in enumerate(model.beams)]
    named += [("shell", k, g) for k, g in enumerate(model.shells)]
    for kind, k, g in named:
        groups["lumped" if g.mass == "lumped" else "consistent"].append(
            f"{kind} group {k} '{g.name}'" if g.name else f"{kind} group {k}")
    if groups["lumped"] and groups["consistent"]:
        listed = {m: ", ".join(v[:4]) + (f" and {len(v) - 4} more" if len(v) > 4 else "") for m, v in groups.items()}
        raise ModelError(f"write_bdf: the model mixes lumped mass ({listed['lumped']}) and consistent mass "
                         f"({listed['consistent']}), and Nastran's PARAM,COUPMASS is one for the whole deck. "
                         "Give every group the same: mass='lumped' or 'consistent' in add_beams/add_rods/add_shells "
                         "(the defaults differ: beams 'consistent', rods and shells 'lumped'), or "
                         "model.set_beam_group(k, mass=...) / model.set_shell_group(k, mass=...)")


def write_beams(bdf, model: Model, u: Units, xyz: dict[int, np.ndarray], notes: list[str]) -> set[int]:
    """Beam and rod groups of a compact deck (one property per group); returns the element ids used."""
    mats: list[Material] = []
    lumped = {g.mass == "lumped" for g in model.beams}
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
    return eid_used
