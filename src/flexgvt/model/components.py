"""Point components: concentrated masses, springs/dampers, suspension cords, rigid links, loads."""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from .spring_table import SpringTable


def as_vector(value, n: int, what: str) -> np.ndarray:
    """A finite float vector of length n (a scalar is broadcast); clear error otherwise."""
    arr = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy() if np.ndim(value) == 0 \
        else np.asarray(value, dtype=float).reshape(-1)
    if arr.shape != (n,):
        raise ModelError(f"{what}: expected {n} values, got {np.shape(value)}")
    if not np.all(np.isfinite(arr)):
        raise ModelError(f"{what}: contains NaN or infinity: {arr}")
    arr.setflags(write=False)
    return arr


def find_items(items, key: str | int, where: str, kind: str) -> list[int]:
    """Positions in ``items`` (masses or springs) named ``key`` (a name or fnmatch pattern) or with id
    ``key`` (an integer), in list order; ModelError naming ``where`` when none matches."""
    if isinstance(key, str):
        found = [k for k, m in enumerate(items) if m.name and fnmatch.fnmatchcase(m.name, key)]
        known = sorted({m.name for m in items if m.name})
        what = f"no {kind} named '{key}'"
    else:
        found = [k for k, m in enumerate(items) if m.id is not None and m.id == int(key)]
        known = sorted(m.id for m in items if m.id is not None)
        what = f"no {kind} with id {key}"
    if not found:
        raise ModelError(f"{where}: {what}; {kind} {'names' if isinstance(key, str) else 'ids'}: "
                         f"{known[:20] or '(none given)'}{' ...' if len(known) > 20 else ''}")
    return found


@dataclass(frozen=True)
class ConcentratedMass:
    """Mass [kg] whose centre sits at ``offset`` [m] (global axes, undeformed) from its node.

    inertia: 3x3 inertia tensor about the mass's own centre [kg m^2], global axes, undeformed.
    The offset and inertia rotate with the node. name: optional, how design variables and tables
    address it (flexgvt.updating.mass); id: optional entity id (a Nastran deck's CONM2 EID).
    """

    node: int
    mass: float
    offset: np.ndarray
    inertia: np.ndarray
    name: str = ""
    id: int | None = None


@dataclass(frozen=True)
class Spring:
    """Linear 6-component spring and viscous damper between node_a and node_b (None: ground).

    stiffness [N/m x3, N m/rad x3] and damping [N s/m x3, N m s/rad x3] act on the relative
    translations and rotation vector of node_b with respect to node_a, in the axes of ``frame``
    (3x3, columns are the spring axes in global coordinates; identity by default).
    The axes stay fixed in space: exact for grounded springs and for joint springs between
    coincident nodes (the usual use); between distant nodes a large rigid rotation of both
    would load the spring, so model such a connection with a beam instead. name: optional, how
    design variables address it (flexgvt.updating.spring); id: optional entity id (a Nastran
    deck's CELAS/CBUSH EID).

    tables: per component (6, None for linear) a force-deflection table (model.SpringTable): that
    component's force is (stiffness[i] / table.nominal_stiffness) * table(deflection), its tangent
    the scaled slope. So stiffness[i] of a table component is a scale of the table in stiffness
    units: Spring.make sets it to the table's nominal stiffness (scale 1) when given as 0, and
    updating's spring variables scale the table through it. Modes about the undeformed state see
    the slope at zero deflection; after a static solve, the slope at the spring's deflection.
    """

    node_a: int
    node_b: int | None
    stiffness: np.ndarray
    damping: np.ndarray
    frame: np.ndarray = field(default_factory=lambda: np.eye(3))
    name: str = ""
    id: int | None = None
    tables: tuple = (None,) * 6

    @property
    def nonlinear(self) -> bool:
        """True when a component follows a force-deflection table."""
        return any(t is not None for t in self.tables)

    @property
    def table_scale(self) -> np.ndarray:
        """(6,) the factor on each table's force (stiffness / nominal stiffness; 0 without a table)."""
        return np.array([0.0 if t is None else k / t.nominal_stiffness for k, t in zip(self.stiffness, self.tables)])

    @staticmethod
    def make(node_a: int, node_b: int | None = None, stiffness: ArrayLike = 0.0, damping: ArrayLike = 0.0,
             frame: ArrayLike | None = None, name: str = "", id: int | None = None,
             tables=None) -> "Spring":
        k = as_vector(stiffness, 6, f"spring at node {node_a}: stiffness")
        c = as_vector(damping, 6, f"spring at node {node_a}: damping")
        if np.any(k < 0) or np.any(c < 0):
            raise ModelError(f"spring at node {node_a}: stiffness and damping must be >= 0, got {k}, {c}")
        if frame is None:
            frame = np.eye(3)
        frame = np.asarray(frame, dtype=float)
        if frame.shape != (3, 3) or not np.allclose(frame.T @ frame, np.eye(3), atol=1e-9):
            raise ModelError(f"spring at node {node_a}: frame must be a 3x3 orthonormal matrix")
        tabs = _tables(tables, f"spring at node {node_a}")
        if any(t is not None for t in tabs):
            k = np.array([t.nominal_stiffness if t is not None and v == 0 else v for v, t in zip(k, tabs)])
            k.setflags(write=False)
        return Spring(int(node_a), None if node_b is None else int(node_b), k, c, frame, str(name),
                      None if id is None else int(id), tabs)


