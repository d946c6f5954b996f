"""What an evaluation of the updating problem produces: one configuration at a design point
(ConfigurationPoint), its rows (Block), and the whole design point (Point)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from ..fem import Modes
from .settings import renamed


class DesignPointFailure(SolverError):
    """A configuration could not be solved at a design point (the optimiser backs off)."""


@dataclass
class Block:
    """One configuration's rows: residuals and constraints (c >= 0) with their Jacobians."""

    residuals: np.ndarray
    names: list[str]
    constraints: np.ndarray
    constraint_names: list[str]
    jacobian: np.ndarray | None = None
    constraint_jacobian: np.ndarray | None = None


@dataclass
class ConfigurationPoint:
    """One configuration at one design point."""

    name: str
    state: object
    eigenvalues: np.ndarray  # (n_analysed,) [rad^2/s^2]
    frequencies_hz: np.ndarray  # (n_analysed,)
    phi: np.ndarray  # (n_free, n_analysed) reduced, mass-normalised
    paired: np.ndarray  # (n_measured,) analytical mode index, -1 unpaired
    mac: np.ndarray  # (n_measured,) MAC of each pair (nan without shapes)
    mac_matrix: np.ndarray | None  # (n_measured, n_analysed)
    sensor_shapes: np.ndarray | None  # (n_analysed, n_sensors)
    static: np.ndarray  # (n_static,) computed static deflections
    K: sp.csc_matrix | None = None  # symmetric tangent the modes solve
    M: sp.csc_matrix | None = None
    tangent: sp.csc_matrix | None = None  # full tangent at the equilibrium
    block: "Block | None" = None  # this configuration's residuals, constraints and their Jacobians
    seen: np.ndarray | None = None  # (n_analysed,) the sensors see the mode (None: not judged)
    _labels: tuple[str, ...] | None = None

    @property
    def labels(self) -> tuple[str, ...]:
        """Labels (OOP/IP/T, rigid-body names) of the analysed modes."""
        if self._labels is None:
            self._labels = tuple(self.modes().labels)
        return self._labels

    def to_dict(self) -> dict:
        """What a remote evaluation sends back (no state, no matrices)."""
        return {"name": self.name, "eigenvalues": self.eigenvalues, "frequencies_hz": self.frequencies_hz,
                "paired": self.paired, "mac": self.mac, "mac_matrix": self.mac_matrix, "static": self.static,
                "labels": self.labels, "block": self.block, "seen": self.seen}

    def summary(self) -> dict:
        """Deprecated: to_dict() (summary() is the one-line text of a result elsewhere)."""
        renamed("ConfigurationPoint.summary()", "ConfigurationPoint.to_dict()")
        return self.to_dict()

    @classmethod
    def from_dict(cls, d: dict) -> "ConfigurationPoint":
        """The point a remote evaluation sent back (to_dict)."""
        return cls(d["name"], None, d["eigenvalues"], d["frequencies_hz"], None, d["paired"], d["mac"],
                   d["mac_matrix"], None, d["static"], block=d["block"], seen=d.get("seen"), _labels=d["labels"])

    @classmethod
    def from_summary(cls, d: dict) -> "ConfigurationPoint":
        """Deprecated: from_dict()."""
        renamed("ConfigurationPoint.from_summary()", "ConfigurationPoint.from_dict()")
        return cls.from_dict(d)

    def modes(self, label: bool = True) -> Modes:
        """The analysed modes as fem Modes (full shapes about the state), labelled unless label=False."""
        system = self.state.system
        T = system.transformation(self.state.positions, self.state.rotations) if system.has_links else None
        shapes = system.expand(self.phi, T).T.reshape(len(self.eigenvalues), system.n_nodes, 6)
        modes = Modes(self.frequencies_hz, np.zeros(len(self.eigenvalues)), self.frequencies_hz.copy(), shapes,
                      system.cm.node_ids, eigenvalues=self.eigenvalues, state=self.state)
        if not label:
            return modes
        from ..fem.labels import label_modes
        return label_modes(modes)


@dataclass
class Point:
    """Everything computed at one design point."""

    x: np.ndarray
    residuals: np.ndarray
    residual_names: list[str]
    configurations: dict[str, ConfigurationPoint]
    mass_properties: object
    jacobian: np.ndarray | None = None
    constraints: np.ndarray = field(default_factory=lambda: np.zeros(0))
    constraint_names: list[str] = field(default_factory=list)
    constraint_jacobian: np.ndarray | None = None
    unpaired: dict[str, list[int]] = field(default_factory=dict)
    seconds: float = 0.0
    n_prior: int = 0  # trailing rows that are the variables' prior (Objective.prior), not data

    @property
    def objective(self) -> float:
        return float(self.residuals @ self.residuals)

    @property
    def data_residuals(self) -> np.ndarray:
        """The residuals of the test data alone (the prior's rows left out)."""
        return self.residuals[:len(self.residuals) - self.n_prior]

    @property
    def data_jacobian(self) -> np.ndarray | None:
        """The Jacobian of data_residuals."""
        return None if self.jacobian is None else self.jacobian[:self.jacobian.shape[0] - self.n_prior]

