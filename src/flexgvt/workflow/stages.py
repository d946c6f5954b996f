"""Staged updating: the project file's [[stages]], run in order, each starting from the model the
previous stage produced.

A stage names the configurations it updates on (names of [[configurations]], or its own tables),
its design variables (names of [[variables]], or its own tables) with this stage's bounds, fixed
inputs it sets first (component tests: a tip-load modulus, a weighed density) and its own
[objective] / [optimiser] keys (e.g. the measured mass properties of a weighing). Normalised
values and bounds are about the values the stage starts from (recentre = true, the default) or
about the project's initial model (recentre = false). A project without [[stages]] is one stage:
the configurations with role "update" and every [[variables]] (the runner's single-stage path).

The runner (flexgvt.workflow.run) orders the stages; this module resolves and checks them, builds
each stage's view of the project (flexgvt.workflow.Project with the stage's start model,
configurations, variables, objective and optimiser: every step function takes it as it is) and
holds what a stage produced (StageResult).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import ModelError
from ..model import Configuration, Model
from ..updating import OptimiserSettings, Parametrisation, Variable
from .projectbase import Project, ProjectError
from .schema import ConfigurationSpec, ObjectiveSpec, ProjectFile, StageSpec, VariableSpec
from .units import DIMENSIONS, quantity

# The dimension of a variable attribute's value, for a fixed input given with a unit (by kind, attribute).
_DIMENSION = {"E": "modulus", "G": "modulus", "rho": "density", "mass": "mass", "offset_x": "length",
              "offset_y": "length", "offset_z": "length", "along": "length", "width": "length", "height": "length",
              "thickness": "length", "outer_radius": "length", "inner_radius": "length",
              **{f"k{i}": "stiffness" for i in (1, 2, 3)}, **{f"k{i}": "rotational_stiffness" for i in (4, 5, 6)}}


@dataclass(frozen=True)
class Stage:
    """One resolved stage: index (0-based), name, description; configurations: those it updates on;
    variables: its design variables with this stage's bounds (normalised about its start when
    recentre, else about the project's initial model); values: fixed inputs {variable name: SI value}
    set before it updates, fixed: their variables; objective, optimiser: its settings (the project's
    with the stage's keys over them)."""

    index: int
    name: str
    description: str
    configurations: tuple[str, ...]
    variables: tuple[Variable, ...]
    recentre: bool
    values: dict
    fixed: tuple[Variable, ...]
    objective: Any
    optimiser: OptimiserSettings

    @property
    def updates(self) -> bool:
        """Whether the stage updates (it has variables and data: configurations or mass properties)."""
        return bool(self.variables)


@dataclass
class StageResult:
    """What one stage produced: its view of the project (the model and configurations it started
    from, its variables and settings), the UpdateResult (None for a stage of fixed inputs only), the
    model and every configuration after it, the fixed inputs' rows, whether it resumed from the store."""

    stage: Stage
    project: Project
    update: object | None
    model: Model
    configurations: dict[str, Configuration]
    fixed: list[dict] = field(default_factory=list)
    resumed: bool = False
    seconds: float = 0.0

    def to_dict(self) -> dict:
        """The stage's entry of results.json's ``stages`` list."""
        s, up = self.stage, self.update
        out = {"name": s.name, "description": s.description, "configurations": list(s.configurations),
               "recentre": s.recentre, "fixed_inputs": self.fixed, "resumed": self.resumed, "seconds": self.seconds}
        if up is None:
            out.update(variables=[], frequencies={}, objective=None, iterations=0, message="fixed inputs only")
            return out
        out.update(variables=[{k: r.get(k) for k in ("name", "kind", "attribute", "initial", "final", "x",
                                                     "change_percent", "lower", "upper", "std", "std_percent",
                                                     "at_bound", "identifiable", "fixed", "reason")}
                              for r in up.variables],
                   frequencies=up.tables, objective={"initial": up.initial.objective, "final": up.final.objective},
                   iterations=len(up.history) - 1, message=str(up.message), success=bool(up.success),
                   method=up.method, solves=up.solves, mass_properties=mass_rows(s, up))
        return out


def mass_rows(stage: Stage, update) -> list[dict]:
    """The measured mass properties of a stage's objective against the model it started from and the
    one it produced: one row per measured value (mass [kg], cg [m], Ixx/Iyy/Izz about the cg [kg m^2]),
    errors in the value's unit and, except for the cg (whose coordinates depend on the origin), in %."""
    target = stage.objective.measured_mass
    if target is None or update is None:
        return []
    a, b = update.initial.mass_properties, update.final.mass_properties
    if a is None or b is None:
        return []
    rows = []

    def add(name, measured, initial, final, relative=True):
        rows.append({"property": name, "measured": float(measured), "initial": float(initial),
                     "updated": float(final), "initial_error": float(initial - measured),
                     "updated_error": float(final - measured),
                     "initial_error_percent": 100 * (initial - measured) / measured if measured and relative else None,
                     "updated_error_percent": 100 * (final - measured) / measured if measured and relative else None})
    if target.mass is not None:
        add("mass [kg]", target.mass, a.mass, b.mass)
    for k, c in enumerate(target.cg or ()):  # a cg coordinate depends on the origin: its error in m only
        add(f"cg {'xyz'[k]} [m]", c, a.cg[k], b.cg[k], relative=False)
    for k, i in enumerate(target.inertia or ()):
        add(f"I{'xyz'[k] * 2} [kg m^2]", i, a.inertia[k, k], b.inertia[k, k])
    return rows


def flatten(spec: ProjectFile, where: str) -> ProjectFile:
    """The spec with every stage's own [[stages.configurations]] appended to [[configurations]] and
    named in the stage instead (so identification, checks and the report see them as any other)."""
    if not spec.stages:
        return spec
    names = [c.name for c in spec.configurations]
    extra: list[ConfigurationSpec] = []
    stages = []
    for i, st in enumerate(spec.stages):
        listed = []
        for j, c in enumerate(st.configurations):
            if isinstance(c, ConfigurationSpec):
                if c.name in names:
                    raise ProjectError(f"{where}: stages[{i}] ('{st.name}').configurations[{j}]: a configuration "
                                       f"'{c.name}' is defined already; give the stage's own one another name, or "
                                       "name the existing one (configurations = [\"...\"])")
                if c.role != "update":
                    raise ProjectError(f"{where}: stages[{i}] ('{st.name}').configurations[{j}] ('{c.name}'): a "
                                       "stage's own configuration is updated on; remove role = \"check\" (define a "
                                       "check configuration under [[configurations]])")
                names.append(c.name)
                extra.append(c)
                listed.append(c.name)
            else:
                listed.append(c)
        stages.append(st.model_copy(update={"configurations": listed}))
    return spec.model_copy(update={"configurations": list(spec.configurations) + extra, "stages": stages})


def _merged_objective(top: ObjectiveSpec, own: ObjectiveSpec | None) -> ObjectiveSpec:
    return top if own is None else top.model_copy(update={k: getattr(own, k) for k in own.model_fields_set})


def _merged_optimiser(top: OptimiserSettings, own) -> OptimiserSettings:
    return top if own is None else replace(top, **{k: getattr(own, k) for k in own.model_fields_set})


def resolve_stages(spec: ProjectFile, model: Model, configurations: dict[str, Configuration],
                   variables: list[Variable], where: str) -> list[Stage]:
    """The checked stages of a flattened spec (see flatten); ProjectError naming the stage and key for an
    empty stage, an unknown configuration or variable, a variable not in the model, bad bounds or values."""
    if not spec.stages:
        return []
    names = [s.name for s in spec.stages]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ProjectError(f"{where}: stages: names must be unique; repeated: {dup}")
    defined = {v.name: v for v in variables}
    roles = {c.name: c.role for c in spec.configurations}
    used: set[str] = set()
    out = []
    for i, st in enumerate(spec.stages):
        loc = f"{where}: stages[{i}] ('{st.name}')"
        listed = [str(c) for c in st.configurations]
        for j, name in enumerate(listed):
            if name not in roles:
                raise ProjectError(f"{loc}.configurations[{j}]: no configuration '{name}'; the project defines "
                                   f"{sorted(roles)}")
            if roles[name] != "update":
                raise ProjectError(f"{loc}.configurations[{j}]: configuration '{name}' has role = \"check\" (only "
                                   "compared, never updated on); remove its role to update on it in this stage")
            if listed.count(name) > 1:
                raise ProjectError(f"{loc}.configurations: '{name}' is named twice")
        used |= set(listed)
        own: list[Variable] = []
        for j, v in enumerate(st.variables):
            if isinstance(v, VariableSpec):
                if v.name in defined:
                    raise ProjectError(f"{loc}.variables[{j}]: a variable '{v.name}' is defined under [[variables]] "
                                       "already; name it (variables = [\"...\"]) or give this one another name")
                own.append(variable_of(v, f"{loc}.variables[{j}] ('{v.name}')", where))
            elif v in defined:
                own.append(defined[v])
            else:
                raise ProjectError(f"{loc}.variables[{j}]: no variable '{v}'; [[variables]] defines "
                                   f"{sorted(defined) or 'none'} (or give the stage its own [[stages.variables]])")
        vnames = [v.name for v in own]
        twice = sorted({n for n in vnames if vnames.count(n) > 1})
        if twice:
            raise ProjectError(f"{loc}.variables: named twice: {twice}")
        for name, b in st.bounds.items():
            if name not in vnames:
                raise ProjectError(f"{loc}.bounds.{name}: '{name}' is not a variable of this stage ({vnames})")
            try:
                own[vnames.index(name)] = replace(own[vnames.index(name)], bounds=tuple(b))
            except ModelError as exc:
                raise ProjectError(f"{loc}.bounds.{name}: {exc}") from None
        objective = _merged_objective(spec.objective, st.objective)
        optimiser = _merged_optimiser(spec.optimiser, st.optimiser)
        target = objective.measured_mass
        has_mass = target is not None and any(getattr(target, k) is not None for k in ("mass", "cg", "inertia"))
        if own and not listed and not has_mass:
            raise ProjectError(f"{loc}: variables {vnames} but nothing to update them on: name the configurations "
                               "(configurations = [...]) or give measured mass properties "
                               "([stages.objective.measured_mass])")
        if not listed and not has_mass and not st.set:
            raise ProjectError(f"{loc}: an empty stage: give the configurations it updates on (configurations = "
                               "[...]), measured mass properties ([stages.objective.measured_mass]) or fixed inputs "
                               "(set = {...})")
        if (listed or has_mass) and not own:
            raise ProjectError(f"{loc}.variables: no design variable to update on its data; name some (variables = "
                               "[...]) or leave the stage's data out")
        stage_configs = [configurations[n] for n in listed]
        if own:
            try:
                Parametrisation(model, stage_configs, own)
            except ModelError as exc:
                raise ProjectError(f"{loc}.variables: {exc}") from None
        values, fixed = _fixed_inputs(st, defined, own, model, configurations, loc)
        out.append(Stage(i, st.name, st.description, tuple(listed), tuple(own), st.recentre, values, fixed,
                         objective, optimiser))
    idle = [n for n, r in roles.items() if r == "update" and n not in used]
    if idle:
        raise ProjectError(f"{where}: configurations {idle} are updated on by no stage: name them in a stage's "
                           "configurations, or set their role = \"check\" to only compare them")
    return out


def variable_of(v: VariableSpec, loc: str, where: str) -> Variable:
    """The flexgvt.updating.Variable of a [[variables]] table (loc: its key, for the message)."""
    from ..updating.settings import renamed
    if v.kind in ("mass", "spring") and any(isinstance(t, int) for t in v.targets):
        renamed(f"{loc}: {v.kind} targets by position", "their names (targets = [\"name\"]) or ids (ids = [...])", 5)
    try:
        attribute = "height" if v.kind == "beam" and v.attribute == "thickness" else v.attribute  # a strip's
        return Variable(v.name, v.kind, attribute, tuple(v.targets),
                        None if v.bounds is None else tuple(v.bounds),
                        configurations=None if v.configurations is None else tuple(v.configurations),
                        ids=tuple(v.ids))
    except ModelError as exc:
        raise ProjectError(f"{loc}: {exc}") from None


def _fixed_inputs(st: StageSpec, defined: dict, own: list[Variable], model: Model, configurations: dict,
                  loc: str) -> tuple[dict, tuple[Variable, ...]]:
    """({variable: SI value}, their variables) of a stage's ``set`` table, each checked on the model."""
    mine = {v.name: v for v in own}
    values, fixed = {}, []
    for name, value in st.set.items():
        var = mine.get(name) or defined.get(name)
        key = f"{loc}.set.{name}"
        if var is None:
            raise ProjectError(f"{key}: no variable '{name}' (the fixed inputs are set through a variable's targets "
                               f"and attribute); defined: {sorted({*defined, *mine})}")
        if isinstance(value, str):
            dim = _DIMENSION.get(var.attribute)
            if var.kind in ("spring", "cord") and var.attribute == "stiffness":
                dim = "stiffness"
            if dim is None or dim not in DIMENSIONS:
                raise ProjectError(f"{key}: give the {var.kind} {var.attribute} as an SI number (no unit is known "
                                   "for it)")
            try:
                value = quantity(value, dim)
            except ModelError as exc:
                raise ProjectError(f"{key}: {exc}") from None
        if not np.isfinite(value):
            raise ProjectError(f"{key}: {value!r} must be a finite number")
        try:
            par = Parametrisation(model, list(configurations.values()), [var])
        except ModelError as exc:
            raise ProjectError(f"{key}: {exc}") from None
        if not var.shifts and not value > 0:
            raise ProjectError(f"{key}: {value!r} must be > 0 (it scales a physical property)")
        if not var.shifts and not np.mean(par.bindings[0].initial):
            raise ProjectError(f"{key}: the targets of '{name}' are 0 in the model, so a value cannot scale them")
        values[name] = float(value)
        fixed.append(var)
    return values, tuple(fixed)


def apply_fixed(stage: Stage, model: Model, configurations: dict) -> tuple[Model, dict, list[dict]]:
    """The model and configurations with the stage's fixed inputs set (the mean of each variable's
    targets becomes its value; the targets keep their ratios), and a row per input."""
    if not stage.fixed:
        return model, configurations, []
    par = Parametrisation(model, list(configurations.values()), list(stage.fixed))
    x, rows = [], []
    for b in par.bindings:
        v, before = b.variable, float(np.mean(b.initial))
        value = stage.values[v.name]
        x.append(1.0 + (value - before) / v.scale if v.shifts else value / before)
        rows.append({"name": v.name, "kind": v.kind, "attribute": v.attribute, "before": before, "value": value,
                     "change_percent": 100 * (value - before) / before if before else None})
    new = model.copy(model.name)
    changed = par.apply(new, np.array(x))
    return new, {**configurations, **changed}, rows


def stage_variables(stage: Stage, project: Project, model: Model, configurations: dict) -> list[Variable]:
    """The stage's variables with bounds in its own normalised values (x = 1: the value it starts
    from): as given when recentre, else the bounds about the project's initial model converted
    (ProjectError when the start lies outside them)."""
    variables = list(stage.variables)
    if stage.recentre or not variables:
        return variables
    names = list(stage.configurations)
    initial = Parametrisation(project.model, [project.configurations[n] for n in names], variables)
    start = Parametrisation(model, [configurations[n] for n in names], variables)
    out = []
    for v, b0, b1 in zip(variables, initial.bindings, start.bindings):
        p0, p1 = float(np.mean(b0.initial)), float(np.mean(b1.initial))
        lo, hi = v.bounds
        if v.shifts:
            new = (lo + (p0 - p1) / v.scale, hi + (p0 - p1) / v.scale)
        else:
            new = (lo * p0 / p1, hi * p0 / p1)
        if not new[0] <= 1.0 <= new[1]:
            where = f"{project.path}: stages[{stage.index}] ('{stage.name}')"
            raise ProjectError(f"{where}: variable '{v.name}' starts at {p1:.6g} ({p1 / p0 if p0 else float('nan'):.4g}"
                               f" of the initial model's), outside its bounds {list(v.bounds)} about the initial "
                               "model (recentre = false): widen them, or set recentre = true to bound it about the "
                               "value it starts from")
        out.append(replace(v, bounds=new))
    return out


def stage_view(project: Project, stage: Stage, model: Model, configurations: dict) -> Project:
    """The project as the stage sees it: its start model and configurations, its variables (bounds in
    its own normalised values) and settings, its configurations the ones with role "update"."""
    specs = [c.model_copy(update={"role": "update" if c.name in stage.configurations else "check"})
             for c in project.spec.configurations]
    spec = project.spec.model_copy(update={"configurations": specs, "objective": stage.objective,
                                           "optimiser": stage.optimiser, "stages": []})
    return replace(project, spec=spec, model=model, configurations=dict(configurations),
                   variables=stage_variables(stage, project, model, configurations))


def start_digest(previous: str, stage: Stage, result: StageResult | None) -> str:
    """A digest of where a stage starts: the previous stage's digest and answer, and this stage's
    fixed inputs (a stage's store is discarded when it changes: its start model is not in the
    store's own key)."""
    h = hashlib.sha256(previous.encode())
    if result is not None and result.update is not None:
        h.update(json.dumps([result.stage.name, np.asarray(result.update.x, float).tolist()]).encode())
    h.update(json.dumps([stage.name, sorted(stage.values.items())]).encode())
    return h.hexdigest()[:20]
