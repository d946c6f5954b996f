"""The project file's schema (pydantic): every table and key a project.toml may hold.

Unknown keys are errors (a typo never silently drops a setting). Quantities are SI numbers or
strings with units ("17.6 N/m"), checked against the dimension the key expects.
"""

from __future__ import annotations

from dataclasses import MISSING
from typing import Annotated, Any, Literal, get_args, get_origin, get_type_hints

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field, create_model, model_validator

from ..updating import MassTarget, Objective, OptimiserSettings, UncertaintySettings
from ..updating.settings import described
from .plansettings import PlanSettings
from .units import DIMENSIONS, quantity, unit_dimensions, unit_system


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
    """What the project is (shown in the report)."""

    name: str = Field("flexgvt project", description="title of the project")
    description: str = Field("", description="one line on what is tested and updated")


def _unit_system(value):
    unit_system(value, "")  # ModelError (a ValueError) with the reason; the location comes from pydantic
    return value


class ModelSpec(Strict):
    """The structure: a built-in case (flexgvt.cases) or a Nastran deck (one of the two)."""

    case: str | None = None
    options: dict[str, int | float | bool | str | dict[str, float | list[float]]] = Field(
        default_factory=dict, description="a built-in case's keyword arguments (a table of numbers for one that "
                                          "takes a dict, e.g. properties = {pendulum_length = 6.0}); "
                                    'with bdf: unsupported = "warn" (read the rest of a deck holding cards flexgvt '
                                    "does not read, and list them)")
    bdf: str | None = None
    units: Annotated[Any, AfterValidator(_unit_system)] = Field(
        "SI", description='the deck\'s unit system: "SI" ("m-kg-s"), "mm-N-t-s" ("mm-t-s"), "in-lbf-s", '
        '"ft-lbf-s", or a table {length = "mm", force = "N"} / {length = "mm", mass = "t", time = "s"}')

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
    name: str = Field("", description="how a mass variable names it (the shaker's moving mass is \"shaker\")")


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
    """Measured data of a configuration: FRFs to identify (UFF 58), time histories to estimate them from
    (UFF 58 type 1) or identified modes (UFF 55/2414, CSV, JSON)."""

    __test__ = False

    frfs: str | list[str] | None = Field(None, description="UFF file(s) of FRFs (dataset 58) to identify")
    time: str | None = Field(None, description="UFF file of simultaneous time histories (dataset 58, function "
                             "type 1): FRFs are estimated from them, then identified")
    references: list[str] | None = Field(None, description='with time: the force channels as POINT+DIRECTION '
                                         '(["100+Z"]); default: those the file marks as forces')
    estimator: Literal["H1", "H2", "Hv"] = Field("H1", description="with time: the FRF estimator (H2 and Hv: one "
                                                 "reference)")
    nperseg: int | None = Field(None, ge=8, description="with time: samples per averaged (Hann, 50 % overlap) "
                                "block; default the whole record")
    drop_incomplete: bool = Field(False, description="leave out the FRF channels (responses, or a reference) "
                                  "whose matrix is incomplete; the run's log and results say which")
    modes: str | None = Field(None, description="identified modes (UFF 55 or 2414, CSV or JSON) instead of FRFs")
    key: str | None = Field(None, description="the sub-object of a modes JSON holding them (dotted for nesting)")
    points: str = Field("nodes", description='test point -> FE node: "nodes" (same ids), "case" (the built-in '
                        "case's sensors) or a CSV file point,node,dx,dy,dz [m]")
    band_hz: Annotated[list[Frequency], Field(min_length=2, max_length=2)] | None = Field(
        None, description="identification band [low, high]", json_schema_extra={"unit": "Hz"})
    max_order: int = Field(60, ge=4, le=400, description="highest PolyMAX model order of the stabilisation diagram")
    select_hz: list[Frequency] | None = Field(None, description="pick the poles nearest these frequencies instead "
                                              "of the automatic selection", json_schema_extra={"unit": "Hz"})
    min_fraction: float = Field(0.3, gt=0, le=1, description="automatic selection: a pole stable in at least this "
                                "fraction of the orders")
    refine: bool = Field(True, description="maximum-likelihood refinement (frequency and damping uncertainties)")
    wide: bool = Field(False, description="identify a wide band in overlapping sub-bands")
    use_modes: list[int] | None = Field(None, description="keep only these identified modes (1-based)")
    labels: list[str] | None = Field(None, description="names of the kept modes for the tables")

    @model_validator(mode="after")
    def _one_kind(self):
        if [self.frfs, self.time, self.modes].count(None) != 2:
            raise ValueError("give one of 'frfs' (UFF FRFs to identify), 'time' (UFF time histories to estimate "
                             "FRFs from) or 'modes' (modes already identified)")
        if self.time is None:
            given = [k for k in ("references", "nperseg") if getattr(self, k) is not None]
            given += ["estimator"] if self.estimator != "H1" else []
            if given:
                raise ValueError(f"{', '.join(repr(k) for k in given)} apply to FRFs estimated from time histories: "
                                 "give 'time' (a UFF file of time histories) or remove them")
        if self.modes is not None and self.drop_incomplete:
            raise ValueError("'drop_incomplete' applies to FRFs ('frfs' or 'time'), not to identified 'modes'")
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
    """A design variable (flexgvt.updating.Variable): targets are beam or shell group, mass or spring names
    or patterns (positions of masses and springs still work, deprecated), or indices of cords; ids:
    mass or spring ids (a deck's CONM2, CELAS or CBUSH EIDs)."""

    name: str
    kind: Literal["beam", "mass", "spring", "cord", "shell"]
    targets: list[str | int] = Field(default_factory=list)
    ids: list[int] = Field(default_factory=list)
    attribute: str
    bounds: Annotated[list[float], Field(min_length=2, max_length=2)] | None = None  # None: the kind's default
    configurations: list[str] | None = None


