"""Mass properties (mass, centre of gravity, inertia tensor) of the deformed or undeformed structure."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Configuration, Model
from .system import System


@dataclass(frozen=True)
class MassProperties:
    """mass [kg], cg (3,) [m], inertia (3, 3) about the cg [kg m^2], global axes."""

    mass: float
    cg: np.ndarray
    inertia: np.ndarray

    def as_dict(self) -> dict:
        I = self.inertia
        return {"mass": self.mass, "Xcg": self.cg[0], "Ycg": self.cg[1], "Zcg": self.cg[2],
                "Ixx": I[0, 0], "Iyy": I[1, 1], "Izz": I[2, 2], "Ixy": I[0, 1], "Ixz": I[0, 2], "Iyz": I[1, 2]}


def mass_properties(state_or_model, configuration: Configuration | None = None) -> MassProperties:
    """Mass properties from the rigid-body projection of the full mass matrix at a state (or the
    undeformed model), so they agree exactly with the modal mass model (offsets, inertias,
    rotary inertia option)."""
    if isinstance(state_or_model, Model):
        system = System(state_or_model, configuration or Configuration("undeformed"))
        x, R = system.undeformed
    else:
        system = state_or_model.system
        x, R = state_or_model.positions, state_or_model.rotations
    return system_mass_properties(system, x, R)


def rigid_body_basis(x: np.ndarray) -> np.ndarray:
    """(6n, 6) unit rigid-body motions about the origin at positions x (n, 3): translations X, Y, Z,
    then rotations about X, Y, Z (node-major, 6 DOF per node)."""
    n = len(x)
    phi = np.zeros((n, 6, 6))
    for a in range(3):
        e = np.zeros(3)
        e[a] = 1.0
        phi[:, a, a] = 1.0
        phi[:, :3, 3 + a] = np.cross(e, x)
        phi[:, 3 + a, 3 + a] = 1.0
    return phi.reshape(6 * n, 6)


def system_mass_properties(system: System, x: np.ndarray, R: np.ndarray) -> MassProperties:
    """Mass properties of a compiled system at positions x (n, 3) and rotations R (n, 3, 3)."""
    M = system.full_mass_matrix(x, R)
    phi = rigid_body_basis(x)
    Mrb = phi.T @ (M @ phi)
    mass = float(np.trace(Mrb[:3, :3]) / 3)
    S = Mrb[3:, :3] / mass  # m S(c) -> S(c)
    cg = np.array([S[2, 1], S[0, 2], S[1, 0]])
    Sc = np.array([[0, -cg[2], cg[1]], [cg[2], 0, -cg[0]], [-cg[1], cg[0], 0]])
    inertia = Mrb[3:, 3:] + mass * Sc @ Sc
    return MassProperties(mass, cg, 0.5 * (inertia + inertia.T))
