"""Sensors: the measured channels as linear maps from an FE shape (6 DOF per node) to a reading.

A sensor is rigidly attached to an FE node at an arm (its offset) and reads the displacement of
its own point along its direction: d . (u + theta x r). On a deformed structure the sensor turns
with the node it is glued to (follow=True): r = R_node r0 and d = R_node d0.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable, Mapping, Sequence

import numpy as np
import scipy.sparse as sp

from ..errors import ModelError

AXES = "XYZ"


@dataclass(frozen=True)
class Sensor:
    """One channel: node (FE node id), direction (3,) unit vector and offset (3,) [m] in the
    undeformed global axes, name (e.g. '12+Z': UFF point 12, direction +Z)."""

    node: int
    direction: np.ndarray
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    name: str = ""

    def __post_init__(self) -> None:
        d = np.asarray(self.direction, float).reshape(-1)
        r = np.asarray(self.offset, float).reshape(-1)
        if d.shape != (3,) or r.shape != (3,) or not np.all(np.isfinite(np.r_[d, r])):
            raise ModelError(f"sensor at node {self.node}: direction and offset must be 3 finite values each")
        norm = np.linalg.norm(d)
        if norm == 0:
            raise ModelError(f"sensor at node {self.node}: the direction is zero")
        object.__setattr__(self, "direction", d / norm)
        object.__setattr__(self, "offset", r)
        object.__setattr__(self, "node", int(self.node))


class Sensors:
    """An ordered set of sensors: the rows of every shape reduced to them."""

    def __init__(self, sensors: Sequence[Sensor]):
        self._items = tuple(sensors)
        if not self._items:
            raise ModelError("Sensors: give at least one sensor")
        self.nodes = np.array([s.node for s in self._items], int)
        self.directions = np.array([s.direction for s in self._items])
        self.offsets = np.array([s.offset for s in self._items])

    def __len__(self) -> int:
        return len(self._items)

    def __iter__(self):
        return iter(self._items)

    def __getitem__(self, k):
        return self._items[k]

    @property
    def names(self) -> list[str]:
        return [s.name or f"{s.node}:{np.round(s.direction, 3).tolist()}" for s in self._items]

    @property
    def dofs(self) -> np.ndarray:
        """(n_sensors, 2) DOF labels (FE node, direction code +-1..3) of the sensors; 0 for a sensor
        along no axis (it then aligns by position only)."""
        d = np.round(self.directions, 12)
        axis = np.argmax(np.abs(d), axis=1)
        along = np.isclose(np.abs(d[np.arange(len(d)), axis]), 1.0)
        code = np.where(along, np.sign(d[np.arange(len(d)), axis]) * (axis + 1), 0).astype(int)
        return np.column_stack([self.nodes, code])

    @classmethod
    def uniaxial(cls, nodes: Iterable[int], directions, offsets=None) -> "Sensors":
        """One sensor per node along ``directions`` ((n, 3) or one (3,)), at ``offsets`` ((n, 3) or None)."""
        nodes = np.atleast_1d(np.asarray(list(nodes), int))
        d = np.broadcast_to(np.asarray(directions, float), (len(nodes), 3))
        r = np.zeros((len(nodes), 3)) if offsets is None else np.broadcast_to(np.asarray(offsets, float),
                                                                              (len(nodes), 3))
        return cls([Sensor(int(n), d[k], r[k]) for k, n in enumerate(nodes)])

    @classmethod
    def triaxial(cls, nodes: Iterable[int], offsets=None) -> "Sensors":
        """Three sensors (X, Y, Z) per node, at the node's offset ((n, 3) or None)."""
        nodes = np.atleast_1d(np.asarray(list(nodes), int))
        r = np.zeros((len(nodes), 3)) if offsets is None else np.broadcast_to(np.asarray(offsets, float),
                                                                              (len(nodes), 3))
        return cls([Sensor(int(n), np.eye(3)[a], r[k], f"{n}+{AXES[a]}") for k, n in enumerate(nodes)
                    for a in range(3)])

    @classmethod
    def from_outputs(cls, outputs, node_map: Mapping[int, int] | None = None,
                     offsets: Mapping[int, Sequence[float]] | None = None) -> "Sensors":
        """From the (n, 2) (point id, direction code) channels of UFF data (flexgvt.io.read_uff, a
        ModalSet's outputs): codes +-1, +-2, +-3 are +-X, +-Y, +-Z. node_map: {test point: FE node}
        (default: the same ids); offsets: {test point: (3,) arm from the node [m]}."""
        outputs = np.asarray(outputs)
        if outputs.ndim != 2 or outputs.shape[1] != 2 or len(outputs) == 0:
            raise ModelError(f"Sensors.from_outputs: expected (n, 2) (point, direction) channels, got {outputs.shape}")
        items = []
        for k, (pt, code) in enumerate(outputs.astype(int)):
            if abs(code) not in (1, 2, 3):
                raise ModelError(f"channel {k} (point {pt}, direction {code}) is not a translation (+-1..3); "
                                 "rotational channels cannot be correlated with the FE translations: drop them")
            node = int(node_map[pt]) if node_map is not None and pt in node_map else int(pt)
            if node_map is not None and pt not in node_map:
                raise ModelError(f"channel {k}: test point {pt} is not in node_map; map every measured point to an "
                                 "FE node")
            arm = np.zeros(3) if offsets is None or pt not in offsets else np.asarray(offsets[pt], float)
            items.append(Sensor(node, np.sign(code) * np.eye(3)[abs(code) - 1], arm,
                                f"{pt}{'+' if code > 0 else '-'}{AXES[abs(code) - 1]}"))
        return cls(items)

    def matrix(self, node_ids: np.ndarray, state=None, follow: bool = True) -> sp.csr_matrix:
        """(n_sensors, 6 len(node_ids)) map from a node-major 6-DOF shape (node order node_ids) to the
        readings: d^T (u + theta x r) = d^T u + (r x d)^T theta. With a State and follow=True the
        arm and direction turn with the node's rotation."""
        node_ids = np.asarray(node_ids, int)
        rows = self.rows(node_ids)
        d, r = self._turned(rows, state, follow)
        vals = np.concatenate([d, np.cross(r, d)], axis=1)  # (n, 6)
        cols = 6 * rows[:, None] + np.arange(6)[None, :]
        n = len(self)
        return sp.csr_matrix((vals.ravel(), (np.repeat(np.arange(n), 6), cols.ravel())), shape=(n, 6 * len(node_ids)))

    def rows(self, node_ids: np.ndarray) -> np.ndarray:
        """(n_sensors,) each sensor's node position in ``node_ids``."""
        node_ids = np.asarray(node_ids, int)
        order = np.argsort(node_ids)
        pos = np.searchsorted(node_ids, self.nodes, sorter=order)
        pos = np.clip(pos, 0, len(node_ids) - 1)
        rows = order[pos]
        missing = node_ids[rows] != self.nodes
        if np.any(missing):
            bad = sorted(set(self.nodes[missing].tolist()))
            raise ModelError(f"sensors on node(s) {bad[:10]} that the model does not have; map the test points "
                             "to FE nodes (Sensors.from_outputs(..., node_map=...))")
        return rows

    def _turned(self, rows: np.ndarray, state, follow: bool) -> tuple[np.ndarray, np.ndarray]:
        """Directions and arms (n_sensors, 3), turned with their nodes' rotations when following a State."""
        d, r = self.directions, self.offsets
        if state is not None and follow:
            Rn = state.rotations[rows]
            d = np.einsum("nij,nj->ni", Rn, d)
            r = np.einsum("nij,nj->ni", Rn, r)
        return d, r

    def turning(self, node_ids: np.ndarray, state, shape: np.ndarray) -> np.ndarray:
        """(n_sensors, 3) derivative of the readings of the node-major 6-DOF ``shape`` (6 len(node_ids),)
        with respect to a spatial spin of each sensor's node, when the sensors turn with the nodes
        of ``state``: a spin dtheta turns d and c = r x d by dtheta x, so the reading
        d.u + c.theta changes by dtheta . (d x u + c x theta)."""
        rows = self.rows(node_ids)
        d, r = self._turned(rows, state, True)
        s = np.asarray(shape).reshape(-1, 6)[rows]
        return np.cross(d, s[:, :3]) + np.cross(np.cross(r, d), s[:, 3:])