def _dimension(unit: str) -> str:
    """The DIMENSIONS name of an SI unit ('kg m^2' -> 'inertia')."""
    dims = unit_dimensions(unit)
    return next(name for name, d in DIMENSIONS.items() if d == dims)


def settings_table(cls: type, name: str, **extra: Any) -> type[BaseModel]:
    """A project-file table generated from the settings dataclass ``cls``: one key per described field
    (flexgvt.updating.settings.setting) with its type, default, limits, choices, unit (strings with
    units accepted) and description; ``extra``: further keys as (type, FieldInfo)."""
    hints = get_type_hints(cls)
    keys: dict[str, Any] = {}
    for f in described(cls):
        md = f.metadata
        kind = hints[f.name]
        optional = f.default is None
        varying = _variable_tuple(kind)  # tuple[x, ...]: a list of any length, limits on its items
        if md["choices"] is not None:
            kind = Literal[md["choices"]]
        elif md["unit"] or md["size"]:
            item = _q(_dimension(md["unit"])) if md["unit"] else float
            if md["size"] or varying:
                item = Annotated[item, Field(**{k: md[k] for k in ("ge", "gt", "le") if md[k] is not None})]
                item = Annotated[list[item], Field(min_length=md["size"], max_length=md["size"])] if md["size"] \
                    else list[item]
            kind = item | None if optional else item
        elif varying:
            kind = _listed(kind)
        limits = {} if md["size"] or varying else {k: md[k] for k in ("ge", "gt", "le") if md[k] is not None}
        default = f.default if f.default is not MISSING else ...
        if varying and isinstance(default, tuple):
            default = [list(v) if isinstance(v, tuple) else v for v in default]  # as the project file writes it
        keys[f.name] = (kind, Field(default, description=md["doc"], json_schema_extra={"unit": md["unit"]},
                                    **limits))
    return create_model(name, __base__=Strict, __doc__=cls.__doc__, **keys, **extra)


def _variable_tuple(kind: Any) -> bool:
    """Whether ``kind`` is tuple[x, ...] (a setting holding any number of values)."""
    return get_origin(kind) is tuple and get_args(kind)[-1:] == (Ellipsis,)


def _listed(kind: Any) -> Any:
    """tuple[x, ...] as list[x], nested ones too (the project file writes lists)."""
    return list[_listed(get_args(kind)[0])] if _variable_tuple(kind) else kind


def _into(cls: type):
    """Validated table -> the settings dataclass ``cls`` (lists as tuples)."""
    return AfterValidator(lambda t: cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in dict(t).items()}))


MassTargetSpec = settings_table(MassTarget, "MassTargetSpec")
ObjectiveSpec = settings_table(Objective, "ObjectiveSpec", measured_mass=(
    Annotated[MassTargetSpec, _into(MassTarget)] | None,
    Field(None, description="measured mass properties ([objective.measured_mass])")))
