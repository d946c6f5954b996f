"""The beam family: corotational two-node beams and rods (kernels in fem.beam)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np

from ...errors import ModelError
from ...model import Configuration
from ..beam import BeamData, beam_forces, beam_mass_matrices, local_mass_matrices, nodal_weights, strain_energies
from ..checks import _REMEDY, VALUE_LIMIT, _bad, _ids
from .base import Derivative, ElementTerms, zero_blocks


@dataclass(frozen=True, eq=False)
class BeamFamily:
    """All beams of a model: data (the kernel's arrays), local_mass (n, 12, 12) element-axes mass
    matrices, element_ids (n,) and group_names (n,). Output of terms: the local forces (n, 7)
    [N, M1 (3), M2 (3)] (column 0 the axial force)."""

    data: BeamData
    local_mass: np.ndarray
    element_ids: np.ndarray
    group_names: np.ndarray

    name: ClassVar[str] = "beam"
    structural: ClassVar[bool] = True
    translation_invariant: ClassVar[bool] = True
    value_fields: ClassVar[tuple[str, ...]] = ("beams",)
    has_damping: ClassVar[bool] = False

    @property
    def nodes(self) -> np.ndarray:
        return self.data.nodes

    def topology(self) -> tuple[np.ndarray, ...]:
        return (self.data.nodes,)

    def terms(self, x, R, lam, tangent, reference=None) -> ElementTerms:
        g, K, local = beam_forces(x, R, self.data, tangent, reference_forces=reference)
        return ElementTerms(g, K, local)

    def mass_values(self, x, R) -> np.ndarray:
        return beam_mass_matrices(x, R, self.data, self.local_mass)

    def damping_values(self, x, R) -> np.ndarray:
        return zero_blocks(len(self.data.L0), 2)

    def add_applied(self, f: np.ndarray, configuration: Configuration, gravity: np.ndarray) -> None:
        """Lumped beam weight and the configuration's distributed loads on beam elements."""
        b = self.data
        w1, w2 = nodal_weights(b)
        np.add.at(f, (b.nodes[:, 0], slice(0, 3)), w1[:, None] * gravity[None, :])
        np.add.at(f, (b.nodes[:, 1], slice(0, 3)), w2[:, None] * gravity[None, :])
        if configuration.distributed:
            pos = {int(e): k for k, e in enumerate(self.element_ids)}
            for load in configuration.distributed:
                try:
                    ks = np.array([pos[int(e)] for e in load.elements], dtype=int)
                except KeyError as exc:
                    raise ModelError(f"configuration '{configuration.name}': distributed load on element "
                                     f"{exc.args[0]}, which is not a beam of the model") from None
                share = 0.5 * b.L0[ks][:, None] * np.asarray(load.per_length, float)[None, :]
                np.add.at(f, (b.nodes[ks, 0], slice(0, 3)), share)
                np.add.at(f, (b.nodes[ks, 1], slice(0, 3)), share)

    def exploded_terms(self, xs, Rs, lam):
        data = replace(self.data, nodes=np.arange(2 * len(self.data.L0), dtype=np.int64).reshape(-1, 2))
        xf, Rf = xs.reshape(-1, 3), Rs.reshape(-1, 3, 3)
        _, K, _ = beam_forces(xf, Rf, data, True)
        return K, beam_mass_matrices(xf, Rf, data, self.local_mass)

    def strain_energies(self, shapes: np.ndarray, x: np.ndarray, R: np.ndarray) -> np.ndarray:
        """(n_modes, 4) OOP, IP, torsion and extension strain energies of mode shapes (mode labels)."""
        return strain_energies(shapes, x, R, self.data)

    def check_values(self, where: str, node_ids: np.ndarray) -> None:
        b = self.data
        if not len(b.L0):
            return
        bad = _bad(b.stiffness) | _bad(b.mass_per_length) | _bad(b.inertia_per_length) | _bad(self.local_mass)
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            raise ModelError(f"{where}: beam element(s) {_ids(self.element_ids[bad])} (group "
                             f"'{self.group_names[k]}') have stiffness or mass terms that are not finite or "
                             f"exceed {VALUE_LIMIT:g} (SI): check the group's material (E, G, rho) and section "
                             f"(A, I, J) values; {_REMEDY}")

    def connections(self) -> np.ndarray:
        return self.data.nodes

    def held_nodes(self) -> np.ndarray:
        return np.zeros(0, int)

    def used_nodes(self) -> np.ndarray:
        return np.zeros(0, int)

    def describe(self, nodes: np.ndarray) -> str:
        on = np.isin(self.data.nodes, nodes).any(axis=1)
        if not np.any(on):
            return ""
        groups = sorted(set(self.group_names[on]))
        return f"beam element(s) {_ids(self.element_ids[on])} (group(s) {', '.join(groups)})"

    def derivative(self, field, item, x, R, lam, gravity, cache) -> Derivative:
        """item = (element rows (k,), d kernel coefficients (k, 8), d rho A (k, 2), d inertia per
        length (k, 2, 3)); the local mass matrices of the change are kept in ``cache``."""
        rows, dcoeff, drhoA, drhoI = item
        rows = np.asarray(rows, int)
        sub = replace(self.data.take(rows), stiffness=np.ascontiguousarray(dcoeff, dtype=float))
        g = K = f = M = None
        if np.any(sub.stiffness):  # E, G, section: the stiffness changes (not rho)
            g, K, _ = beam_forces(x, R, sub, True)
        if np.any(drhoA) or np.any(drhoI):  # rho, section: the mass changes (not E, G)
            dsub = replace(sub, mass_per_length=np.asarray(drhoA, float), inertia_per_length=np.asarray(drhoI, float))
            dw1, dw2 = nodal_weights(dsub)
            f = np.zeros((len(rows), 12))
            f[:, 0:3] = lam * dw1[:, None] * gravity[None, :]
            f[:, 6:9] = lam * dw2[:, None] * gravity[None, :]
            # The element-axes mass matrices do not depend on the state: once per change and
            # element lengths (a configuration's imperfection changes them), for every system.
            key = ("local_mass", sub.L0.tobytes())
            local = cache.get(key)
            if local is None:
                local = cache[key] = local_mass_matrices(dsub)
            M = beam_mass_matrices(x, R, sub, local)
        return Derivative(rows, g, f, K, M)
