"""The distributed-cord family: a heavy cord given ``segments=N`` (fg.Cord) hangs from its anchor to
its attachment as N tension members joined at N - 1 interior points of the cord (kernel
fem.points.member_forces). Each member carries the static tension: axially N k (k the whole cord's
rate EA / L), sideways the string's geometric stiffness T / l_segment; the cord's mass is lumped at
the points (m / N each, m / 2N at the attachment, m / 2N at the anchor, which holds it). So the
cord's own surge and string modes, and their coupling with the structure's, come out of the same
pre-stressed modal solve.

The interior points are nodes of the configuration only: System appends them after the model's
nodes (ids above the model's largest), with their rotations held (a point of a cord has none).
The cord family keeps the cord's row (its damping, its slack check and its place among the
configuration's cords) with no stiffness and no mass; this family reports the cord's tension at
the attachment and its length along the points in the cord family's outputs (Evaluation).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...errors import ModelError
from ...model import Configuration
from ..checks import _REMEDY, _bad, _ids
from ..points import member_forces
from .base import Derivative, ElementTerms, zero_blocks
from .cord import Cords
from .mass import PointMasses


@dataclass(frozen=True)
class SegmentOutput:
    """What the members give at a state: tension (s,) [N] and length (s,) [m] of each member; rows
    (c,) the distributed cords' rows among the configuration's cords, their tension at the
    attachment (c,) [N] and their length along the points (c,) [m]."""

    tension: np.ndarray
    length: np.ndarray
    rows: np.ndarray
    attachment_tension: np.ndarray
    total_length: np.ndarray


@dataclass(frozen=True, eq=False)
class CordSegmentFamily:
    """Members (s of them) of the configuration's distributed cords. nodes (s, 3): end P on nodes a,
    b at fraction w with the rigid arm offset (an interior point: a = b, w = 0, no arm), end Q at node
    c (s = 1) or at the fixed anchor (s = 0, c = a as a placeholder). points: storage indices of the
    interior points (their rotations are held); point_xyz: their undeformed positions, evenly
    along the straight line from anchor to attachment."""

    nodes_abc: np.ndarray  # (s, 3)
    w: np.ndarray  # (s,)
    offset: np.ndarray  # (s, 3) [m]
    anchor: np.ndarray  # (s, 3) [m]
    moving: np.ndarray  # (s,) 1.0: end Q is node c; 0.0: the fixed anchor
    stiffness: np.ndarray  # (s,) N k [N/m]
    l0: np.ndarray  # (s,) unstretched member length at full load [m]
    lgeom: np.ndarray  # (s,) undeformed member length [m]
    cord: np.ndarray  # (s,) position of the member's cord in `rows`
    last: np.ndarray  # (c,) each cord's member at the attachment
    rows: np.ndarray  # (c,) the cords' rows among the configuration's cords
    points: np.ndarray  # (p,) storage indices of the interior points
    point_xyz: np.ndarray  # (p, 3) [m]
    point_cord: np.ndarray  # (p,) position of the point's cord in `rows`
    masses: PointMasses  # at the points and the attachments

    name: ClassVar[str] = "cord_segments"
    structural: ClassVar[bool] = True
    translation_invariant: ClassVar[bool] = False
    value_fields: ClassVar[tuple[str, ...]] = ()
    has_damping: ClassVar[bool] = False

    @staticmethod
    def build(configuration: Configuration, cords: Cords, xyz: np.ndarray) -> "CordSegmentFamily":
        """The members and interior points of ``configuration``'s cords with segments >= 2; cords:
        the cord family's arrays (attachments, anchors, rates, lengths); xyz: the model's undeformed
        node positions (the points are numbered after them)."""
        where = f"configuration '{configuration.name}'"
        cols = {k: [] for k in ("abc", "w", "off", "anchor", "moving", "k", "l0", "lgeom", "cord")}
        rows, last, pts, pcord, mnodes, mmass, moff = [], [], [], [], [], [], []
        n = len(xyz)
        for row, c in enumerate(configuration.suspension):
            N = int(getattr(c, "segments", 0))
            if N < 2:
                continue
            if c.mass <= 0:
                raise ModelError(f"{where}: cord {row} (node {c.node}) has segments={N} but no mass: its interior "
                                 "points would carry no mass; give the cord's mass (mass=...) or segments=0")
            j = len(rows)
            rows.append(row)
            a, b, w, off = cords.nodes_a[row], cords.nodes_b[row], cords.w[row], cords.offset[row]
            P0 = (1 - w) * xyz[a] + w * xyz[b] + off
            A = np.asarray(cords.anchor[row], float)
            ids = n + len(pts) + np.arange(N - 1)
            pts.extend(A + np.outer(np.arange(1, N) / N, P0 - A))
            pcord.extend([j] * (N - 1))
            # From the anchor down: anchor -> point 1, point i -> i + 1, point N-1 -> attachment.
            ends_p = [(i, i, 0.0, np.zeros(3)) for i in ids] + [(a, b, w, off)]
            ends_q = [None] + list(ids)
            for (pa, pb, pw, po), q in zip(ends_p, ends_q):
                cols["abc"].append((pa, pb, pa if q is None else q))
                cols["w"].append(pw)
                cols["off"].append(po)
                cols["anchor"].append(A if q is None else np.zeros(3))
                cols["moving"].append(0.0 if q is None else 1.0)
                cols["k"].append(N * c.stiffness)
                cols["l0"].append(c.unstretched_length / N)
                cols["lgeom"].append(cords.lgeom[row] / N)
                cols["cord"].append(j)
            last.append(len(cols["w"]) - 1)
            m = c.mass / N
            mnodes.extend(ids)
            mmass.extend([m] * (N - 1))
            moff.extend([np.zeros(3)] * (N - 1))
            for node, share in ((a, 1 - w), (b, w)) if w > 0 else ((a, 1.0),):
                mnodes.append(node)
                mmass.append(share * m / 2)
                moff.append(np.asarray(off, float))
        k = len(mnodes)
        masses = PointMasses(np.array(mnodes, int), np.array(mmass, float), np.array(moff, float).reshape(k, 3),
                             np.zeros((k, 3, 3)))
        return CordSegmentFamily(np.array(cols["abc"], int).reshape(-1, 3), np.array(cols["w"], float),
                                 np.array(cols["off"], float).reshape(-1, 3),
                                 np.array(cols["anchor"], float).reshape(-1, 3), np.array(cols["moving"], float),
                                 np.array(cols["k"], float), np.array(cols["l0"], float),
                                 np.array(cols["lgeom"], float), np.array(cols["cord"], int), np.array(last, int),
                                 np.array(rows, int), n + np.arange(len(pts)), np.array(pts, float).reshape(-1, 3),
                                 np.array(pcord, int), masses)

    def l0_at(self, lam: float) -> np.ndarray:
        """Unstretched member lengths along the load ramp (as the cord family's)."""
        return self.lgeom + lam * (self.l0 - self.lgeom)

    @property
    def nodes(self) -> np.ndarray:
        return self.nodes_abc

    def topology(self) -> tuple[np.ndarray, ...]:
        return (self.nodes_abc, self.points)

    def _forces(self, x, R, lam, rows=slice(None), xs=None, Rs=None):
        a, b, c = self.nodes_abc[rows].T
        if xs is None:
            xs = np.stack([x[a], x[b], x[c]], axis=1)
            Rs = np.stack([R[a], R[b]], axis=1)
        return member_forces(xs[:, 0], Rs[:, 0], xs[:, 1], Rs[:, 1], xs[:, 2], self.offset[rows], self.anchor[rows],
                             self.moving[rows], self.stiffness[rows], self.l0_at(lam)[rows], self.w[rows])

    def terms(self, x, R, lam, tangent, reference=None) -> ElementTerms:
        if not len(self.w):
            return ElementTerms(np.zeros((0, 18)), np.zeros((0, 18, 18)), None)
        g, K, T, length = self._forces(x, R, lam)
        total = np.bincount(self.cord, weights=length, minlength=len(self.rows))
        return ElementTerms(g, K, SegmentOutput(T, length, self.rows, T[self.last], total))

    def mass_values(self, x, R) -> np.ndarray:
        return zero_blocks(len(self.w), 3)

    def damping_values(self, x, R) -> np.ndarray:
        return zero_blocks(len(self.w), 3)

    def point_masses(self) -> PointMasses:
        """The cords' lumped masses (System hands them to the point-mass family)."""
        return self.masses

    def point_nodes(self) -> np.ndarray:
        """The interior points: nodes with translations only (System holds their rotations)."""
        return self.points

    def add_applied(self, f: np.ndarray, configuration: Configuration, gravity: np.ndarray) -> None:
        return None  # the points' weight comes with their masses

    def exploded_terms(self, xs, Rs, lam):
        _, K, _, _ = self._forces(None, None, lam, xs=xs, Rs=Rs)
        return K, None

    def derivative(self, field, item, x, R, lam, gravity, cache) -> Derivative:
        raise ModelError(f"a distributed cord (segments >= 2) has no design variables (asked for '{field}'); "
                         "vary a cord without segments, or the structure")

    def check_values(self, where: str, node_ids: np.ndarray) -> None:
        if not len(self.w):
            return
        bad = _bad(self.stiffness) | _bad(self.l0) | _bad(self.anchor)
        if np.any(bad):
            raise ModelError(f"{where}: distributed cord(s) {_ids(self.rows[self.cord[bad]])} have a stiffness, "
                             f"length or anchor that is not finite or too large: {_REMEDY}")

    def connections(self) -> np.ndarray:
        m = self.moving > 0
        abc = self.nodes_abc
        return np.r_[abc[m][:, [0, 2]], abc[m][:, [1, 2]], abc[:, [0, 1]]]

    def held_nodes(self) -> np.ndarray:
        return self.nodes_abc[self.moving == 0, 0]

    def used_nodes(self) -> np.ndarray:
        return self.points

    def describe(self, nodes: np.ndarray) -> str:
        return "a distributed cord" if np.any(np.isin(self.nodes_abc, nodes)) else ""

    def mode_kinds(self, shapes: np.ndarray, x: np.ndarray) -> list[str | None]:
        """Per mode (shapes (n_modes, n_nodes, 6), mass-normalised; x the state's positions): 'bungee
        surge' or 'bungee string' when more than half the mode's kinetic energy is in the cords'
        interior points (surge: mostly along the cord's line, string: across it), else None."""
        if not len(self.points):
            return [None] * len(shapes)
        u = np.asarray(shapes, float)[:, self.points, :3]
        m = self.masses.mass[:len(self.points)]
        a_cord = self.anchor[self.moving == 0]  # one anchor member per cord, in cord order
        ends = np.array([x[self.nodes_abc[i, 0]] for i in self.last])  # near enough the attachment's line
        axis = ends - a_cord
        axis /= np.linalg.norm(axis, axis=1, keepdims=True)
        e = axis[self.point_cord]
        along = np.einsum("mpi,pi->mp", u, e)
        energy = np.einsum("p,mpi,mpi->m", m, u, u)
        axial = (m[None, :] * along ** 2).sum(axis=1)
        out = []
        for k in range(len(shapes)):  # mass-normalised: the mode's kinetic energy (x 2 / omega^2) is 1
            if energy[k] > 0.5:
                out.append("bungee surge" if axial[k] > 0.5 * energy[k] else "bungee string")
            else:
                out.append(None)
        return out
