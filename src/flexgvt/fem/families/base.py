"""The element-family protocol: what a family of elements gives System, which assembles over a
tuple of families (beams, point masses, cords, springs; shells next) and knows none of them.

A family is a frozen object holding its own per-element arrays (built per model and configuration)
and evaluating them vectorised over all its elements. Every element of a family has the same
number of nodes p, each with the six DOFs (dx, spin) of the node; the element vectors and
matrices are over [node 1 (6), node 2 (6), ...], d = 6 p. See docs/architecture.md, "Element
families", for the contract in prose.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ...model import Configuration


@dataclass(frozen=True)
class ElementTerms:
    """A family's element terms at one state: forces (n, d) conjugate to the element DOFs (internal
    forces, load potentials of offset weights included) [N, N m]; tangent (n, d, d) with
    K[a, b] = d forces_a / d p_b, or None when not asked; output: the family's own results at the
    state (beam local forces, cord tensions and lengths), handed back to it as ``reference``."""

    forces: np.ndarray
    tangent: np.ndarray | None
    output: Any = None


@dataclass(frozen=True)
class Derivative:
    """d(element terms)/dp of elements ``rows`` of a family for one parameter change: forces (k, d)
    (internal), applied (k, d) or None (the change of the applied loads, e.g. weight with rho),
    tangent (k, d, d) or None, mass (k, d, d) or None."""

    rows: np.ndarray
    forces: np.ndarray | None = None
    applied: np.ndarray | None = None
    tangent: np.ndarray | None = None
    mass: np.ndarray | None = None


@runtime_checkable
class Family(Protocol):
    """What System needs from an element family.

    name: the key of its outputs in Evaluation.outputs and of its items in sensitivity.ValueChange;
    structural: its stiffness is the structure's own (counted in System.structure_diagonal, against
    which grounded springs are judged; springs are not); translation_invariant: elements whose
    tangent and mass depend on the differences of their nodes' positions only (the state
    derivatives take the first node's translations as minus the sum of the others'); value_fields:
    the ValueChange fields this family differentiates. Optional: mass_from_positions (True: the mass
    does not depend on the rotations, and exploded_terms(..., mass=False) gives the tangent alone).
    """

    name: str
    structural: bool
    translation_invariant: bool
    value_fields: tuple[str, ...]

    @property
    def nodes(self) -> np.ndarray:
        """(n, p) node storage indices of each element: its DOF needs (6 per node)."""

    @property
    def has_damping(self) -> bool:
        """True when damping_values is not zero."""

    def topology(self) -> tuple[np.ndarray, ...]:
        """The arrays the DOF numbering and sparsity pattern depend on (compared by System.for_values)."""

    def terms(self, x: np.ndarray, R: np.ndarray, lam: float, tangent: bool, reference: Any = None) -> ElementTerms:
        """Forces and (if tangent) consistent tangent at nodal positions x (n_nodes, 3) [m] and
        rotations R (n_nodes, 3, 3), load factor lam; reference: ``output`` of another evaluation
        to use in the stress-dependent part of the tangent (or None)."""

    def mass_values(self, x: np.ndarray, R: np.ndarray) -> np.ndarray:
        """(n, d, d) element mass matrices about the state [kg, kg m, kg m^2]."""

    def damping_values(self, x: np.ndarray, R: np.ndarray) -> np.ndarray:
        """(n, d, d) element viscous damping matrices about the state [N s/m, N m s/rad]."""

    def add_applied(self, f: np.ndarray, configuration: Configuration, gravity: np.ndarray) -> None:
        """Add the family's applied loads at load factor 1 (fixed direction: lumped weight,
        distributed loads) into the nodal array f (n_nodes, 6) [N, N m]."""

    def exploded_terms(self, xs: np.ndarray, Rs: np.ndarray, lam: float) -> tuple[np.ndarray, np.ndarray | None]:
        """(tangent (n, d, d), mass (n, d, d) or None when the family has no mass) of every element
        with its own copy of its nodes: xs (n, p, 3), Rs (n, p, 3, 3) (for state derivatives)."""

    def derivative(self, field: str, item: tuple, x: np.ndarray, R: np.ndarray, lam: float,
                   gravity: np.ndarray, cache: dict) -> Derivative:
        """The change of the family's element terms for ValueChange.<field> = item."""

    def check_values(self, where: str, node_ids: np.ndarray) -> None:
        """Raise a ModelError naming the first elements whose values would overflow the solvers
        (NaN, inf, beyond checks.VALUE_LIMIT or COORDINATE_LIMIT) and the remedy."""

    def connections(self) -> np.ndarray:
        """(k, 2) node pairs the family joins stiffly (checks.check_connected)."""

    def held_nodes(self) -> np.ndarray:
        """Nodes the family holds to the ground (a grounded spring, a cord to its anchor)."""

    def used_nodes(self) -> np.ndarray:
        """Nodes the family gives mass or stiffness (beyond its connections): not inert."""

    def describe(self, nodes: np.ndarray) -> str:
        """What of the family is attached to nodes (storage indices), for messages; "" if nothing."""


def element_dofs(nodes: np.ndarray) -> np.ndarray:
    """(n, 6 p) full DOF numbers of elements with nodes (n, p)."""
    nodes = np.asarray(nodes, np.int64)
    return (6 * nodes[:, :, None] + np.arange(6)).reshape(len(nodes), 6 * nodes.shape[1])


def zero_blocks(n: int, p: int) -> np.ndarray:
    """(n, 6 p, 6 p) zeros: a family without mass or damping."""
    return np.zeros((n, 6 * p, 6 * p))
