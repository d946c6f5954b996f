"""The point-mass family: concentrated masses with offsets and inertia (kernels in fem.points)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...errors import ModelError
from ...model import Configuration
from ..checks import _REMEDY, COORDINATE_LIMIT, VALUE_LIMIT, _bad, _ids
from ..points import mass_gravity, mass_matrix
from .base import Derivative, ElementTerms, zero_blocks


@dataclass(frozen=True)
class PointMasses:
    nodes: np.ndarray  # (m,) storage indices
    mass: np.ndarray  # (m,) [kg]
    offset: np.ndarray  # (m, 3) [m]
    inertia: np.ndarray  # (m, 3, 3) [kg m^2]

    @staticmethod
    def empty() -> "PointMasses":
        return PointMasses(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3, 3)))

    def merged(self, other: "PointMasses") -> "PointMasses":
        """These masses followed by ``other``'s."""
        return PointMasses(*(np.concatenate([getattr(self, f), getattr(other, f)])
                             for f in ("nodes", "mass", "offset", "inertia")))


@dataclass(frozen=True, eq=False)
class PointMassFamily:
    """Point masses in one configuration: masses (the model's, the configuration's, then the share of
    heavy cords that moves with their attachment) and weight (m, 3) = mass x gravity [N]. Their
    weight at rotating offsets is a load potential: it enters ``terms``, not add_applied."""

    masses: PointMasses
    weight: np.ndarray

    name: ClassVar[str] = "mass"
    structural: ClassVar[bool] = True
    translation_invariant: ClassVar[bool] = False
    value_fields: ClassVar[tuple[str, ...]] = ("masses",)
    has_damping: ClassVar[bool] = False

    @staticmethod
    def build(masses: PointMasses, gravity: np.ndarray) -> "PointMassFamily":
        return PointMassFamily(masses, masses.mass[:, None] * gravity[None, :])

    @property
    def nodes(self) -> np.ndarray:
        return self.masses.nodes[:, None]

    def topology(self) -> tuple[np.ndarray, ...]:
        return (self.masses.nodes,)

    def terms(self, x, R, lam, tangent, reference=None) -> ElementTerms:
        m = self.masses
        if not len(m.nodes):
            return ElementTerms(np.zeros((0, 6)), np.zeros((0, 6, 6)))
        g, K = mass_gravity(R[m.nodes], m.offset, lam * self.weight)
        return ElementTerms(g, K)

    def mass_values(self, x, R) -> np.ndarray:
        m = self.masses
        return mass_matrix(R[m.nodes], m.offset, m.mass, m.inertia)

    def damping_values(self, x, R) -> np.ndarray:
        return zero_blocks(len(self.masses.nodes), 1)

    def add_applied(self, f: np.ndarray, configuration: Configuration, gravity: np.ndarray) -> None:
        return None

    def exploded_terms(self, xs, Rs, lam):
        m = self.masses
        _, K = mass_gravity(Rs[:, 0], m.offset, lam * self.weight)
        return K, mass_matrix(Rs[:, 0], m.offset, m.mass, m.inertia)

    def check_values(self, where: str, node_ids: np.ndarray) -> None:
        m = self.masses
        if not len(m.nodes):
            return
        with np.errstate(over="ignore", invalid="ignore"):
            arm = np.linalg.norm(np.nan_to_num(m.offset, nan=np.inf), axis=1)
            moment = m.mass * arm ** 2
        bad = _bad(m.mass) | _bad(m.inertia) | _bad(m.offset, COORDINATE_LIMIT) | _bad(moment)
        if np.any(bad):
            raise ModelError(f"{where}: concentrated mass(es) at node(s) {_ids(node_ids[m.nodes[bad]])} have a "
                             f"mass, offset or inertia that is not finite or too large (offset beyond "
                             f"{COORDINATE_LIMIT:g} m or m |offset|^2 beyond {VALUE_LIMIT:g} kg m^2): {_REMEDY}")

    def connections(self) -> np.ndarray:
        return np.zeros((0, 2), int)

    def held_nodes(self) -> np.ndarray:
        return np.zeros(0, int)

    def used_nodes(self) -> np.ndarray:
        return self.masses.nodes[self.masses.mass > 0]

    def describe(self, nodes: np.ndarray) -> str:
        return "concentrated mass(es)" if np.any(np.isin(self.masses.nodes, nodes)) else ""

    def derivative(self, field, item, x, R, lam, gravity, cache) -> Derivative:
        """item = (rows, (mass, offset) at p + h, (mass, offset) at p - h, 1 / (2 h)): masses enter
        linearly and offsets quadratically, so the central difference is exact."""
        rows, (m_p, off_p), (m_m, off_m), inv2h = item
        rows = np.asarray(rows, int)
        nodes = self.masses.nodes[rows]
        inertia = self.masses.inertia[rows]
        g = K = M = 0.0
        for m_, off, w in ((m_p, off_p, inv2h), (m_m, off_m, -inv2h)):
            weight = lam * np.asarray(m_, float)[:, None] * gravity[None, :]
            gi, Ki = mass_gravity(R[nodes], np.asarray(off, float), weight)
            g, K = g + w * gi, K + w * Ki
            M = M + w * mass_matrix(R[nodes], np.asarray(off, float), np.asarray(m_, float), inertia)
        return Derivative(rows, g, None, K, M)
