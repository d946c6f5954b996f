"""Model data in a comparable form, for bulk data round-trip tests."""

from __future__ import annotations

import dataclasses

import numpy as np

from flexgvt.model import Model, TaperedSection


def _perp(orientation, a, b):
    ex = (b - a) / np.linalg.norm(b - a)
    z = orientation - (orientation @ ex) * ex
    return z / np.linalg.norm(z)


def model_data(model) -> dict:
    """Nodes, beam groups, masses, effective springs, rigid links: plain numbers, order-stable."""
    xyz = dict(zip(model.node_ids.tolist(), model.xyz))
    beams = []
    for g in model.beams:
        m = g.material
        beams.append({
            "material": (m.E, m.rho, m.shear_modulus),
            "section": list(g.section.end_properties()) if isinstance(g.section, TaperedSection) else
            g.section.properties(),
            "nodes": g.nodes.tolist(),
            "orientation": np.array([_perp(o, xyz[a], xyz[b]) for o, (a, b) in zip(g.orientation, g.nodes)]),
            "mass": g.mass, "rotary_inertia": g.rotary_inertia})
    masses = [(m.node, m.mass, np.asarray(m.offset), np.asarray(m.inertia)) for m in model.masses]
    springs: dict = {}
    for s in model.springs:
        F = np.asarray(s.frame)
        key = (s.node_a, s.node_b)
        k = springs.setdefault(key, np.zeros((4, 3, 3)))
        k[0] += F @ np.diag(s.stiffness[:3]) @ F.T
        k[1] += F @ np.diag(s.stiffness[3:]) @ F.T
        k[2] += F @ np.diag(s.damping[:3]) @ F.T
        k[3] += F @ np.diag(s.damping[3:]) @ F.T
    links = sorted((link.independent, tuple(sorted(link.dependents)), link.components) for link in model.rigid_links)
    interpolations = sorted((ip.reference, tuple(sorted(zip(ip.nodes, np.round(ip.weights / ip.weights.sum(), 12)))),
                             ip.components) for ip in model.interpolations)
    return {"nodes": sorted((n, tuple(x)) for n, x in xyz.items()), "beams": beams, "masses": masses,
            "springs": springs, "links": links, "interpolations": interpolations}


def config_data(model, cfg) -> dict:
    """Fixed DOFs, total gravity vector, per-node force/moment sums, per-element-node-pair line loads."""
    elem_nodes = {int(e): tuple(int(n) for n in pair) for g in model.beams for e, pair in zip(g.ids, g.nodes)}
    loads: dict = {}
    for f in cfg.forces:
        acc = loads.setdefault(f.node, np.zeros(6))
        acc += np.r_[f.force, f.moment]
    dist: dict = {}
    for d in cfg.distributed:
        for e in d.elements:
            acc = dist.setdefault(elem_nodes[e], np.zeros(3))
            acc += np.asarray(d.per_length)
    return {"fixed": {n: "".join(sorted(c)) for n, c in cfg.fixed.items()}, "gravity": cfg.gravity_vector,
            "loads": loads, "distributed": dist}


def assert_close(a, b, rtol=1e-9, path="") -> None:
    """Recursive comparison of nested dict/list/tuple/array data with a relative tolerance."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), f"{path}: keys {sorted(a, key=str)} != {sorted(b, key=str)}"
        for k in a:
            assert_close(a[k], b[k], rtol, f"{path}.{k}")
    elif isinstance(a, (list, tuple)) and not (a and isinstance(a[0], (int, float, np.floating)) and
                                               all(isinstance(x, (int, float, np.floating)) for x in a)):
        assert len(a) == len(b), f"{path}: length {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_close(x, y, rtol, f"{path}[{i}]")
    elif isinstance(a, str) or a is None or isinstance(a, bool):
        assert a == b, f"{path}: {a!r} != {b!r}"
    else:
        x, y = np.asarray(a, float), np.asarray(b, float)
        scale = max(np.abs(x).max(initial=0.0), np.abs(y).max(initial=0.0), 1e-300)
        assert x.shape == y.shape and np.allclose(x, y, rtol=rtol, atol=rtol * scale), f"{path}: {x} != {y}"


def rebuild(model: Model, material=None, section=None, mass=None, spring=None) -> Model:
    """A copy of ``model`` with some values changed (what model updating hands back)."""
    new = Model(model.name)
    new.add_nodes(model.xyz, ids=model.node_ids)
    for g in model.beams:
        mat = (material or {}).get(g.name, g.material)
        sec = (section or {}).get(g.name, g.section)
        new.add_beams(g.nodes, mat, sec, orientation=g.orientation, rotary_inertia=g.rotary_inertia, mass=g.mass,
                      name=g.name)
    for i, m in enumerate(model.masses):
        scale = (mass or {}).get(i, 1.0)
        new.add_mass(m.node, m.mass * scale, offset=m.offset, inertia=m.inertia * scale)
    for i, s in enumerate(model.springs):
        scale = (spring or {}).get(i, 1.0)
        new.add_spring(s.node_a, s.node_b, stiffness=s.stiffness * scale, damping=s.damping, frame=s.frame)
    for link in model.rigid_links:
        new.add_rigid_link(link.independent, link.dependents, components=link.components)
    for ip in model.interpolations:
        new.add_interpolation(ip.reference, ip.nodes, ip.weights, components=ip.components)
    return new


def comparable(obj):
    """Dataclass values without names (renumbered ids rename cards), arrays as lists, floats to 12 digits."""
    if dataclasses.is_dataclass(obj):
        return tuple((f.name, comparable(getattr(obj, f.name))) for f in dataclasses.fields(obj) if f.name != "name")
    if isinstance(obj, (tuple, list)):
        return tuple(comparable(v) for v in obj)
    if isinstance(obj, np.ndarray):
        return comparable(obj.tolist())
    if isinstance(obj, float):
        return float(f"{obj:.12g}")
    return obj


def shell_data(model):
    """Shell groups as comparable values: nodes, property, theta, material axis, ZOFFS, corners, mass."""
    return [(g.nodes.tolist(), comparable(g.property), comparable(g.theta), comparable(g.material_axis),
             comparable(g.zoffs), comparable(g.corner_thickness), g.mass) for g in model.shells]
