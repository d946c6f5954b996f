"""What the model is updated against: measured modes per configuration, mass properties, static
deflections, and the weights and limits of the objective (docs/method.md section 4)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError
from ..modal import ModalSet
from .settings import check_settings, setting


@dataclass(frozen=True)
class Measured:
    """Test data of one configuration: measured modes (``modal_set``) plus the targets and weights.

    frequencies_hz (n,); shapes (n, n_sensors) real or complex, rows in the order of ``sensors``
    (a flexgvt.correlation.Sensors), or None (frequencies only: modes are then paired by
    frequency and followed by MAC between design points); frequency_std_hz: standard deviations
    of repeated tests (weights and the variables' uncertainty); static: {(node, component 1-6):
    measured static displacement [m or rad]} of the configuration's equilibrium; labels: names of
    the measured modes for the tables; observed_by: with frequencies only, the Sensors that measured
    them: the first pairing then takes only analytical modes they see, whose reading amplitude
    (mass-normalised shapes) is at least ``visibility`` times the best-seen mode's (vertical
    accelerometers do not see in-plane or pendulum modes, which would otherwise pair by frequency).
    """

    configuration: str
    frequencies_hz: np.ndarray
    shapes: np.ndarray | None = None
    sensors: object | None = None
    frequency_std_hz: np.ndarray | None = None
    static: dict = field(default_factory=dict)
    labels: tuple[str, ...] = ()
    observed_by: object | None = None
    visibility: float = 0.05

    def __post_init__(self) -> None:
        where = f"measured data of configuration '{self.configuration}'"
        f = np.atleast_1d(np.asarray(self.frequencies_hz, float))
        if f.ndim != 1 or len(f) == 0:
            raise ModelError(f"{where}: give at least one measured frequency")
        if not np.all(np.isfinite(f)):
            raise ModelError(f"{where}: measured frequencies {np.flatnonzero(~np.isfinite(f)).tolist()} (0-based) are "
                             "NaN or infinite; remove those modes or fix the identification")
        if np.any(f <= 0):
            raise ModelError(f"{where}: measured frequencies must be > 0 (rigid-body modes at 0 Hz carry no "
                             "information for updating; leave them out)")
        object.__setattr__(self, "frequencies_hz", f)
        if self.shapes is not None:
            s = np.asarray(self.shapes)
            if s.ndim != 2 or s.shape[0] != len(f):
                raise ModelError(f"{where}: shapes must be (n_modes={len(f)}, n_sensors), got {s.shape}")
            if not np.all(np.isfinite(s)):
                raise ModelError(f"{where}: the measured shapes contain NaN or infinity (mode(s) "
                                 f"{np.flatnonzero(~np.all(np.isfinite(s), axis=1)).tolist()}); fix or drop them")
            if self.sensors is None:
                raise ModelError(f"{where}: measured shapes need their sensors (flexgvt.correlation.Sensors)")
            if len(self.sensors) != s.shape[1]:
                raise ModelError(f"{where}: {s.shape[1]} shape components but {len(self.sensors)} sensors")
            object.__setattr__(self, "shapes", s)
        if self.frequency_std_hz is not None:
            sd = np.asarray(self.frequency_std_hz, float)
            if sd.shape != f.shape or not np.all(np.isfinite(sd)) or np.any(sd < 0):
                raise ModelError(f"{where}: frequency_std_hz must be {len(f)} finite values >= 0")
            object.__setattr__(self, "frequency_std_hz", sd)
        if self.observed_by is not None and not 0.0 < self.visibility < 1.0:
            raise ModelError(f"{where}: visibility={self.visibility} must lie in (0, 1)")
        for key, value in self.static.items():
            if not np.isfinite(value):
                raise ModelError(f"{where}: static deflection at {key} is not finite")

    @classmethod
    def from_modal_set(cls, configuration: str, modal_set: ModalSet, sensors=None, **kwargs) -> "Measured":
        """From a ModalSet (identified by flexgvt.ema or read by flexgvt.workflow.read_modes): its DOFs
        give the sensors unless given."""
        if sensors is None and modal_set.shapes is not None:
            from ..correlation import Sensors
            sensors = Sensors.from_outputs(modal_set.dofs)
        kwargs.setdefault("labels", modal_set.labels)
        return cls(configuration, modal_set.frequencies_hz, modal_set.shapes, sensors,
                   frequency_std_hz=modal_set.frequency_std_hz, **kwargs)

    @property
    def modal_set(self) -> ModalSet:
        """The measured modes as a ModalSet (DOFs: the sensors' (node, direction code)); the targets and
        weights (static deflections, observed_by, visibility) are what Measured adds to it."""
        dofs = None if self.sensors is None or self.shapes is None else self.sensors.dofs
        return ModalSet(self.frequencies_hz, None, self.shapes, dofs=dofs, frequency_std_hz=self.frequency_std_hz,
                        labels=self.labels, name=self.configuration)


@dataclass(frozen=True)
class MassTarget:
    """Measured mass properties of the undeformed structure (None: not measured).

    mass [kg]; cg (3,) [m]; inertia (3,) Ixx, Iyy, Izz about the cg [kg m^2]. A cg error is
    divided by the model's rms mass spread about its cg along that axis, at least cg_scale [m]."""

    mass: float | None = setting(None, "measured mass", unit="kg", gt=0)
    cg: tuple | None = setting(None, "measured centre of gravity (x, y, z)", unit="m", size=3)
    inertia: tuple | None = setting(None, "measured Ixx, Iyy, Izz about the cg", unit="kg m^2", gt=0, size=3)
    cg_scale: float = setting(0.01, "smallest length a cg error is divided by (the model's mass spread along "
                                "that axis, at least this)", unit="m", gt=0)


@dataclass(frozen=True)
class Objective:
    """Weights and limits of the updating objective (each term on when its data exist).

    frequency, mac, mass, cg, inertia, static, orthogonality: weights of the residual groups (each
    residual is a relative error; a MAC residual is 1 - MAC; the cross-orthogonality residuals are
    XOR - I over the paired modes, XOR through the SEREP mass of the paired analytical modes). mac_min: pairs below
    it violate a constraint
    (SLSQP, trust-constr) or are penalised (least squares, Nelder-Mead); mass_limits: relative
    band the mass properties must stay in (e.g. 0.1 = +-10 %); use_std: weight frequency errors
    by the measured standard deviations when given (relative scatter over the median's);
    mac_floor: pairs below it are not made; max_frequency_ratio: modes farther apart in frequency
    than this factor are not paired (see flexgvt.correlation.pair)."""

    frequency: float = setting(1.0, "weight of the relative frequency errors", ge=0)
    mac: float = setting(0.0, "weight of 1 - MAC of the paired modes", ge=0)
    mass: float = setting(1.0, "weight of the relative mass error", ge=0)
    cg: float = setting(1.0, "weight of the cg errors", ge=0)
    inertia: float = setting(1.0, "weight of the relative inertia errors", ge=0)
    static: float = setting(0.0, "weight of the relative static deflection errors", ge=0)
    mac_min: float | None = setting(None, "pairs below this MAC violate a constraint (slsqp, trust-constr) or are "
                                    "penalised", ge=0, le=1)
    mass_limits: float | None = setting(None, "relative band the mass properties must stay in (0.1: +-10 %; a cg "
                                        "coordinate: 10 % of the mass spread along its axis)", gt=0)
    use_std: bool = setting(True, "weight frequency errors by the measured standard deviations when given")
    mac_floor: float = setting(0.5, "pairing: pairs below this MAC are not made", ge=0, le=1)
    max_frequency_ratio: float | None = setting(2.0, "pairing: modes farther apart in frequency than this factor "
                                                "are not paired", gt=1)
    orthogonality: float = setting(0.0, "weight of the cross-orthogonality residuals XOR - I", ge=0)
    prior: str = setting("none", "none: least squares on the test data alone; bounds: the most probable point "
                         "of the posterior (MAP): each variable also carries a Gaussian prior about its "
                         "initial value with the variance of a uniform distribution over its bounds, "
                         "weighed against the data by the measured frequency standard deviations, so "
                         "directions the data hardly see stay near the initial model instead of wandering",
                         choices=("none", "bounds"))

    def __post_init__(self) -> None:
        check_settings(self, "objective")