OptimiserSpec = settings_table(OptimiserSettings, "OptimiserSpec")
PlanSpec = settings_table(PlanSettings, "PlanSpec")
UncertaintySpec = settings_table(UncertaintySettings, "UncertaintySpec")


def _method_only(value: Any) -> Any:
    """``uncertainty = "mcmc"`` as the table's method alone."""
    return {"method": value} if isinstance(value, str) else value


class PredictionSpec(Strict):
    """Free-flying prediction: the suspension removed (free-free) and the ``proposed`` configurations
    (e.g. long bungees) of the model; ``reference``: a JSON of known frequencies to score against."""

    free_free: bool = Field(True, description="predict the free-free modes (suspension removed)")
    proposed: list[str] = Field(default_factory=list, description="the model's configurations to predict "
                                "(e.g. long bungees)")
    n_modes: int = Field(10, ge=1, le=100, description="free-free modes predicted")
    reference: str | None = Field(None, description="JSON of known free-free frequencies to score against")
    uncertainty: Annotated[UncertaintySpec, BeforeValidator(_method_only), _into(UncertaintySettings)] = Field(
        default_factory=UncertaintySettings, description="confidence bounds of the predicted frequencies: "
        "[prediction.uncertainty], or its method alone (uncertainty = \"mcmc\")")


class OutputSpec(Strict):
    """Where results go: ``directory`` (relative to the project file) must stay inside the project
    folder unless ``allow_outside`` is set."""

    directory: str = Field("results", description="output folder, relative to the project file")
    allow_outside: bool = Field(False, description="let ``directory`` point outside the project folder")
    report: bool = Field(True, description="write report.html (flexgvt run)")
    bdf: bool = Field(True, description="write the updated model as updated.bdf")
    uff: bool = Field(True, description="write identified and predicted modes as UFF 55")


class StageSpec(Strict):
    """One stage of a staged updating ([[stages]], run in order): its configurations, design variables
    and bounds, fixed inputs and settings; it starts from the model the previous stage produced."""

    name: str = Field(min_length=1, description="the stage's name (report, results.json, store)")
    description: str = Field("", description="one line on what the stage tests and updates")
    configurations: list[str | ConfigurationSpec] = Field(
        default_factory=list, description="the configurations updated on in this stage: names of [[configurations]] "
        "or its own [[stages.configurations]] tables (as [[configurations]])")
    variables: list[str | VariableSpec] = Field(
        default_factory=list, description="the design variables of this stage: names of [[variables]] or its own "
        "[[stages.variables]] tables (as [[variables]])")
    bounds: dict[str, Annotated[list[float], Field(min_length=2, max_length=2)]] = Field(
        default_factory=dict, description="this stage's normalised bounds of named variables, e.g. "
        "{ E = [0.9, 1.1] } (default: the variable's own)")
    recentre: bool = Field(True, description="true: the bounds multiply the values the stage starts from (carried "
                           "from the previous stage); false: they multiply the project's initial model's values")
    set: dict[str, float | str] = Field(
        default_factory=dict, description="fixed inputs set before the stage updates (component tests: a tip-load "
        "modulus, a weighed density): variable name -> the value of its attribute (SI, or a string with a unit), "
        "e.g. { E_spar = \"45 GPa\" }")
    objective: ObjectiveSpec | None = Field(None, description="this stage's [objective] keys (the others as "
                                            "[objective]); e.g. its measured_mass (weights)")
    optimiser: OptimiserSpec | None = Field(None, description="this stage's [optimiser] keys (the others as "
                                            "[optimiser])")


class ProjectFile(Strict):
    """The whole project file."""

    project: ProjectInfo = Field(default_factory=ProjectInfo)
    model: ModelSpec
    configurations: list[ConfigurationSpec] = Field(min_length=1)
    suspension_tests: list[BlockTest] = Field(default_factory=list)
    variables: list[VariableSpec] = Field(default_factory=list)
    objective: ObjectiveSpec = Field(default_factory=ObjectiveSpec)
    optimiser: Annotated[OptimiserSpec, _into(OptimiserSettings)] = Field(default_factory=OptimiserSettings)
    prediction: PredictionSpec = Field(default_factory=PredictionSpec)
    plan: Annotated[PlanSpec, _into(PlanSettings)] = Field(default_factory=PlanSettings)
    outputs: OutputSpec = Field(default_factory=OutputSpec)
    stages: list[StageSpec] = Field(default_factory=list, description="staged updating, in order (none: one "
                                    "stage, the configurations with role \"update\" and every [[variables]])")
