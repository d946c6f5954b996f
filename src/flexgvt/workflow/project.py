"""A project file read, validated and resolved into the model, configurations and variables it names.

    project = fg.workflow.load_project("project.toml")
    project.model, project.configurations, project.variables

Every check that can fail is done here, before any long computation: TOML syntax, unknown keys,
units, missing files, unknown configurations, block tests or model components, a configuration
to update without test data. Each error names the file and the offending key.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
from pydantic import ValidationError

from ..errors import FlexGVTError, ModelError
from ..model import ConcentratedMass, Configuration, Cord, Model, NodalLoad
from ..model.configuration import STANDARD_GRAVITY
from .deck import guyan_sets
from .projectbase import Project, ProjectError
from .schema import ConfigurationSpec, ProjectFile
from .stages import flatten, resolve_stages


def _loc(loc) -> str:
    """'configurations[0].test.frfs' from a pydantic location, without its internal union/validator tags."""
    out = ""
    for part in loc:
        if isinstance(part, str) and (not part.isidentifier() or part in _TYPE_TAGS):
            continue
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


_TYPE_TAGS = {"str", "int", "float", "bool", "list", "dict", "none"}
_EXPECTED = {"int": "an integer", "float": "a number", "string": "a string (text in quotes)",
             "bool": "true or false", "list": "a list [...]", "dict": "a table", "model": "a table"}


def _message(e: dict) -> str:
    """A pydantic error in the project's words: what was expected and what was given."""
    kind = e["type"].split("_")[0]
    if kind in _EXPECTED and e["type"].endswith(("_type", "_parsing", "_parsing_size", "_from_float")):
        given = repr(e.get("input"))
        return f"expected {_EXPECTED[kind]}, got {given[:60] + '...' if len(given) > 60 else given}"
    return e["msg"].removeprefix("Value error, ")


