"""Test geometry from UFF: coordinate systems (18, 2420), nodes (15, 2411) in global axes, each
node's displacement coordinate system, trace lines (82) and elements (2412) kept for drawing.

Convention (docs/uff.md): a coordinate system is a rotation R (3, 3) whose ROWS are its local x, y, z
axes written in the parent (global) frame, and an origin o (3,): a point or vector with local
components l is, globally, o + l @ R (a vector: l @ R). Dataset 2420 stores exactly this 4x3 matrix
(rows 1-3 R, row 4 o); dataset 18 gives three points in its reference system (origin, a point on
+x, a point in the +xz plane), from which x = (p_x - o)/|.|, z = the part of (p_xz - o) normal to
x, y = z x x; reference systems are resolved first (chained).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import FileFormatError
from .uff_scan import as_column as _column
from .uff_scan import as_ids as _ids
from .uff_scan import get_field as _get

CS_KINDS = {0: "cartesian", 1: "cylindrical", 2: "spherical"}


@dataclass(frozen=True)
class CoordinateSystem:
    """label; kind 'cartesian' (cylindrical and spherical are refused where used); R (3, 3) rows =
    local axes in global; origin (3,) [m]."""

    label: int
    kind: str
    R: np.ndarray
    origin: np.ndarray
    name: str = ""

    def to_global(self, local: np.ndarray) -> np.ndarray:
        """Points (n, 3) given in this system -> global (n, 3)."""
        return self.origin + np.asarray(local, float) @ self.R


GLOBAL = CoordinateSystem(0, "cartesian", np.eye(3), np.zeros(3), "global")


@dataclass(frozen=True)
class TestGeometry:
    """Test points: ids (n,), xyz (n, 3) global [m]; axes (n, 3, 3): each point's displacement
    coordinate system (rows = its local x, y, z in global axes; identity when global), so the
    measured DOF 'point 5, +Z' is along +axes[5][2]; traces: (name, point ids) of the 82 trace lines;
    elements: (element id, FE descriptor, node ids) of 2412; coordinate_systems {label: CS}."""

    __test__ = False  # not a pytest class

    point_ids: np.ndarray
    xyz: np.ndarray
    axes: np.ndarray | None = None
    traces: tuple = ()
    elements: tuple = ()
    coordinate_systems: dict = field(default_factory=dict)
    notes: tuple = ()

    def __post_init__(self) -> None:
        ids = np.asarray(self.point_ids).astype(np.int64)
        object.__setattr__(self, "point_ids", ids)
        axes = np.broadcast_to(np.eye(3), (len(ids), 3, 3)).copy() if self.axes is None else np.asarray(self.axes)
        object.__setattr__(self, "axes", axes)

    def index(self, point_id: int) -> int:
        hits = np.flatnonzero(self.point_ids == point_id)
        if not len(hits):
            raise FileFormatError(f"test point {point_id} is not in the geometry (points {self.point_ids[:10].tolist()}"
                                  f"{'...' if len(self.point_ids) > 10 else ''})")
        return int(hits[0])

    def direction(self, point_id: int, code: int) -> np.ndarray:
        """(3,) global unit vector of the measured DOF (point, UFF direction code +-1..6; 4..6 the axis
        of a rotation) in the point's displacement coordinate system."""
        code = int(code)
        if code == 0 or abs(code) > 6:
            raise FileFormatError(f"point {point_id}: direction code {code} has no direction (scalar channel)")
        return np.sign(code) * self.axes[self.index(point_id)][(abs(code) - 1) % 3]

    def directions(self, dofs) -> np.ndarray:
        """(n, 3) global unit vectors of (n, 2) DOF labels (point, code)."""
        return np.array([self.direction(int(p), int(c)) for p, c in np.asarray(dofs).reshape(-1, 2)])

    def merged(self, other: TestGeometry) -> TestGeometry:
        return TestGeometry(np.r_[self.point_ids, other.point_ids], np.r_[self.xyz, other.xyz],
                            np.r_[self.axes, other.axes], self.traces + other.traces, self.elements + other.elements,
                            {**self.coordinate_systems, **other.coordinate_systems}, self.notes + other.notes)


def _finite(a, where, what):
    try:
        a = np.asarray(a, float)
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: {what} are not numbers") from None
    if not np.all(np.isfinite(a)):
        raise FileFormatError(f"{where}: {what} hold NaN or infinite values")
    return a


def _orthonormal(R: np.ndarray, where: str, label: int) -> np.ndarray:
    if not np.allclose(R @ R.T, np.eye(3), atol=1e-6) or np.linalg.det(R) < 0:
        raise FileFormatError(f"{where}: coordinate system {label}: the rotation rows are not a right-handed "
                              "orthonormal triad (|R R^T - I| > 1e-6 or det < 0); re-export the coordinate systems")
    return R


def systems_2420(s: dict, where: str, length: float) -> dict:
    labels = s.get("CS_sys_labels")
    mats = s.get("CS_matrices")
    if labels is None or mats is None:
        raise FileFormatError(f"{where}: no coordinate system labels or matrices; re-export the file")
    mats = _finite(mats, where, "transformation matrices")
    labels = np.atleast_1d(np.asarray(labels)).astype(int)
    kinds = np.atleast_1d(np.asarray(s.get("CS_types", np.zeros(len(labels))))).astype(int)
    names = list(s.get("CS_names", [""] * len(labels)))
    if mats.shape != (len(labels), 4, 3) or len(kinds) != len(labels):
        raise FileFormatError(f"{where}: {mats.shape} matrices for {len(labels)} coordinate systems (4x3 each)")
    out = {}
    for k, lab in enumerate(labels):
        R = _orthonormal(mats[k, :3], where, lab)
        out[int(lab)] = CoordinateSystem(int(lab), CS_KINDS.get(int(kinds[k]), f"type {kinds[k]}"), R,
                                         mats[k, 3] / length, str(names[k]).strip() if k < len(names) else "")
    return out


