"""The spring family: 6-component springs and dampers between two nodes or from a node to ground
(kernels in fem.points). A grounded spring is stored as node b with a = -1; its element is over
[node b, node b] with the first half zero. A component with a force-deflection table (model.Spring.tables)
takes its force and tangent from the table at its deflection, scaled by stiffness / nominal stiffness."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...errors import FlexGVTWarning, ModelError
from ...model import Configuration, Model
from ..checks import _REMEDY, VALUE_LIMIT, _bad, _ids
from ..points import spring_damping, spring_forces
from .base import Derivative, ElementTerms

# A grounded spring component this many times stiffer than the structure's diagonal stiffness at its
# DOF is a constraint (SpringFamily.clamps): it changes the modes by ~1/ratio from the clamped ones,
# below the round-off (~eps * ratio * the shift-invert's amplification) that keeping it would cost.
SPRING_CLAMP_RATIO = 1e8
# One that cannot be held is warned beyond this ratio: a 20- and a 40-element strip held by a grounded
# spring turned 0.3 rad about z (kept as a spring): first frequencies within 2e-9 of the clamped strip
# at ratios to 2e11, 5e-7 at 2e13, ARPACK without convergence at 2e15.
SPRING_WARN_RATIO = 1e12


@dataclass(frozen=True)
class Springs:
    a: np.ndarray  # (s,) storage index or -1 for ground
    b: np.ndarray
    stiffness: np.ndarray  # (s, 6)
    damping: np.ndarray  # (s, 6)
    frame: np.ndarray  # (s, 3, 3)
    tables: tuple = ()  # per spring its six tables (SpringTable or None); () when no spring has one

    @staticmethod
    def of(model: Model, items) -> "Springs":
        """The springs ``items`` (model.Spring) of ``model`` as arrays."""
        items = list(items)
        if not items:
            return Springs(np.zeros(0, int), np.zeros(0, int), np.zeros((0, 6)), np.zeros((0, 6)), np.zeros((0, 3, 3)))
        tables = tuple(s.tables for s in items) if any(s.nonlinear for s in items) else ()
        a = np.array([-1 if s.node_b is None else model.index_of([s.node_a], "spring")[0] for s in items])
        # A grounded spring acts on node_a: store it as b with a = -1.
        b = np.array([model.index_of([s.node_a if s.node_b is None else s.node_b], "spring")[0] for s in items])
        return Springs(a, b, np.array([s.stiffness for s in items]), np.array([s.damping for s in items]),
                       np.array([s.frame for s in items]), tables)

    def merged(self, other: "Springs") -> "Springs":
        """These springs followed by ``other``'s."""
        tables = () if not (self.tables or other.tables) else self.all_tables + other.all_tables
        return Springs(*(np.concatenate([getattr(self, f), getattr(other, f)])
                         for f in ("a", "b", "stiffness", "damping", "frame")), tables)

    @property
    def all_tables(self) -> tuple:
        """Per spring its six tables (None for linear components)."""
        return self.tables or ((None,) * 6,) * len(self.a)

    @property
    def table_mask(self) -> np.ndarray:
        """(s, 6) True where a component follows a table."""
        return np.array([[t is not None for t in row] for row in self.all_tables], bool).reshape(-1, 6)

    def law(self, rows, stiffness: np.ndarray):
        """The force law of springs ``rows`` with stiffnesses (or their changes) ``stiffness`` (k, 6)
        for fem.points.spring_forces: None when all are linear; else a function of the deflections in
        the spring axes (k, 6) giving (forces, slopes): k d on linear components, the table's scaled
        force and slope on the others (linear in ``stiffness``, so a stiffness change gives the
        derivative)."""
        if not self.tables:
            return None
        picked = [(i, c, t) for i, row in enumerate(np.asarray(self.tables, object)[rows].reshape(-1, 6))
                  for c, t in enumerate(row) if t is not None]
        if not picked:
            return None
        stiffness = np.asarray(stiffness, float)

        def evaluate(d):
            f, k = stiffness * d, stiffness.copy()
            for i, c, t in picked:
                force, slope = t.evaluate(d[i, c])
                scale = stiffness[i, c] / t.nominal_stiffness
                f[i, c], k[i, c] = scale * force, scale * slope
            return f, k
        return evaluate


