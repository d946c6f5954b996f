"""The cord family: suspension cords from fixed anchors to an attachment on the structure (at a node
with a rigid arm, or along an element between two nodes); kernels in fem.points."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

from ...errors import ModelError
from ...model import Configuration, Model
from ..checks import _REMEDY, COORDINATE_LIMIT, _bad, _ids
from ..points import cord_damping, cord_forces
from .base import Derivative, ElementTerms, zero_blocks
from .mass import PointMasses


@dataclass(frozen=True)
class Cords:
    """The cords of a configuration (storage indices and SI values; k cords)."""

    nodes_a: np.ndarray  # (k,) node a
    nodes_b: np.ndarray  # (k,) node b (node a again for a cord at a node)
    offset: np.ndarray  # (k, 3) rigid arm of the attachment [m]
    anchor: np.ndarray  # (k, 3) fixed anchor point [m]
    stiffness: np.ndarray  # (k,) [N/m]
    damping: np.ndarray  # (k,) [N s/m]
    l0: np.ndarray  # (k,) unstretched length at full load [m]
    w: np.ndarray  # (k,) attachment fraction along a-b
    lgeom: np.ndarray  # (k,) anchor-to-attachment distance of the undeformed structure [m]

    def l0_at(self, lam: float) -> np.ndarray:
        """Unstretched cord lengths along the load ramp: unstrained at lam = 0, nominal at lam = 1."""
        return self.lgeom + lam * (self.l0 - self.lgeom)


def build_cords(model: Model, configuration: Configuration, xyz: np.ndarray) -> Cords:
    """The configuration's suspension cords as arrays, checked (attachment on the structure, anchor
    off it; a cord slack at the start warns)."""
    where = f"configuration '{configuration.name}'"
    cords = list(configuration.suspension)
    a = model.index_of([c.node for c in cords], f"{where}: cord") if cords else np.zeros(0, int)
    b = model.index_of([c.node if c.node_b is None else c.node_b for c in cords],
                       f"{where}: cord node_b") if cords else np.zeros(0, int)
    offset = np.array([c.offset for c in cords], float).reshape(-1, 3)
    anchor = np.array([c.anchor for c in cords], float).reshape(-1, 3)
    k = np.array([c.stiffness for c in cords], float)
    c_ = np.array([c.damping for c in cords], float)
    l0 = np.array([c.unstretched_length for c in cords], float)
    span = np.linalg.norm(xyz[b] - xyz[a], axis=1)
    along = np.array([c.along for c in cords], float)
    off = along > span * (1 + 1e-12)
    if np.any(off):
        i = int(np.flatnonzero(off)[0])
        raise ModelError(f"{where}: cord {i} is attached {along[i]} m along from node {cords[i].node} toward node "
                         f"{cords[i].node_b}, beyond the {span[i]:.6g} m between them: the attachment point "
                         "is off the structure; give 0 <= along <= that distance")
    w = np.where(span > 0, along / np.where(span > 0, span, 1.0), 0.0)
    attach = (1 - w)[:, None] * xyz[a] + w[:, None] * xyz[b] + offset
    lgeom = np.linalg.norm(attach - anchor, axis=1)
    if np.any(lgeom == 0):
        raise ModelError(f"{where}: a cord's anchor coincides with its attachment point; move the anchor")
    slack = np.flatnonzero(l0 >= lgeom)
    if len(slack):
        i = int(slack[0])
        warnings.warn(f"{where}: cord {i} (node {cords[i].node}) is slack at the start: its unstretched length "
                      f"{l0[i]:.4g} m is not shorter than the {lgeom[i]:.4g} m from its anchor "
                      "to the attachment, so it carries nothing until the structure moves away; shorten it "
                      "(size it with suspension.Line.cord) if it should hold the structure", stacklevel=5)
    return Cords(a, b, offset, anchor, k, c_, l0, w, lgeom)


@dataclass(frozen=True, eq=False)
class CordFamily:
    """Cords in one configuration; mass (k,) [kg] of each cord. Output of terms: (tension (k,) [N],
    length (k,) [m]). A heavy cord hangs half its weight on the structure: a third of its mass moves
    with the attachment (point_masses, which System hands to the point-mass family), the remaining
    sixth is an applied load (add_applied)."""

    cords: Cords
    mass: np.ndarray
    segmented: np.ndarray | None = None  # (k,) bool: a distributed cord (families.segments carries it)

    name: ClassVar[str] = "cord"
    structural: ClassVar[bool] = True
    translation_invariant: ClassVar[bool] = False
    value_fields: ClassVar[tuple[str, ...]] = ("cords", "cord_offsets", "cord_along")

    @staticmethod
    def build(model: Model, configuration: Configuration, xyz: np.ndarray) -> "CordFamily":
        cords = build_cords(model, configuration, xyz)
        segmented = np.array([getattr(c, "segments", 0) >= 2 for c in configuration.suspension], bool)
        mass = np.array([c.mass for c in configuration.suspension], float)
        if np.any(segmented):  # the segment family carries their stiffness and mass; the row keeps the rest
            cords = replace(cords, stiffness=np.where(segmented, 0.0, cords.stiffness))
            mass = np.where(segmented, 0.0, mass)
        return CordFamily(cords, mass, segmented)

    @property
    def nodes(self) -> np.ndarray:
        return np.column_stack([self.cords.nodes_a, self.cords.nodes_b]) if len(self.mass) else np.zeros((0, 2), int)

    @property
    def has_damping(self) -> bool:
        return bool(np.any(self.cords.damping > 0))

    def topology(self) -> tuple[np.ndarray, ...]:
        return (self.cords.nodes_a, self.cords.nodes_b)

    def state(self, x: np.ndarray, R: np.ndarray, rows=slice(None)) -> tuple:
        """(x_a, R_a, x_b, R_b) of the cords' two nodes (the same node twice for a cord at a node)."""
        a, b = self.cords.nodes_a[rows], self.cords.nodes_b[rows]
        return x[a], R[a], x[b], R[b]

    def terms(self, x, R, lam, tangent, reference=None) -> ElementTerms:
        c = self.cords
        if not len(c.w):
            return ElementTerms(np.zeros((0, 12)), np.zeros((0, 12, 12)), (np.zeros(0), np.zeros(0)))
        g, K, tension, length = cord_forces(*self.state(x, R), c.offset, c.anchor, c.stiffness, c.l0_at(lam), c.w)
        return ElementTerms(g, K, (tension, length))

    def mass_values(self, x, R) -> np.ndarray:
        return zero_blocks(len(self.mass), 2)

    def damping_values(self, x, R) -> np.ndarray:
        c = self.cords
        if not len(c.w):
            return zero_blocks(0, 2)
        return cord_damping(*self.state(x, R), c.offset, c.anchor, c.damping, c.w)

    def point_masses(self) -> PointMasses:
        """A third of each heavy cord's mass at its attachment (split between its nodes a and b by
        the attachment fraction w), at the attachment's offset."""
        c = self.cords
        nodes, mass, offset = [], [], []
        for k, m in enumerate(self.mass):
            if m <= 0:
                continue
            for node, share in ((c.nodes_a[k], 1 - c.w[k]), (c.nodes_b[k], c.w[k])) if c.w[k] > 0 else \
                    ((c.nodes_a[k], 1.0),):
                nodes.append(node)
                mass.append(share * m / 3)
                offset.append(np.asarray(c.offset[k], float))
        n = len(nodes)
        return PointMasses(np.array(nodes, int), np.array(mass, float), np.array(offset, float).reshape(n, 3),
                           np.zeros((n, 3, 3)))

    def add_applied(self, f: np.ndarray, configuration: Configuration, gravity: np.ndarray) -> None:
        """The sixth of each heavy cord's weight not moving with the attachment."""
        c = self.cords
        for m, a, b, w, off in zip(self.mass, c.nodes_a, c.nodes_b, c.w, c.offset):
            if m > 0:
                F = m * gravity / 6.0
                M = np.cross(np.asarray(off, float), F)
                f[a] += (1 - w) * np.r_[F, M]
                f[b] += w * np.r_[F, M]

    def exploded_terms(self, xs, Rs, lam):
        c = self.cords
        _, K, _, _ = cord_forces(xs[:, 0], Rs[:, 0], xs[:, 1], Rs[:, 1], c.offset, c.anchor, c.stiffness,
                                 c.l0_at(lam), c.w)
        return K, None

    def check_values(self, where: str, node_ids: np.ndarray) -> None:
        c = self.cords
        if not len(c.w):
            return
        bad = (_bad(c.stiffness) | _bad(c.damping) | _bad(c.anchor, COORDINATE_LIMIT) | _bad(c.l0, COORDINATE_LIMIT)
               | _bad(c.offset, COORDINATE_LIMIT))
        if np.any(bad):
            raise ModelError(f"{where}: cord(s) {_ids(np.flatnonzero(bad))} (at node(s) "
                             f"{_ids(node_ids[c.nodes_a[bad]])}) have a stiffness, damping, anchor, "
                             f"length or offset that is not finite or too large: {_REMEDY}")

    def connections(self) -> np.ndarray:
        return self.nodes

    def held_nodes(self) -> np.ndarray:
        return np.r_[self.cords.nodes_a, self.cords.nodes_b]

    def used_nodes(self) -> np.ndarray:
        return np.zeros(0, int)

    def describe(self, nodes: np.ndarray) -> str:
        return ""

    def derivative(self, field, item, x, R, lam, gravity, cache) -> Derivative:
        """cords: (rows, d stiffness (k,)); cord_offsets: (rows, [(offsets (k, 3), weight), ...]) a
        difference rule in the attachment offset; cord_along: (rows, [(fractions (k,), weight), ...])
        the same in the attachment fraction (the line of action is not polynomial in either)."""
        c = self.cords
        rows = np.asarray(item[0], int)
        if self.segmented is not None and np.any(self.segmented[rows]):
            raise ModelError(f"cord(s) {_ids(rows[self.segmented[rows]])} are distributed (segments >= 2): they "
                             f"have no design variables ('{field}'); vary a cord without segments")
        if field == "cords":
            g, K, _, _ = cord_forces(*self.state(x, R, rows), c.offset[rows], c.anchor[rows],
                                     np.asarray(item[1], float), c.l0_at(lam)[rows], c.w[rows])
            return Derivative(rows, g, None, K)
        g = K = 0.0
        for value, weight in item[1]:
            off = np.asarray(value, float) if field == "cord_offsets" else c.offset[rows]
            frac = c.w[rows] if field == "cord_offsets" else np.asarray(value, float)
            gi, Ki, _, _ = cord_forces(*self.state(x, R, rows), off, c.anchor[rows], c.stiffness[rows],
                                       c.l0_at(lam)[rows], frac)
            g, K = g + weight * gi, K + weight * Ki
        return Derivative(rows, g, None, K)