@dataclass(frozen=True)
class PointMap:
    """Test points mapped to FE nodes: point_ids (n,), node_ids (n,) the nearest node, distances (n,)
    [m], tolerance [m] the largest accepted distance, far (point ids beyond it), shared {node: [points]}
    (nodes that two or more points map to), node_xyz (n, 3) the mapped nodes' positions [m]."""

    point_ids: np.ndarray
    node_ids: np.ndarray
    distances: np.ndarray
    tolerance: float
    far: tuple = ()
    shared: dict = field(default_factory=dict)
    node_xyz: np.ndarray | None = None  # (n, 3) the mapped nodes' positions [m]

    @property
    def node_map(self) -> dict:
        """{test point: FE node} (the node_map of Sensors.from_outputs)."""
        return {int(p): int(n) for p, n in zip(self.point_ids, self.node_ids)}

    def table(self) -> list[dict]:
        """One row per point: point, node, distance_m, status ('ok', 'far', 'shared')."""
        rows = []
        for p, n, d in zip(self.point_ids, self.node_ids, self.distances):
            status = "far" if int(p) in self.far else "shared" if int(n) in self.shared else "ok"
            rows.append({"point": int(p), "node": int(n), "distance_m": float(d), "status": status})
        return rows


def map_points(point_ids, points_xyz, node_ids, nodes_xyz, tolerance: float = 0.05,
               on_far: str = "error", on_shared: str = "warn") -> PointMap:
    """Map each test point (n, 3) [m, global] to the nearest FE node (m, 3) [m] (give the undeformed
    positions of the configuration the test was made in). tolerance: the largest distance accepted, as a
    fraction of the model's size (the diagonal of its nodes' bounding box). on_far / on_shared: 'error'
    (ModelError), 'warn' (FlexGVTWarning) or 'ignore' for points farther than the tolerance and for two
    points mapped to one node. Check the unit systems first: test geometry in mm against a model in m is
    the usual cause of far points."""
    import warnings

    from ..errors import FlexGVTWarning

    pts = np.asarray(points_xyz, float).reshape(-1, 3)
    nodes = np.asarray(nodes_xyz, float).reshape(-1, 3)
    pids = np.asarray(point_ids).astype(int).reshape(-1)
    nids = np.asarray(node_ids).astype(int).reshape(-1)
    if len(pids) != len(pts) or len(nids) != len(nodes) or not len(pts) or not len(nodes):
        raise ModelError(f"map_points: {len(pids)} ids for {len(pts)} test points and {len(nids)} ids for "
                         f"{len(nodes)} nodes; give one id per position (and at least one of each)")
    if not (np.all(np.isfinite(pts)) and np.all(np.isfinite(nodes))):
        raise ModelError("map_points: NaN or infinite coordinates")
    for name, v in (("on_far", on_far), ("on_shared", on_shared)):
        if v not in ("error", "warn", "ignore"):
            raise ModelError(f"map_points: {name}={v!r} must be 'error', 'warn' or 'ignore'")
    size = float(np.linalg.norm(nodes.max(axis=0) - nodes.min(axis=0))) or 1.0
    tol = float(tolerance) * size
    d2 = ((pts[:, None, :] - nodes[None, :, :]) ** 2).sum(axis=2)
    nearest = np.argmin(d2, axis=1)
    dist = np.sqrt(d2[np.arange(len(pts)), nearest])
    mapped = nids[nearest]
    far = tuple(int(p) for p, d in zip(pids, dist) if d > tol)
    shared = {}
    for n in np.unique(mapped):
        hit = pids[mapped == n]
        if len(hit) > 1:
            shared[int(n)] = [int(p) for p in hit]
    result = PointMap(pids, mapped, dist, tol, far, shared, nodes[nearest])

    def act(kind, message):
        if kind == "error":
            raise ModelError(message)
        if kind == "warn":
            warnings.warn(message, FlexGVTWarning, stacklevel=3)

    if far:
        worst = ", ".join(f"point {p} -> node {n} at {d:.4g} m" for p, n, d in zip(pids, mapped, dist) if d > tol)
        act(on_far, f"{len(far)} test point(s) farther than {tol:.4g} m ({tolerance:g} of the model's size "
                    f"{size:.4g} m) from any FE node: {worst[:400]}; check the test geometry's units and axes "
                    "against the model's, or raise the tolerance")
    if shared:
        act(on_shared, "test points mapped to one FE node: " + "; ".join(
            f"node {n}: points {p}" for n, p in list(shared.items())[:10]) + "; refine the mesh near them, "
            "give offsets (Sensors arms) or drop duplicate points")
    return result