@dataclass(frozen=True, eq=False)
class SpringFamily:
    """Springs in one configuration (the model's, then the configuration's); xyz (n_nodes, 3): the
    undeformed node positions (a spring's stretch is measured from them)."""

    springs: Springs
    xyz: np.ndarray

    name: ClassVar[str] = "spring"
    structural: ClassVar[bool] = False
    translation_invariant: ClassVar[bool] = False
    value_fields: ClassVar[tuple[str, ...]] = ("springs",)

    @property
    def ground(self) -> np.ndarray:
        return self.springs.a < 0

    @property
    def nodes(self) -> np.ndarray:
        s = self.springs
        if not len(s.b):
            return np.zeros((0, 2), int)
        return np.column_stack([np.where(s.a >= 0, s.a, s.b), s.b])  # grounded: node a's half zeroed

    @property
    def has_damping(self) -> bool:
        return bool(np.any(self.springs.damping > 0))

    def topology(self) -> tuple[np.ndarray, ...]:
        return (self.springs.a, self.springs.b)

    def _forces(self, xa_moved, Ra_moved, xb, Rb, rows, stiffness):
        """Forces and tangent of springs ``rows`` with their node a at (xa_moved, Ra_moved) (ignored
        for grounded springs) and node b at (xb, Rb)."""
        s, X = self.springs, self.xyz
        a, b = s.a[rows], s.b[rows]
        ground = a < 0
        ia = np.where(ground, b, a)
        xa = np.where(ground[:, None], X[b], xa_moved)
        Ra = np.where(ground[:, None, None], np.eye(3), Ra_moved)
        g, K = spring_forces(xa, X[ia], Ra, xb, X[b], Rb, s.frame[rows], stiffness, s.law(rows, stiffness))
        # A grounded spring's first node is a placeholder (its own node): zero that half.
        g[ground, :6] = 0.0
        K[ground, :6, :] = 0.0
        K[ground, :, :6] = 0.0
        return g, K

    def terms(self, x, R, lam, tangent, reference=None) -> ElementTerms:
        s = self.springs
        if not len(s.b):
            return ElementTerms(np.zeros((0, 12)), np.zeros((0, 12, 12)))
        ia = np.where(s.a < 0, s.b, s.a)
        return ElementTerms(*self._forces(x[ia], R[ia], x[s.b], R[s.b], slice(None), s.stiffness))

    def mass_values(self, x, R) -> np.ndarray:
        return np.zeros((len(self.springs.b), 12, 12))

    def damping_values(self, x, R) -> np.ndarray:
        s = self.springs
        if not len(s.b):
            return np.zeros((0, 12, 12))
        ground = s.a < 0
        Ra = np.where(ground[:, None, None], np.eye(3), R[np.where(ground, s.b, s.a)])
        C = spring_damping(Ra, R[s.b], s.frame, s.damping)
        C[ground, :6, :] = 0.0
        C[ground, :, :6] = 0.0
        return C

    def add_applied(self, f: np.ndarray, configuration: Configuration, gravity: np.ndarray) -> None:
        return None

    def exploded_terms(self, xs, Rs, lam):
        _, K = self._forces(xs[:, 0], Rs[:, 0], xs[:, 1], Rs[:, 1], slice(None), self.springs.stiffness)
        return K, None

    def derivative(self, field, item, x, R, lam, gravity, cache) -> Derivative:
        """item = (rows, d stiffness (k, 6))."""
        rows = np.asarray(item[0], int)
        s = self.springs
        ia = np.where(s.a[rows] < 0, s.b[rows], s.a[rows])
        g, K = self._forces(x[ia], R[ia], x[s.b[rows]], R[s.b[rows]], rows, np.asarray(item[1], float))
        return Derivative(rows, g, None, K)

    def check_values(self, where: str, node_ids: np.ndarray) -> None:
        s = self.springs
        if not len(s.b):
            return
        bad = _bad(s.stiffness) | _bad(s.damping)
        if np.any(bad):
            raise ModelError(f"{where}: spring(s) at node(s) {_ids(node_ids[s.b[bad]])} have a stiffness or damping "
                             f"that is not finite or exceeds {VALUE_LIMIT:g} (SI): to clamp a DOF fix it "
                             f"(fixed={{node: '123456'}}); otherwise {_REMEDY}")

    @property
    def _stiff(self) -> np.ndarray:
        return np.any(self.springs.stiffness > 0, axis=1)

    def connections(self) -> np.ndarray:
        s = self.springs
        pair = self._stiff & (s.a >= 0)
        return np.column_stack([s.a[pair], s.b[pair]])

    def held_nodes(self) -> np.ndarray:
        return self.springs.b[self._stiff & (self.springs.a < 0)]

    def used_nodes(self) -> np.ndarray:
        return self.springs.b[self._stiff]

    def describe(self, nodes: np.ndarray) -> str:
        s = self.springs
        return "spring(s)" if np.any(np.isin(s.b, nodes) | np.isin(s.a, nodes)) else ""

    def clamps(self, diag: np.ndarray, fixed: np.ndarray, link_dofs: np.ndarray, node_ids: np.ndarray,
               where: str) -> np.ndarray:
        """Full DOFs (sorted) that grounded springs hold as constraints: a component stiffer than
        SPRING_CLAMP_RATIO times the structure's own diagonal stiffness ``diag`` (6n,) there, along a
        global axis (spring axes may be turned; those along a global one act on its DOF alone), on a
        DOF no link sets (link_dofs (n, 6)); the three rotations of a node only together (a partly
        held rotation stays a spring). Such a spring changes the modes from the clamped ones by
        about the inverse ratio, while the round-off it brings into the factorisations grows with
        the ratio. A component that cannot be held and is more than SPRING_WARN_RATIO times stiffer
        than the structure gives a FlexGVTWarning."""
        s = self.springs
        n = len(link_dofs)
        ground = s.a < 0
        # (spring, node) pairs: a grounded spring's node, both nodes of the others.
        pair = np.r_[np.arange(len(s.b)), np.flatnonzero(~ground)]
        nodes = np.r_[s.b, s.a[~ground]]
        axis = np.argmax(np.abs(s.frame), axis=1)  # (m, 3): the global axis nearest each spring axis
        aligned = np.isclose(np.abs(np.take_along_axis(s.frame, axis[:, None, :], axis=1)[:, 0]), 1.0, rtol=0,
                             atol=1e-12)  # such an axis acts on its global DOF alone (the others are normal to it)
        full = 6 * nodes[:, None] + np.c_[axis[pair], 3 + axis[pair]]
        k, d = np.where(s.table_mask, 0.0, s.stiffness)[pair], diag[full]  # a table spring is never a clamp
        known = d > 0  # a DOF only springs hold: no conditioning loss
        stiff = known & (k > SPRING_CLAMP_RATIO * d)
        extreme = known & (k > SPRING_WARN_RATIO * d)
        ok = stiff & np.tile(aligned[pair], 2) & ~link_dofs.reshape(-1)[full] & ground[pair][:, None]
        held = np.zeros(6 * n, bool)
        held[full[:, :3][ok[:, :3]]] = True
        rot_held = np.zeros((n, 3), bool)
        r, c = np.nonzero(ok[:, 3:])
        rot_held[nodes[r], axis[pair][r, c]] = True
        rot_extreme = np.zeros(n, bool)
        np.logical_or.at(rot_extreme, nodes, np.any(extreme[:, 3:] & ok[:, 3:], axis=1))
        warn = list(nodes[np.any(extreme & ~ok, axis=1)])
        whole = np.all(rot_held | fixed.reshape(n, 6)[:, 3:], axis=1)
        held.reshape(n, 6)[:, 3:] |= rot_held & whole[:, None]
        warn += list(np.flatnonzero(rot_extreme & ~whole))
        if warn:
            node = warn[0]
            warnings.warn(
                f"{where}: {len(warn)} spring(s) (the first at node "
                f"{node_ids[node]}) are more than {SPRING_WARN_RATIO:g} times stiffer than the structure at "
                "their DOFs, and the solver cannot hold those DOFs as constraints instead (a spring between two "
                "nodes, axes not along the global ones, a DOF set by a link, or only part of a node's rotations): "
                "round-off may spoil the modes and the static solution. Fix the DOFs (fixed={node: '123456'}) "
                "or use a rigid link or linear constraint instead", FlexGVTWarning, stacklevel=4)
        return np.flatnonzero(held & ~fixed)
