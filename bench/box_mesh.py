"""A structured quad mesh of the built-up wingbox (docs/method.md section 5 case 4) for the scale
benchmark, until fg.cases.wingbox is on main: a cantilever box, span along y from the clamped
root, chord along x, depth along z; two skins, two spars and ribs at a fixed pitch, all 4-node
quads sharing their edge nodes. The same plates for CalculiX (8-node S8R, mid-side nodes added).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SPAN, CHORD, DEPTH = 16.0, 1.0, 0.16
T_SKIN, T_SPAR, T_RIB = 0.008, 0.005, 0.002
E, NU, RHO = 69e9, 0.33, 2851.0
RIB_PITCH = 0.5


@dataclass
class BoxMesh:
    xyz: np.ndarray  # (n, 3) node coordinates [m], node id = row + 1
    quads: dict[str, np.ndarray]  # part -> (m, 4) node ids, counter-clockwise about the outward normal
    root: np.ndarray  # node ids at y = 0
    divisions: tuple[int, int, int]  # chord, depth, span

    @property
    def n_nodes(self) -> int:
        return len(self.xyz)


def divisions(size: float, depth_size: float | None = None) -> tuple[int, int, int]:
    """Quads of about ``size`` [m] (chord, span) and ``depth_size`` (spars, ribs) or the same; the span
    count a multiple of the ribs' count (32)."""
    nc = max(2, round(CHORD / size))
    nd = max(2, round(DEPTH / (depth_size or size)))
    n_ribs = round(SPAN / RIB_PITCH)
    ns = n_ribs * max(1, round(SPAN / size / n_ribs))
    return nc, nd, ns


def box(nc: int, nd: int, ns: int) -> BoxMesh:
    """The box with nc x nd x ns divisions along chord, depth and span."""
    n_per_rib = ns // round(SPAN / RIB_PITCH)
    xs, zs, ys = np.linspace(0, CHORD, nc + 1), np.linspace(0, DEPTH, nd + 1), np.linspace(0, SPAN, ns + 1)
    ids: dict[tuple[int, int, int], int] = {}  # (i chord, k depth, j span) -> node id
    xyz = []

    def node(i, k, j):
        key = (i, k, j)
        if key not in ids:
            ids[key] = len(xyz) + 1
            xyz.append((xs[i], ys[j], zs[k]))
        return ids[key]

    rib_stations = [j for j in range(n_per_rib, ns + 1, n_per_rib)]
    for j in range(ns + 1):  # section perimeter nodes, then the rib's interior at rib stations
        for i in range(nc + 1):
            node(i, 0, j)
            node(i, nd, j)
        for k in range(1, nd):
            node(0, k, j)
            node(nc, k, j)
        if j in rib_stations:
            for i in range(1, nc):
                for k in range(1, nd):
                    node(i, k, j)
    quads = {"skin": [], "spar": [], "rib": []}
    for j in range(ns):
        for i in range(nc):  # bottom skin (normal -z), top skin (+z)
            quads["skin"].append([ids[i, 0, j], ids[i, 0, j + 1], ids[i + 1, 0, j + 1], ids[i + 1, 0, j]])
            quads["skin"].append([ids[i, nd, j], ids[i + 1, nd, j], ids[i + 1, nd, j + 1], ids[i, nd, j + 1]])
        for k in range(nd):  # front spar (normal -x), rear spar (+x)
            quads["spar"].append([ids[0, k, j], ids[0, k + 1, j], ids[0, k + 1, j + 1], ids[0, k, j + 1]])
            quads["spar"].append([ids[nc, k, j], ids[nc, k, j + 1], ids[nc, k + 1, j + 1], ids[nc, k + 1, j]])
    for j in rib_stations:  # ribs in x-z planes (normal +y)
        for i in range(nc):
            for k in range(nd):
                quads["rib"].append([ids[i, k, j], ids[i, k + 1, j], ids[i + 1, k + 1, j], ids[i + 1, k, j]])
    root = np.array([v for (i, k, j), v in ids.items() if j == 0])
    return BoxMesh(np.array(xyz), {p: np.array(q) for p, q in quads.items()}, root, (nc, nd, ns))