def _tables(tables, where: str) -> tuple:
    """Six entries (SpringTable or None) from None, a 6-sequence or {component 1..6: table}."""
    if tables is None:
        return (None,) * 6
    if isinstance(tables, dict):
        bad = [c for c in tables if not (isinstance(c, (int, np.integer)) and 1 <= c <= 6)]
        if bad:
            raise ModelError(f"{where}: table components must be 1..6 (x, y, z, rx, ry, rz), got {bad}")
        tables = [tables.get(c) for c in range(1, 7)]
    tables = tuple(tables)
    if len(tables) != 6 or any(t is not None and not isinstance(t, SpringTable) for t in tables):
        raise ModelError(f"{where}: tables must be six entries, each a SpringTable (SpringTable.make(x, f)) or None, "
                         "or a dict {component 1..6: SpringTable}")
    return tables


@dataclass(frozen=True)
class Cord:
    """Suspension cord from a fixed ``anchor`` point [m] to a structure node.

    stiffness [N/m] and damping [N s/m] act along the cord; ``unstretched_length`` [m] sets the
    tension T = stiffness * (length - unstretched_length) (a slack cord carries nothing).
    ``offset`` [m] is the attachment point relative to the node (global axes, undeformed), so the
    line of action follows the deformed attachment. ``node_b`` and ``along`` [m] attach the cord
    between two nodes (along an element): at ``along`` from ``node`` toward ``node_b``, the
    attachment moving with the two nodes' translations interpolated linearly (plus the arm
    ``offset`` turned with each node); ``along`` is continuous, so it can be a design variable.
    A taut cord of length L adds the pendulum stiffness T/L sideways. ``mass`` [kg]: the cord's own
    mass (a long bungee's): half its weight hangs on the structure (the tension at the attachment
    is stiffness * stretch - m g / 2) and a third of it moves with the attachment (the Rayleigh
    mass of a uniform spring). ``segments`` >= 2 (with a mass): the cord distributed instead, as
    that many tension members joined at interior points carrying m / segments each, so its own
    surge and string modes and their coupling with the structure come out of the modal solve
    (fem.families.segments); 0 (default) or 1: the single cord with the Rayleigh mass above.
    """

    node: int
    anchor: tuple[float, float, float]
    stiffness: float
    unstretched_length: float
    damping: float = 0.0
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    node_b: int | None = None
    along: float = 0.0
    mass: float = 0.0
    segments: int = 0

    def __post_init__(self) -> None:
        if not np.all(np.isfinite(np.r_[self.anchor, self.offset, self.stiffness, self.damping,
                                        self.unstretched_length, self.along, self.mass])):
            raise ModelError(f"cord at node {self.node}: NaN or infinity in its data")
        if self.mass < 0:
            raise ModelError(f"cord at node {self.node}: mass={self.mass} must be >= 0")
        if isinstance(self.segments, bool) or not isinstance(self.segments, (int, np.integer)) or self.segments < 0:
            raise ModelError(f"cord at node {self.node}: segments={self.segments!r} must be a whole number >= 0 "
                             "(0 or 1: one cord; 2 or more: the cord distributed over that many members)")
        if self.segments >= 2 and self.mass <= 0:
            raise ModelError(f"cord at node {self.node}: segments={self.segments} needs the cord's mass (mass > 0): "
                             "its interior points would carry none")
        if self.node_b is None and self.along != 0.0:
            raise ModelError(f"cord at node {self.node}: along={self.along} needs node_b, the element's other node")
        if self.node_b is not None and (self.node_b == self.node or self.along < 0):
            raise ModelError(f"cord at node {self.node}: node_b must be another node and along >= 0 "
                             f"(got node_b={self.node_b}, along={self.along})")
        if self.stiffness <= 0 or self.damping < 0 or self.unstretched_length <= 0:
            raise ModelError(f"cord at node {self.node}: stiffness and unstretched_length must be > 0 and "
                             f"damping >= 0 (got {self.stiffness}, {self.unstretched_length}, {self.damping})")


