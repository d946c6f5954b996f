"""The project file's schema (pydantic): every table and key a project.toml may hold.

Unknown keys are errors (a typo never silently drops a setting). Quantities are SI numbers or
strings with units ("17.6 N/m"), checked against the dimension the key expects.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from .units import quantity


def _q(dimension: str):
    return Annotated[float, BeforeValidator(lambda v: quantity(v, dimension))]


Mass = _q("mass")
Length = _q("length")
Frequency = _q("frequency")
Stiffness = _q("stiffness")
Damping = _q("damping")
Acceleration = _q("acceleration")
Vector3 = Annotated[list[Length], Field(min_length=3, max_length=3)]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class ProjectInfo(Strict):
    name: str = "flexgvt project"
    description: str = ""


class ModelSpec(Strict):
    """The structure: a built-in case (flexgvt.cases) or a Nastran deck (one of the two)."""

    case: str | None = None
    options: dict[str, int | float | bool | str] = Field(default_factory=dict)
    bdf: str | None = None
    units: str = "SI"

    @model_validator(mode="after")
    def _one_source(self):
        if (self.case is None) == (self.bdf is None):
            raise ValueError("give exactly one of 'case' (a built-in model) or 'bdf' (a Nastran deck)")
        return self


class BlockTest(Strict):
    """A suspension point characterised on a block (flexgvt.suspension.identify_block)."""

    name: str
    mass: Mass
    frequency_hz: Frequency | list[Frequency]
    damping_ratio: float | list[float]


class CordSpec(Strict):
    """A suspension cord: stiffness/damping given or from a block test; sized to carry ``carries``."""

    node: int
    anchor: Vector3
    block_test: str | None = None
    stiffness: Stiffness | None = None
    damping: Damping = 0.0
    unstretched_length: Length | None = None
    carries: Mass | None = None
    offset: Vector3 = Field(default_factory=lambda: [0.0, 0.0, 0.0])

    @model_validator(mode="after")
    def _complete(self):
        if (self.block_test is None) == (self.stiffness is None):
            raise ValueError("give the cord's 'stiffness' (and 'damping') or the 'block_test' that identified it, "
                             "not both")
        if (self.unstretched_length is None) == (self.carries is None):
            raise ValueError("give the cord's 'unstretched_length' or the mass it 'carries' at equilibrium")
        return self


class MassSpec(Strict):
    """An extra mass of this test only (a shaker's moving part, an adapter)."""

    node: int
    mass: Mass
    offset: Vector3 = Field(default_factory=lambda: [0.0, 0.0, 0.0])


Force = _q("force")
Moment = _q("moment")


class ForceSpec(Strict):
    """A nodal load of this test (fixed direction, scaled with the load factor like gravity)."""

    node: int
    force: Annotated[list[Force], Field(min_length=3, max_length=3)] = Field(default_factory=lambda: [0.0] * 3)
    moment: Annotated[list[Moment], Field(min_length=3, max_length=3)] = Field(default_factory=lambda: [0.0] * 3)


class ShakerSpec(Strict):
    """A shaker attached through a stinger: its moving mass at the node, and the components the
    stinger holds (a stiff stinger on a heavy shaker: the translations, "123")."""

    node: int
    mass: Mass = 0.0
    fixed: str = ""


class TestData(Strict):
    """Measured data of a configuration: FRFs to identify (UFF 58) or identified modes (UFF 55, CSV, JSON)."""

    __test__ = False

    frfs: str | list[str] | None = None
    modes: str | None = None
    key: str | None = None
    points: str = "nodes"
    band_hz: Annotated[list[Frequency], Field(min_length=2, max_length=2)] | None = None
    max_order: int = Field(60, ge=4, le=400)
    select_hz: list[Frequency] | None = None
    min_fraction: float = Field(0.3, gt=0, le=1)
    refine: bool = True
    wide: bool = False
    use_modes: list[int] | None = None
    labels: list[str] | None = None

    @model_validator(mode="after")
    def _one_kind(self):
        if (self.frfs is None) == (self.modes is None):
            raise ValueError("give 'frfs' (UFF files to identify) or 'modes' (modes already identified), one of them")
        return self


class ConfigurationSpec(Strict):
    """A test configuration: from the model's configuration ``from`` (a case's or a deck subcase),
    with its suspension, boundary conditions, extra masses and load factor set or changed here."""

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)

    name: str
    from_: str | None = Field(None, alias="from")
    role: Literal["update", "check"] = "update"
    gravity: float | None = None
    fixed: dict[str, str] | None = None
    cords: list[CordSpec] | None = None
    masses: list[MassSpec] = Field(default_factory=list)
    forces: list[ForceSpec] = Field(default_factory=list)
    shaker: ShakerSpec | None = None
    test: TestData | None = None


