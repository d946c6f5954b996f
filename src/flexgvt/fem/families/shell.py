"""The shell family: flat corotational quads or triangles (kernels in fem._shell_kernel, the EICR
wrapper in fem._shell_corotational, sections compiled in fem._shell_model). One family per corner
count: "shell4" (quads) and "shell3" (triangles)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

from ...errors import ModelError
from ...model import Configuration
from .._shell_corotational import CorotationalTerms, corotated_frames, corotational_setup, corotational_terms
from .._shell_elements import drill_factor_penalty
from .._shell_kernel import turn_blocks
from .._shell_model import ShellArrays, group_sections
from ..checks import _REMEDY, _bad, _ids
from ..labels import section_fractions
from .base import Derivative, ElementTerms, zero_blocks


def _turned(M: np.ndarray, E: np.ndarray, p: int) -> np.ndarray:
    """Element matrices M (n, 6p, 6p) with components in the frames E (n, 3, 3), in global components:
    E M_ab E^T on each 3 x 3 block (a compiled loop, _shell_kernel.turn_blocks: the batched 3 x 3
    products cost 8 ms per evaluation of the 0.25 m wingbox, 600 times per verification seed; the
    block-diagonal frame matrix made the state derivatives' mass five times slower)."""
    M = np.ascontiguousarray(M, dtype=float)
    return turn_blocks(M, np.ascontiguousarray(E, dtype=float), np.empty_like(M))


def _weight_direction(gravity: np.ndarray, p: int) -> np.ndarray:
    """(6p,) the acceleration of gravity on every corner's translations [m/s^2]."""
    return np.tile(np.r_[gravity, 0.0, 0.0, 0.0], p)


@dataclass(frozen=True, eq=False)
class ShellFamily:
    """All shells of one corner count. Output of terms: the CorotationalTerms (frames, local
    deformations and forces), which a reference evaluation hands back for the stress-dependent
    part of the tangent."""

    arrays: ShellArrays
    name: str

    structural: ClassVar[bool] = True
    translation_invariant: ClassVar[bool] = True  # terms of the corner differences only
    mass_from_positions: ClassVar[bool] = True  # the mass matrix depends on the corners' positions only
    value_fields: ClassVar[tuple[str, ...]] = ("shells",)
    has_damping: ClassVar[bool] = False

    @staticmethod
    def build(arrays: ShellArrays) -> "ShellFamily":
        return ShellFamily(arrays, f"shell{arrays.p}")

    @property
    def nodes(self) -> np.ndarray:
        return self.arrays.nodes

    @property
    def p(self) -> int:
        return self.arrays.p

    def topology(self) -> tuple[np.ndarray, ...]:
        return (self.arrays.nodes,)

    def terms(self, x, R, lam, tangent, reference: CorotationalTerms | None = None) -> ElementTerms:
        nodes = self.arrays.nodes
        t = corotational_terms(self.arrays.corotational, x[nodes], R[nodes], tangent, reference=reference)
        return ElementTerms(t.forces, t.tangent, t)

    def _global_mass(self, xs: np.ndarray) -> np.ndarray:
        """The element masses (components in the corotated frame) in global components at corners xs."""
        return _turned(self.arrays.corotational.M, corotated_frames(xs), self.p)

    def mass_values(self, x, R) -> np.ndarray:
        return self._global_mass(x[self.arrays.nodes])

    def damping_values(self, x, R) -> np.ndarray:
        return zero_blocks(len(self.arrays.nodes), self.p)

    def add_applied(self, f: np.ndarray, configuration: Configuration, gravity: np.ndarray) -> None:
        """The weight as the consistent load M g of the undeformed elements, fixed in direction
        (forces; the moments of offset mass, m1 g, at their undeformed value)."""
        if not np.any(gravity):
            return
        a = self.arrays
        w = (self._global_mass(a.corotational.X) @ _weight_direction(gravity, self.p)).reshape(len(a.nodes), self.p, 6)
        np.add.at(f, a.nodes.reshape(-1), w.reshape(-1, 6))

    def exploded_terms(self, xs, Rs, lam, mass: bool = True):
        """mass=False: the tangent only (the mass turns with the corner positions alone, so a
        rotation of a node leaves it unchanged: mass_from_positions)."""
        t = corotational_terms(self.arrays.corotational, xs, Rs, True)
        return t.tangent, (self._global_mass(xs) if mass else None)

    def strain_energies(self, shapes: np.ndarray, x: np.ndarray, R: np.ndarray) -> np.ndarray:
        """(n_modes, 5) the shells' strain energy of mode shapes (n_modes, n_nodes, 6) at the state,
        1/2 phi^T K phi with the symmetric part of their tangent, split into OOP, IP, torsion,
        extension and local deformation by the motion of the shell nodes' cross-sections
        (labels.section_fractions)."""
        a = self.arrays
        K = self.terms(x, R, 1.0, True).tangent
        phi = np.asarray(shapes, float)[:, a.nodes].reshape(len(shapes), len(a.nodes), 6 * self.p)
        energy = 0.5 * np.einsum("mna,nab,mnb->m", phi, K, phi)
        used = np.unique(a.nodes)
        M = self.mass_values(x, R)
        diag = np.diagonal(M, axis1=1, axis2=2).reshape(len(a.nodes), self.p, 6)[:, :, :3].mean(axis=2)
        mass = np.bincount(a.nodes.reshape(-1), weights=diag.reshape(-1), minlength=len(x))[used]
        X = np.zeros((len(x), 3))
        X[a.nodes.reshape(-1)] = self.arrays.corotational.X.reshape(-1, 3)  # the corners' reference positions
        return np.maximum(energy, 0.0)[:, None] * section_fractions(np.asarray(shapes)[:, used], x[used], mass,
                                                                    reference=X[used])

    def thickness_at(self, nodes: np.ndarray) -> tuple[float, int] | None:
        """The thickness most of the shells touching ``nodes`` (storage indices) have [m] (the thinner
        on a tie) and how many have it; None when none does."""
        on = np.isin(self.arrays.nodes, nodes).any(axis=1)
        if not np.any(on):
            return None
        values, counts = np.unique(self.arrays.thickness[on], return_counts=True)
        k = int(np.argmax(counts))  # np.unique sorts: the first of the most common is the thinnest
        return float(values[k]), int(counts[k])

    def check_values(self, where: str, node_ids: np.ndarray) -> None:
        a = self.arrays
        bad = _bad(a.C) | _bad(a.mass)
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            raise ModelError(f"{where}: shell element(s) {_ids(a.element_ids[bad])} (group '{a.group_names[k]}') "
                             f"have section or mass terms that are not finite or too large: check the group's "
                             f"property (thickness, NSM) and materials; {_REMEDY}")

    def connections(self) -> np.ndarray:
        nodes = self.arrays.nodes
        return np.stack([nodes, np.roll(nodes, -1, axis=1)], axis=-1).reshape(-1, 2)

    def held_nodes(self) -> np.ndarray:
        return np.zeros(0, int)

    def used_nodes(self) -> np.ndarray:
        return np.zeros(0, int)

    def describe(self, nodes: np.ndarray) -> str:
        a = self.arrays
        on = np.isin(a.nodes, nodes).any(axis=1)
        if not np.any(on):
            return ""
        kind = "quad" if self.p == 4 else "triangle"
        return f"shell {kind}(s) {_ids(a.element_ids[on])} (group(s) {', '.join(sorted(set(a.group_names[on])))})"

    def derivative(self, field, item, x, R, lam, gravity, cache) -> Derivative:
        """item = {group position in Model.shells: [(property, weight), ...]}: a difference rule in a
        property value. The element terms are linear in the element constants (the local stiffness,
        the initial-stress resultants' map, the masses), so their change is the same corotational
        evaluation with sum weight * constants(property). A quad's constants are linear in its section
        and mass (the drilling penalty too, on the base section's branch): one kernel pass with the
        rule applied to the sections; the triangle's ANDES scale depends on the section's Poisson
        ratio, so its constants come from one kernel pass per property. Once per change and reference
        geometry (``cache``)."""
        a = self.arrays
        groups = np.array(sorted(int(g) for g in item), int)
        rows = np.flatnonzero(np.isin(a.groups, groups))
        if not len(rows):
            return Derivative(rows)
        base = a.corotational
        # Keyed by the elements' reference geometry too: one change serves every configuration, and
        # a configuration's imperfection (Configuration.imperfection) moves its shells' reference.
        key = ("shell", self.name, base.X[rows].tobytes())
        data = cache.get(key)
        if data is None:
            K, M = np.zeros((len(rows),) + base.K.shape[1:]), np.zeros((len(rows),) + base.K.shape[1:])
            GN = None if base.GN is None else np.zeros((len(rows),) + base.GN.shape[1:])
            X = base.X[rows]
            for g in groups:
                on = a.groups[rows] == g
                if not np.any(on):  # a group of the other corner count
                    continue
                group = a.shell_groups[g]
                where = f"shell group '{group.name}'"
                ids, lumped = a.element_ids[rows][on], a.lumped[rows][on]
                sections = [(*group_sections(replace(group, property=prop), X[on], where)[:2], weight)
                            for prop, weight in item[g]]
                if self.p == 4:  # linear in the section and mass: one element pass with their changes
                    dC = sum(w * C for C, _, w in sections)
                    dm = sum(w * m for _, m, w in sections)
                    drill = drill_factor_penalty(X[on], dC, like=a.C[rows][on])
                    parts = [(corotational_setup(X[on], dC, ids=ids, initial_stress=GN is not None, mass=dm,
                                                 lumped=lumped, drill=drill, stress_matrices=False), 1.0)]
                else:  # the triangle's ANDES scale is not linear in the section: the rule on whole setups
                    parts = [(corotational_setup(X[on], C, ids=ids, initial_stress=GN is not None, mass=m,
                                                 lumped=lumped), w) for C, m, w in sections]
                for one, weight in parts:
                    K[on] += weight * one.K
                    M[on] += weight * one.M
                    if GN is not None:
                        GN[on] += weight * one.GN
            data = cache[key] = replace(base, X=X, E0=base.E0[rows], Xl=base.Xl[rows], K=K, GN=GN,
                                        KS=None if base.KS is None else base.KS[rows], M=M)
        nodes = a.nodes[rows]
        forces = tangent = None
        if np.any(data.K):
            t = corotational_terms(data, x[nodes], R[nodes], True)
            forces, tangent = t.forces, t.tangent
        mass = applied = None
        if np.any(data.M):
            mass = _turned(data.M, corotated_frames(x[nodes]), self.p)
            if np.any(gravity):  # the weight's change, as add_applied: the undeformed elements' M g
                applied = lam * (_turned(data.M, data.E0, self.p) @ _weight_direction(gravity, self.p))
        return Derivative(rows, forces, applied, tangent, mass)