def systems_18(s: dict, where: str, length: float, known: dict) -> dict:
    nums = np.atleast_1d(np.asarray(s.get("cs_num", []))).astype(int)
    n = len(nums)
    try:
        kinds = np.atleast_1d(np.asarray(s["cs_type"])).astype(int)
        refs = np.atleast_1d(np.asarray(s["ref_cs_num"])).astype(int)
        pts = [_finite(s[k], where, k).reshape(-1, 3) for k in ("ref_o", "x_point", "xz_point")]
    except (KeyError, TypeError, ValueError):
        raise FileFormatError(f"{where}: coordinate system records are incomplete; re-export the file") from None
    if len(kinds) != n or len(refs) != n or any(len(p) != n for p in pts):
        raise FileFormatError(f"{where}: the coordinate system records have different lengths (a line is missing)")
    names = list(s.get("cs_name", [""] * n))
    out = dict(known)
    pending = {int(nums[k]): k for k in range(n)}
    while pending:
        done = [lab for lab, k in pending.items() if int(refs[k]) in out or int(refs[k]) == 0]
        if not done:
            raise FileFormatError(f"{where}: coordinate systems {sorted(pending)[:10]} refer to systems that are not "
                                  "defined (or to each other in a circle); re-export the coordinate systems")
        for lab in done:
            k = pending.pop(lab)
            parent = GLOBAL if int(refs[k]) == 0 else out[int(refs[k])]
            if parent.kind != "cartesian":
                raise FileFormatError(f"{where}: coordinate system {lab} is defined in the {parent.kind} system "
                                      f"{parent.label}; only cartesian reference systems are supported")
            o, px, pxz = (parent.to_global(p[k] / length) for p in pts)
            x = px - o
            v = pxz - o
            if np.linalg.norm(x) == 0:
                raise FileFormatError(f"{where}: coordinate system {lab}: the +x point is the origin")
            x = x / np.linalg.norm(x)
            z = v - (v @ x) * x
            if np.linalg.norm(z) <= 1e-9 * max(np.linalg.norm(v), 1e-300):
                raise FileFormatError(f"{where}: coordinate system {lab}: the +xz-plane point is on the x axis")
            z = z / np.linalg.norm(z)
            R = np.array([x, np.cross(z, x), z])
            out[lab] = CoordinateSystem(lab, CS_KINDS.get(int(kinds[k]), f"type {kinds[k]}"), R, o,
                                        str(names[k]).strip() if k < len(names) else "")
    return out


def _system(systems: dict, label: int, where: str, node: int, role: str) -> CoordinateSystem:
    if label == 0:
        return GLOBAL
    cs = systems.get(label)
    if cs is None:
        raise FileFormatError(f"{where}: node {node}: {role} coordinate system {label} is not defined in the file "
                              "(no dataset 18 or 2420 gives it); export the coordinate systems with the geometry")
    if cs.kind != "cartesian":
        raise FileFormatError(f"{where}: node {node}: {role} coordinate system {label} is {cs.kind}; flexgvt reads "
                              "cartesian systems only: export the geometry in cartesian systems")
    return cs


def nodes(s: dict, where: str, length: float, systems: dict, coordinates_global: bool = False) -> TestGeometry:
    """Dataset 15 or 2411: coordinates given in each node's definition system -> global [m] (or, with
    coordinates_global, taken as global: NX writes them so, docs/uff.md), with its displacement axes."""
    ids = _ids(_get(s, "node_nums", where), where)
    cols = [_column(_get(s, c, where), where, f"{c} coordinates", len(ids)) for c in ("x", "y", "z")]
    local = np.column_stack(cols) / length
    if not np.all(np.isfinite(local)):
        raise FileFormatError(f"{where}: NaN or infinite coordinates")
    def_cs = _ids(s.get("def_cs", np.zeros(len(ids))), where, "definition coordinate systems")
    disp_cs = _ids(s.get("disp_cs", np.zeros(len(ids))), where, "displacement coordinate systems")
    if len(def_cs) != len(ids) or len(disp_cs) != len(ids):
        raise FileFormatError(f"{where}: coordinate system columns do not have one value per node")
    xyz = local.copy()
    axes = np.empty((len(ids), 3, 3))
    for k, node in enumerate(ids):
        if def_cs[k] and not coordinates_global:
            xyz[k] = _system(systems, int(def_cs[k]), where, int(node), "definition").to_global(local[k])
        axes[k] = _system(systems, int(disp_cs[k]), where, int(node), "displacement").R
    return TestGeometry(ids, xyz, axes, coordinate_systems=dict(systems))


def traces(s: dict, where: str) -> tuple:
    nodes_ = _ids(s.get("nodes", []), where, "trace line points")
    return ((str(s.get("id", "")).strip() or f"trace {s.get('trace_num', '?')}", nodes_),)


def elements(s: dict, where: str) -> tuple:
    out = []
    for key, items in s.items():
        if not isinstance(key, (int, np.integer)):
            continue
        for e in items if isinstance(items, list) else []:
            try:
                out.append((int(e["element_nums"]), int(e["fe_descriptor"]),
                            tuple(int(v) for v in _ids(e["nodes_nums"], where, "element nodes"))))
            except (KeyError, TypeError, ValueError):
                raise FileFormatError(f"{where}: an element record is incomplete; re-export the elements") from None
    return tuple(out)