@dataclass(frozen=True)
class RigidLink:
    """The ``components`` of the ``dependents`` follow ``independent`` as a rigid body (RBE2).

    components: '123456' (all, default) or any set of translations (basic axes) with the three
    rotations all or none, e.g. '123' (a ball joint: the dependent's rotations stay its own). The
    constraint is exact at any rotation: x_d[c] = (x_i + R_i (X_d - X_i))[c], R_d = R_i.
    """

    independent: int
    dependents: tuple[int, ...]
    components: str = "123456"


@dataclass(frozen=True)
class InterpolationLink:
    """The ``reference`` node moves with the weighted best-fit rigid motion of ``nodes`` (Nastran RBE3).

    weights: one per node (translations of the nodes enter, weighted). The fit is exact at any
    rotation: x_ref = c + Q (X_ref - C), R_ref = Q, with c, C the weighted centroids of the
    current and undeformed node positions and Q the rotation of the polar decomposition of
    sum w_i (x_i - c)(X_i - C)^T; for small motions this is Nastran's RBE3 with C = 123.
    components: the reference's tied DOFs, '123456' (default) or '123' (its rotations stay its
    own). The nodes add no stiffness: loads and masses at the reference are distributed to them.
    """

    reference: int
    nodes: tuple[int, ...]
    weights: np.ndarray
    components: str = "123456"


@dataclass(frozen=True)
class LinearConstraint:
    """sum_j a_j u_j = 0 (Nastran MPC): the first term's DOF is the dependent one.
    terms: ((node, component 1-6, coefficient), ...), components in basic axes. With translations
    only, it holds exactly on the total translations u = x - X at any displacement. A finite
    rotation has no linear total measure: a constraint with rotation terms holds on the
    increments (spins), as Nastran's MPC does in the small-rotation sense; use a rigid or
    interpolation link where rotations are large."""

    terms: tuple[tuple[int, int, float], ...]


@dataclass(frozen=True)
class NodalLoad:
    """Force [N] and moment [N m] at a node, fixed in direction (global axes), scaled by the load factor."""

    node: int
    force: tuple[float, float, float] = (0.0, 0.0, 0.0)
    moment: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not np.all(np.isfinite(np.r_[self.force, self.moment])):
            raise ModelError(f"load at node {self.node}: NaN or infinity in force/moment")


@dataclass(frozen=True)
class DistributedLoad:
    """Load per unit length [N/m] on beam elements, fixed in direction (global axes), not a follower."""

    elements: tuple[int, ...]
    per_length: tuple[float, float, float]

    def __post_init__(self) -> None:
        if not np.all(np.isfinite(self.per_length)):
            raise ModelError("distributed load: NaN or infinity in per_length")