def flexgvt_model(mesh: BoxMesh, mass: str = "lumped"):
    """The box as an fg.Model (node ids from 1) and its clamped-root fixed DOFs."""
    import flexgvt as fg
    from flexgvt.model import Material

    al = Material("al", E, RHO, nu=NU)
    model = fg.Model("wingbox")
    model.add_nodes(mesh.xyz, ids=np.arange(1, mesh.n_nodes + 1))
    for part, t in (("skin", T_SKIN), ("spar", T_SPAR), ("rib", T_RIB)):
        model.add_shells(mesh.quads[part], material=al, thickness=t, name=part, mass=mass)
    return model, {int(n): "123456" for n in mesh.root}


def s8r_input(mesh: BoxMesh, n_modes: int, gravity: bool) -> str:
    """A CalculiX input of the same plates as S8R (mid-side nodes added on every quad edge): the
    unloaded modes, or a -1 g NLGEOM step and the modes about it (PERTURBATION)."""
    xyz = [tuple(p) for p in mesh.xyz]
    mid: dict[tuple[int, int], int] = {}

    def midside(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            xyz.append(tuple(0.5 * (mesh.xyz[a - 1] + mesh.xyz[b - 1])))
            mid[key] = len(xyz)
        return mid[key]

    lines_el = []
    eid = 0
    for part in ("skin", "spar", "rib"):
        lines_el.append(f"*ELEMENT, TYPE=S8R, ELSET={part.upper()}")
        for q in mesh.quads[part]:
            eid += 1
            m = [midside(q[c], q[(c + 1) % 4]) for c in range(4)]
            lines_el.append(", ".join(str(v) for v in [eid, *q, *m]))
    lines = ["*NODE"] + [f"{k + 1}, {x:.10g}, {y:.10g}, {z:.10g}" for k, (x, y, z) in enumerate(xyz)]
    lines += lines_el
    at_root = set(mesh.root.tolist())
    root = sorted(at_root | {v for (a, b), v in mid.items() if a in at_root and b in at_root})
    lines += ["*NSET, NSET=ROOT"] + [", ".join(map(str, root[k:k + 12])) for k in range(0, len(root), 12)]
    lines += ["*ELSET, ELSET=EALL", "SKIN, SPAR, RIB"]
    lines += ["*MATERIAL, NAME=AL", "*ELASTIC", f"{E:.6g}, {NU}", "*DENSITY", f"{RHO}"]
    for part, t in (("skin", T_SKIN), ("spar", T_SPAR), ("rib", T_RIB)):
        lines += [f"*SHELL SECTION, ELSET={part.upper()}, MATERIAL=AL", f"{t}"]
    lines += ["*BOUNDARY", "ROOT, 1, 6"]
    if gravity:
        lines += ["*STEP, NLGEOM, INC=200", "*STATIC", "0.1, 1.0, 1e-5, 0.25", "*DLOAD",
                  "EALL, GRAV, 9.80665, 0., 0., -1.", "*NODE PRINT, NSET=TIP", "U", "*END STEP",
                  "*STEP, PERTURBATION"]
    else:
        lines += ["*STEP"]
    lines += ["*FREQUENCY", f"{n_modes}", "*END STEP"]
    tip = [n + 1 for n in range(mesh.n_nodes) if abs(mesh.xyz[n, 1] - SPAN) < 1e-9]
    tip_set = ["*NSET, NSET=TIP"] + [", ".join(map(str, tip[k:k + 12])) for k in range(0, len(tip), 12)]
    at = lines.index("*ELSET, ELSET=EALL")
    lines[at:at] = tip_set
    return "\n".join(lines) + "\n"
