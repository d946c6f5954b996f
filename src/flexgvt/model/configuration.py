"""A test configuration: boundary conditions, suspension and loads of one test, kept apart from the model."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Mapping

import numpy as np

from ..errors import ModelError
from .components import ConcentratedMass, Cord, DistributedLoad, NodalLoad, Spring

STANDARD_GRAVITY = 9.80665  # m/s^2


def parse_dofs(spec: str | Iterable[int], where: str) -> tuple[int, ...]:
    """'123456'-style component string (or iterable of 1..6) -> sorted 0-based DOF indices."""
    items = list(str(spec)) if isinstance(spec, (str, int)) else list(spec)
    try:
        dofs = sorted({int(c) - 1 for c in items})
    except ValueError:
        raise ModelError(f"{where}: DOF components {spec!r} must be digits 1-6 (1-3 translations, 4-6 rotations)") \
            from None
    if not dofs or dofs[0] < 0 or dofs[-1] > 5:
        raise ModelError(f"{where}: DOF components {spec!r} must be digits 1-6")
    return tuple(dofs)


@dataclass(frozen=True)
class Configuration:
    """Boundary conditions + suspension + loads of one test.

    fixed: {node id: '123456'-style components held at zero}; prescribed: {node id: {component
    1-6: value}} enforced displacements [m] and rotations [rad] (Nastran SPCD), ramped with the
    load factor and held there (a prescribed rotation needs the node's other rotations fixed or
    prescribed too); suspension: cords; springs:
    configuration-specific springs (a test-fixture root spring, say); masses: extra masses
    present only in this test; gravity: load factor on gravity (1.0 = 1 g) acting along
    ``gravity_direction`` with ``g`` [m/s^2]; forces and distributed loads are fixed in direction
    and scaled by the same load factor ramp. support: {node id: components} reference DOFs of a
    free structure (Nastran SUPORT): they hold nothing (the structure is solved free-free, its
    rigid-body modes at 0 Hz) and are kept for the analyses that need them. imperfection: {node id:
    (dx, dy, dz)} offsets of the stress-free geometry in this test [m] (an imperfect article: the
    small buckling-shape imperfection that takes a perfect one onto its post-buckled path).
    """

    name: str
    fixed: Mapping[int, str] = field(default_factory=dict)
    suspension: tuple[Cord, ...] = ()
    springs: tuple[Spring, ...] = ()
    masses: tuple[ConcentratedMass, ...] = ()
    gravity: float = 0.0
    gravity_direction: tuple[float, float, float] = (0.0, 0.0, -1.0)
    g: float = STANDARD_GRAVITY
    forces: tuple[NodalLoad, ...] = ()
    distributed: tuple[DistributedLoad, ...] = ()
    prescribed: Mapping[int, Mapping[int, float]] = field(default_factory=dict)
    support: Mapping[int, str] = field(default_factory=dict)
    imperfection: Mapping[int, tuple[float, float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "suspension", tuple(self.suspension))
        object.__setattr__(self, "springs", tuple(self.springs))
        object.__setattr__(self, "masses", tuple(self.masses))
        object.__setattr__(self, "forces", tuple(self.forces))
        object.__setattr__(self, "distributed", tuple(self.distributed))
        object.__setattr__(self, "fixed", {int(k): str(v) for k, v in dict(self.fixed).items()})
        for node, spec in self.fixed.items():
            parse_dofs(spec, f"configuration '{self.name}': fixed[{node}]")
        object.__setattr__(self, "support", {int(k): str(v) for k, v in dict(self.support).items()})
        for node, spec in self.support.items():
            parse_dofs(spec, f"configuration '{self.name}': support[{node}]")
        prescribed = {}
        for node, values in dict(self.prescribed).items():
            where = f"configuration '{self.name}': prescribed[{node}]"
            items = {}
            for comp, value in dict(values).items():
                if len(str(comp)) != 1:
                    raise ModelError(f"{where}: give one component 1-6 per value, got {comp!r}")
                (dof,) = parse_dofs(str(comp), where)
                if not math.isfinite(float(value)):
                    raise ModelError(f"{where}: the value of component {comp} must be finite, got {value!r}")
                items[dof + 1] = float(value)
            rot = {c for c in items if c > 3}
            if rot:
                spec = self.fixed.get(int(node))
                fixed_rot = {d + 1 for d in parse_dofs(spec, where) if d >= 3} if spec else set()
                if rot | fixed_rot != {4, 5, 6}:
                    raise ModelError(f"{where}: a prescribed rotation needs the node's other rotations fixed or "
                                     "prescribed (fixed={node: '456'} or all three values); finite rotations about "
                                     "one free axis are not defined")
            prescribed[int(node)] = items
        object.__setattr__(self, "prescribed", prescribed)
        imperfection = {}
        for node, offset in dict(self.imperfection).items():
            v = tuple(float(c) for c in offset)
            if len(v) != 3 or not all(math.isfinite(c) for c in v):
                raise ModelError(f"configuration '{self.name}': imperfection[{node}] must be three finite offsets "
                                 f"(dx, dy, dz) [m], got {offset!r}")
            imperfection[int(node)] = v
        object.__setattr__(self, "imperfection", imperfection)
        direction = np.asarray(self.gravity_direction, dtype=float)
        if not np.all(np.isfinite(np.r_[direction, self.gravity, self.g])) or np.linalg.norm(direction) == 0:
            raise ModelError(f"configuration '{self.name}': gravity, g and a non-zero gravity_direction must be finite")

    @property
    def gravity_vector(self) -> np.ndarray:
        """Acceleration of gravity at load factor 1 [m/s^2] times the configuration's factor."""
        d = np.asarray(self.gravity_direction, dtype=float)
        return self.gravity * self.g * d / np.linalg.norm(d)

    def with_(self, **changes) -> "Configuration":
        """A copy with some fields changed (the model is never copied)."""
        from dataclasses import replace
        return replace(self, **changes)