def sensors_from_test(outputs, geometry, point_map: PointMap, offsets: bool = True) -> Sensors:
    """Sensors for measured channels (n, 2) (point, UFF direction code in the point's displacement
    system): each on its mapped FE node, along the DOF's global direction (geometry.direction: a DOF at
    an angle reads the projection of the node's motion on it), with the point's offset from the node
    as the arm (offsets=True) so rotations are seen as well. geometry: io.uff TestGeometry (or any
    object with point_ids, xyz and direction(point, code))."""
    outputs = np.asarray(outputs).astype(int).reshape(-1, 2)
    node_of = point_map.node_map
    items = []
    for k, (pt, code) in enumerate(outputs):
        if abs(code) not in (1, 2, 3):
            raise ModelError(f"channel {k} (point {pt}, direction {code}) is not a translation (+-1..3); "
                             "rotational channels cannot be correlated with the FE translations: drop them")
        if pt not in node_of:
            raise ModelError(f"channel {k}: test point {pt} is not in the point map; map every measured point")
        direction = np.asarray(geometry.direction(int(pt), int(code)), float)
        arm = np.zeros(3)
        if offsets:
            row = int(np.flatnonzero(point_map.point_ids == pt)[0])
            arm = np.asarray(geometry.xyz[geometry.index(int(pt))], float) - point_map.node_xyz[row]
        items.append(Sensor(node_of[pt], direction, arm, f"{pt}{'+' if code > 0 else '-'}{AXES[abs(code) - 1]}"))
    return Sensors(items)



def map_test_geometry(geometry, model, tolerance: float = 0.05, deformed=None, **kwargs) -> PointMap:
    """map_points for a test geometry (io.uff TestGeometry: point_ids, xyz global [m]) onto a model's
    undeformed node positions (model.node_ids, model.xyz: the same for every configuration), or onto
    a deformed equilibrium (``deformed``: a fem State, its node_ids and positions) when the test points
    were measured on the loaded structure. kwargs: on_far, on_shared."""
    if deformed is not None:
        return map_points(geometry.point_ids, geometry.xyz, deformed.node_ids, deformed.positions, tolerance,
                          **kwargs)
    return map_points(geometry.point_ids, geometry.xyz, model.node_ids, model.xyz, tolerance, **kwargs)