def load_project(path: str | Path, pretest: bool = False) -> Project:
    """Read and check a project file; raises ProjectError naming the file and key on any problem.
    pretest: for planning the test (`flexgvt plan`): test data are neither needed nor read, nor design variables."""
    from .validate import checked_path
    path = checked_path(Path("."), str(path), "flexgvt", "project file")
    try:
        if not path.is_file():
            raise ProjectError(f"{path}: project file not found")
        if path.stat().st_size > 10_000_000:
            raise ProjectError(f"{path}: larger than 10 MB; not a project file")
        raw = tomllib.loads(path.read_bytes().decode("utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise ProjectError(f"{path}: not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise ProjectError(f"{path}: not a text file (TOML is UTF-8 text)") from None
    except RecursionError:
        raise ProjectError(f"{path}: not valid TOML: nested too deeply") from None
    except OSError as exc:
        raise ProjectError(f"{path}: cannot be read ({exc.strerror})") from None
    try:
        spec = ProjectFile.model_validate(raw)
    except ValidationError as exc:
        problems: dict[str, list[str]] = {}
        for e in exc.errors():
            msg = _message(e)
            if e["type"] == "extra_forbidden":
                msg = "unknown key (check the spelling; `flexgvt init` writes every key with a comment)"
            where = problems.setdefault(_loc(e["loc"]) or "(top level)", [])
            if msg not in where:
                where.append(msg)
        lines = [f"{k}: {' or '.join(v)}" for k, v in problems.items()]
        if len(lines) == 1:
            raise ProjectError(f"{path}: {lines[0]}") from None
        raise ProjectError(f"{path}: {len(lines)} problems in the project file:\n" + "\n".join(
            "  " + s for s in lines)) from None
    return resolve(path, spec, pretest)


def _need_file(path: Path, where: str, what: str) -> Path:
    from .validate import need_file
    return need_file(path, where, what)


_DECK_OPTIONS = {"unsupported": ("error", "warn"), "mass": ("lumped", "consistent"),
                 "rotary_inertia": (True, False), "cbar_torsional_inertia": (True, False)}


def _read_deck(bdf: Path, spec, where: str):
    """read_bdf with the project's model.units and [model.options] (each checked; unknown keys are errors);
    the deck's warnings (cards not read, approximations) re-issued as FlexGVTWarnings naming the project."""
    import warnings

    from ..errors import FlexGVTWarning
    from ..io import read_bdf
    from ..io.nastran import Units, UnsupportedCardsError
    from .units import unit_system
    options = dict(spec.options)
    for key, value in options.items():
        if key not in _DECK_OPTIONS:
            raise ProjectError(f"{where}: model.options.{key}: unknown key for a deck; the keys are "
                               f"{', '.join(_DECK_OPTIONS)} (unsupported = \"warn\" reads a deck holding cards "
                               "flexgvt does not read)")
        allowed = _DECK_OPTIONS[key]
        if not any(value is v if isinstance(v, bool) else value == v for v in allowed):
            shown = " or ".join(str(v).lower() if isinstance(v, bool) else f'"{v}"' for v in allowed)
            raise ProjectError(f"{where}: model.options.{key}: {value!r} must be {shown}")
    try:
        units = Units(*unit_system(spec.units, f"{where}: model.units"))
    except ModelError as exc:
        raise ProjectError(str(exc)) from None
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            deck = read_bdf(bdf, units=units, **options)
    except UnsupportedCardsError as exc:
        text = str(exc).split(". Remove or replace them")[0]
        raise ProjectError(f"{where}: model.bdf: {text}. Remove or replace them, or set unsupported = \"warn\" "
                           "under [model.options] to read the rest (on the command line: flexgvt solve "
                           "--allow-unsupported)") from None
    except FlexGVTError as exc:
        raise ProjectError(f"{where}: model.bdf: {exc}") from None
    for w in caught:
        warnings.warn(f"{where}: model.bdf: {w.message}", FlexGVTWarning, stacklevel=3)
    sets = guyan_sets(deck)
    if sets:  # a design decision, said once: updating needs the full model's exact modes and sensitivities
        warnings.warn(f"{where}: model.bdf asks for Guyan reduction ({'/'.join(sets)}); a project identifies, "
                      "updates and predicts with the full model (exact modes and sensitivities, which the "
                      "reduction only approximates). `flexgvt solve` on the deck gives the reduced modes as "
                      "Nastran prints them", FlexGVTWarning, stacklevel=3)
    return deck


def resolve(path: Path, spec: ProjectFile, pretest: bool = False) -> Project:
    """Build the model, configurations and variables a validated spec names, checking every reference."""
    from .validate import check_test_data, checked_path, output_dir, read_reference
    folder = path.parent
    where = str(path)

    def rel(value: str, key: str) -> Path:  # key: "<project file>: <key>"
        return checked_path(folder, value, key, "file")

    output_dir(folder, spec.outputs.directory, spec.outputs.allow_outside, f"{where}: outputs.directory")
    spec = flatten(spec, where)
    case = deck = None
    if spec.model.case is not None:
        from .. import cases
        try:
            case = cases.get(spec.model.case, **spec.model.options)
        except TypeError as exc:
            raise ProjectError(f"{where}: model.options: {exc}") from None
        except ModelError as exc:
            raise ProjectError(f"{where}: model.case: {exc}") from None
        model, available = case.model, dict(case.configurations)
    else:
        bdf = _need_file(rel(spec.model.bdf, f"{where}: model.bdf"), f"{where}: model.bdf", "deck")
        deck = _read_deck(bdf, spec.model, where)
        model, available = deck.model, deck.configurations  # it also answers a labelled subcase's subcase_<id>

    names = [c.name for c in spec.configurations]
    for kind, items in (("configurations", names), ("variables", [v.name for v in spec.variables]),
                        ("suspension_tests", [b.name for b in spec.suspension_tests])):
        dup = sorted({n for n in items if items.count(n) > 1})
        if dup:
            raise ProjectError(f"{where}: {kind}: names must be unique; repeated: {dup}")
    blocks = {b.name: b for b in spec.suspension_tests}
    for k, b in enumerate(spec.suspension_tests):
        try:
            block_point(b)
        except FlexGVTError as exc:
            raise ProjectError(f"{where}: suspension_tests[{k}] ('{b.name}'): {exc}") from None
    configurations, sensors = {}, {}
    for k, c in enumerate(spec.configurations):
        loc = f"{where}: configurations[{k}] ('{c.name}')"
        configurations[c.name] = _configuration(c, available, blocks, model, loc)
        if c.role == "update" and c.test is None and not pretest:
            raise ProjectError(f"{loc}: no test data: add a [configurations.test] table with 'frfs', 'time' or "
                               "'modes', or set role = \"check\" to only predict this configuration")
        if c.test is not None and not pretest:  # planning comes before the test: its files need not exist
            t = c.test
            for key, files in (("frfs", t.frfs), ("modes", t.modes)):
                for f in ([files] if isinstance(files, str) else files or []):
                    _need_file(rel(f, f"{loc}.test.{key}"), f"{loc}.test.{key}", "test data file")
            sensors[c.name] = _points(t.points, case, model, lambda s, loc=loc: rel(s, f"{loc}.test.points"),
                                      f"{loc}.test.points")
    if not spec.variables and not spec.stages and not pretest and any(c.role == "update" for c in spec.configurations):
        raise ProjectError(f"{where}: variables: no design variable; add [[variables]] tables (or set every "
                           "configuration's role = \"check\" to only compare and predict)")
    variables = _variables(spec, model, configurations, where)
    for k, name in enumerate(spec.prediction.proposed):
        if name not in available and name not in configurations:
            raise ProjectError(f"{where}: prediction.proposed[{k}]: no configuration '{name}'; the model defines "
                               f"{sorted(available)}, the project {names}")
    if spec.prediction.reference is not None:
        key = f"{where}: prediction.reference"
        read_reference(_need_file(rel(spec.prediction.reference, key), key, "reference file"), key)
    stages = [] if pretest else resolve_stages(spec, model, configurations, variables, where)
    project = Project(path, spec, model, configurations, available, variables, case, deck, sensors, stages)
    for k, c in enumerate(spec.configurations):
        if c.test is not None and not pretest:
            check_test_data(project, k, c, where)
    return project


def _configuration(c: ConfigurationSpec, available: dict, blocks: dict, model: Model, loc: str) -> Configuration:
    if c.from_ is not None and c.from_ not in available:
        raise ProjectError(f"{loc}.from: the model has no configuration '{c.from_}'; it defines {sorted(available)}")
    base = available[c.from_] if c.from_ is not None else Configuration(c.name)
    changes: dict = {"name": c.name}
    if c.gravity is not None:
        changes["gravity"] = c.gravity
    for j, m in enumerate(c.masses):
        _node(model, m.node, f"{loc}.masses[{j}].node")
    extra = [ConcentratedMass(m.node, m.mass, np.asarray(m.offset, float), np.zeros((3, 3)), m.name)
             for m in c.masses]
    fixed = dict(base.fixed)
    if c.fixed is not None:
        fixed = {}
        for node, comps in c.fixed.items():
            try:
                fixed[int(node)] = comps
            except ValueError:
                raise ProjectError(f"{loc}.fixed: key {node!r} must be a node id") from None
            _node(model, int(node), f"{loc}.fixed.{node}")
    if c.shaker is not None:
        _node(model, c.shaker.node, f"{loc}.shaker.node")
        if c.shaker.mass:
            extra.append(ConcentratedMass(c.shaker.node, c.shaker.mass, np.zeros(3), np.zeros((3, 3)), "shaker"))
        if c.shaker.fixed:
            held = set(fixed.get(c.shaker.node, "")) | set(c.shaker.fixed)
            fixed[c.shaker.node] = "".join(sorted(held))
    if c.fixed is not None or (c.shaker is not None and c.shaker.fixed):
        changes["fixed"] = fixed
    if extra:
        changes["masses"] = tuple(base.masses) + tuple(extra)
    for j, f in enumerate(c.forces):
        _node(model, f.node, f"{loc}.forces[{j}].node")
    if c.forces:
        changes["forces"] = tuple(base.forces) + tuple(NodalLoad(f.node, tuple(f.force), tuple(f.moment))
                                                       for f in c.forces)
    if c.cords is not None:
        g = (c.gravity if c.gravity is not None else base.gravity) * base.g or STANDARD_GRAVITY
        cords = []
        for j, cs in enumerate(c.cords):
            cl = f"{loc}.cords[{j}]"
            _node(model, cs.node, f"{cl}.node")
            k, damp = cs.stiffness, cs.damping
            if cs.block_test is not None:
                if cs.block_test not in blocks:
                    raise ProjectError(f"{cl}.block_test: no suspension test '{cs.block_test}'; defined: "
                                       f"{sorted(blocks)}")
                point = block_point(blocks[cs.block_test])
                k, damp = point.stiffness, point.damping
            if not (np.isfinite(k) and k > 0 and np.isfinite(damp) and damp >= 0):
                raise ProjectError(f"{cl}: stiffness {k!r} N/m must be > 0 and damping {damp!r} N s/m >= 0")
            if cs.carries is not None and not cs.carries >= 0:
                raise ProjectError(f"{cl}.carries: {cs.carries!r} kg must be >= 0")
            attach = model.xyz[model.index_of([cs.node])[0]] + np.asarray(cs.offset)
            length = float(np.linalg.norm(np.asarray(cs.anchor) - attach))
            if not np.isfinite(length):
                raise ProjectError(f"{cl}: the anchor and offset must be finite coordinates [m]")
            free = cs.unstretched_length if cs.unstretched_length is not None else length - cs.carries * g / k
            if free <= 0:
                raise ProjectError(f"{cl}: the cord would need a negative unstretched length to carry "
                                   f"{cs.carries} kg ({cs.carries * g / k:.3g} m stretch over a {length:.3g} m "
                                   "cord); move the anchor higher or stiffen the cord")
            cords.append(Cord(cs.node, tuple(cs.anchor), k, free, damp, tuple(cs.offset)))
        changes["suspension"] = tuple(cords)
    try:
        return base.with_(**changes)
    except ModelError as exc:
        raise ProjectError(f"{loc}: {exc}") from None


def block_point(b):
    """The SuspensionPoint a block test gives (flexgvt.suspension.identify_block)."""
    from ..suspension import identify_block
    return identify_block(b.mass, frequency_hz=b.frequency_hz, damping_ratio=b.damping_ratio)


def _node(model: Model, node: int, where: str) -> None:
    try:
        model.index_of([node], "node")
    except ModelError:
        raise ProjectError(f"{where}: node {node} is not in model '{model.name}'") from None


def _points(points: str, case, model: Model, rel, where: str) -> tuple[dict, dict]:
    """Test point -> FE node and arm: 'nodes' (same ids, no arm), 'case' (a built-in case's sensors,
    point k + 1 = its k-th sensor position) or a CSV file point,node,dx,dy,dz [m]."""
    if points == "nodes":
        return {}, {}
    if points == "case":
        if case is None or not case.sensors:
            raise ProjectError(f"{where}: 'case' needs a built-in model with sensors; give a CSV of points instead")
        return case_points(case)
    from .validate import test_points
    path = _need_file(rel(points), where, "test point file")
    rows = test_points(path, where)
    node_map = {int(r[0]): int(r[1]) for r in rows}
    for pt, node in node_map.items():
        _node(model, node, f"{where}: {path} point {pt}")
    offsets = {int(r[0]): r[2:5] for r in rows} if rows.shape[1] == 5 else {}
    return node_map, offsets


def case_points(case) -> tuple[dict, dict]:
    """A case's sensor positions as test points 1..n (one per distinct node and arm)."""
    node_map, offsets, seen = {}, {}, {}
    for node, offset, _ in case.sensors.values():
        key = (int(node), tuple(np.round(np.asarray(offset, float), 9)))
        if key not in seen:
            seen[key] = len(seen) + 1
            node_map[seen[key]] = int(node)
            offsets[seen[key]] = np.asarray(offset, float)
    return node_map, offsets


def _variables(spec: ProjectFile, model: Model, configurations: dict, where: str) -> list:
    from ..updating import Parametrisation
    from .stages import variable_of
    out = []
    for k, v in enumerate(spec.variables):
        var = variable_of(v, f"{where}: variables[{k}] ('{v.name}')", where)
        try:
            Parametrisation(model, list(configurations.values()), [var])
        except ModelError as exc:
            raise ProjectError(f"{where}: variables[{k}] ('{v.name}'): {exc}") from None
        out.append(var)
    if out and not spec.stages:  # with stages, each stage's own set is checked (two may overlap in two stages)
        try:
            Parametrisation(model, list(configurations.values()), out)
        except ModelError as exc:
            raise ProjectError(f"{where}: variables: {exc}") from None
    return out