class VariableSpec(Strict):
    """A design variable (flexgvt.updating.Variable): targets are beam group names or patterns,
    or indices of masses, springs or cords."""

    name: str
    kind: Literal["beam", "mass", "spring", "cord"]
    targets: list[str | int] = Field(default_factory=list)
    attribute: str
    bounds: Annotated[list[float], Field(min_length=2, max_length=2)] = Field(default_factory=lambda: [0.9, 1.1])
    configurations: list[str] | None = None


class MassTargetSpec(Strict):
    mass: Mass | None = None
    cg: Vector3 | None = None
    inertia: Annotated[list[float], Field(min_length=3, max_length=3)] | None = None


class ObjectiveSpec(Strict):
    frequency: float = Field(1.0, ge=0)
    mac: float = Field(0.0, ge=0)
    mass: float = Field(1.0, ge=0)
    cg: float = Field(1.0, ge=0)
    inertia: float = Field(1.0, ge=0)
    orthogonality: float = Field(0.0, ge=0)
    mac_min: float | None = Field(None, ge=0, le=1)
    mac_floor: float = Field(0.5, ge=0, le=1)
    max_frequency_ratio: float | None = Field(2.0, gt=1)
    mass_limits: float | None = Field(None, gt=0)
    measured_mass: MassTargetSpec | None = None


class OptimiserSpec(Strict):
    method: Literal["least_squares", "lm", "dogbox", "trf", "slsqp", "trust-constr", "nelder-mead"] = "least_squares"
    starts: int = Field(1, ge=1, le=100)
    seed: int = 0
    max_iterations: int = Field(50, ge=1)
    tolerance: float = Field(1e-8, gt=0)
    n_modes: int | None = Field(None, ge=1)


class PredictionSpec(Strict):
    """Free-flying prediction: the suspension removed (free-free) and the ``proposed`` configurations
    (e.g. long bungees) of the model; ``reference``: a JSON of known frequencies to score against."""

    free_free: bool = True
    proposed: list[str] = Field(default_factory=list)
    n_modes: int = Field(10, ge=1, le=100)
    reference: str | None = None


class OutputSpec(Strict):
    """Where results go: ``directory`` (relative to the project file) must stay inside the project
    folder unless ``allow_outside`` is set."""

    directory: str = "results"
    allow_outside: bool = False
    report: bool = True
    bdf: bool = True
    uff: bool = True


class ProjectFile(Strict):
    """The whole project file."""

    project: ProjectInfo = Field(default_factory=ProjectInfo)
    model: ModelSpec
    configurations: list[ConfigurationSpec] = Field(min_length=1)
    suspension_tests: list[BlockTest] = Field(default_factory=list)
    variables: list[VariableSpec] = Field(default_factory=list)
    objective: ObjectiveSpec = Field(default_factory=ObjectiveSpec)
    optimiser: OptimiserSpec = Field(default_factory=OptimiserSpec)
    prediction: PredictionSpec = Field(default_factory=PredictionSpec)
    outputs: OutputSpec = Field(default_factory=OutputSpec)
