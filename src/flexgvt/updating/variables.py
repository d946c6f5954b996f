"""Design variables: named, bound to model entities, normalised by their initial values, bounded.

    E1 = fg.updating.beam("E_region1", groups="region1", attribute="E", bounds=(0.9, 1.1))
    k = fg.updating.cord("suspension_k", attribute="stiffness", bounds=(0.8, 1.2))

A variable's normalised value x scales each target's initial value (p = x p0); offsets, whose
initial value may be zero, shift instead: p = p0 + (x - 1) scale. Several targets (beam groups
matched by name or pattern, several masses, springs or cords) move together: that is how a
region or a component is grouped.
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass, fields, replace
from typing import Iterable, Sequence

import numpy as np

from ..errors import ModelError
from ..cases.case import Case
from ..model import BeamGroup, Configuration, Material, Model, TaperedSection
from ..model.section import Section
from ..model.components import ConcentratedMass, find_items
from ..model.shells import Laminate
from .settings import renamed

KINDS = ("beam", "mass", "spring", "cord", "shell")
MATERIAL_ATTRIBUTES = ("E", "G", "rho")
MASS_ATTRIBUTES = ("mass", "offset_x", "offset_y", "offset_z")
SPRING_ATTRIBUTES = tuple(f"k{i}" for i in range(1, 7)) + tuple(f"c{i}" for i in range(1, 7)) + ("stiffness", "damping")
CORD_ATTRIBUTES = ("stiffness", "damping", "offset_x", "offset_y", "offset_z", "along")
SHELL_ATTRIBUTES = ("thickness", "E", "G", "rho", "nsm")
SECTION_ALIASES = {"thickness": "height"}  # a RectangularSection's height is a strip's or skin's thickness
# Normalised bounds of a variable that gives none, by kind (the factories, Variable and project files).
DEFAULT_BOUNDS = {"beam": (0.9, 1.1), "mass": (0.9, 1.1), "spring": (0.5, 2.0), "cord": (0.8, 1.2),
                  "shell": (0.9, 1.1)}


@dataclass(frozen=True)
class Variable:
    """One design variable.

    kind: 'beam' (a material or section attribute of beam groups), 'mass', 'spring', 'cord' or
    'shell' (a property attribute of shell groups: SHELL_ATTRIBUTES);
    attribute: E, G, rho, or a section field (width, height, thickness, A, Iy, ...) for beams;
    mass, offset_x/y/z for masses; k1..k6, c1..c6, stiffness, damping for springs; stiffness,
    damping for cords. targets: beam group names or fnmatch patterns ('region*'), mass or spring
    names or patterns (ConcentratedMass.name, Spring.name; integers: positions in model.masses /
    model.springs, deprecated), or cord indices within each configuration named in
    ``configurations`` (None: every configuration); ids: mass or spring ids (a deck's CONM2 or
    CELAS EIDs); a mass variable with ``configurations`` targets those configurations' own masses.
    bounds: normalised (lower, upper), None: DEFAULT_BOUNDS of the kind; scale: the absolute size
    of x - 1 = 1 for shifted attributes (offsets) [m].
    """

    name: str
    kind: str
    attribute: str
    targets: tuple = ()
    bounds: tuple[float, float] | None = None
    scale: float = 0.01
    configurations: tuple[str, ...] | None = None
    ids: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ModelError(f"design variable '{self.name}': kind '{self.kind}' must be one of {KINDS}")
        if self.kind in DEFAULT_BOUNDS and self.bounds is None:
            object.__setattr__(self, "bounds", DEFAULT_BOUNDS[self.kind])
        try:
            lo, hi = (float(b) for b in self.bounds)
        except (TypeError, ValueError):
            raise ModelError(f"design variable '{self.name}': bounds {self.bounds!r} must be two numbers "
                             "(lower, upper)") from None
        targets = tuple(self.targets)
        ids = tuple(self.ids)
        named = self.kind in ("mass", "spring")
        if self.kind in ("beam", "shell"):
            bad = [t for t in targets if not isinstance(t, str)]
            what = f"{self.kind} group names or patterns (strings, e.g. \"wing_*\")"
        else:
            bad = [t for t in targets if isinstance(t, (bool, np.bool_))
                   or not isinstance(t, (int, np.integer) + ((str,) if named else ()))]
            what = f"{self.kind} names or indices" if named else f"{self.kind} indices (integers >= 0)"
        if bad:
            raise ModelError(f"design variable '{self.name}': targets {bad} are not {what}")
        if ids and not named:
            raise ModelError(f"design variable '{self.name}': only masses and springs are addressed by id")
        if any(isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)) for i in ids):
            raise ModelError(f"design variable '{self.name}': ids {list(ids)} must be integers")
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise ModelError(f"design variable '{self.name}': bounds {self.bounds} must be finite with lower < upper")
        if not self.shifts:
            if lo <= 0:
                raise ModelError(f"design variable '{self.name}': bounds {self.bounds} scale a physical property and "
                                 "must stay > 0")
        object.__setattr__(self, "bounds", (lo, hi))
        object.__setattr__(self, "targets", targets)
        object.__setattr__(self, "ids", tuple(int(i) for i in ids))

    @property
    def per_configuration(self) -> bool:
        """Targets configuration items (cords, a configuration's own masses), not the model."""
        return self.kind == "cord" or (self.kind == "mass" and self.configurations is not None)

    @property
    def shifts(self) -> bool:
        """Offsets and a cord's attachment position ``along`` shift (p0 + (x - 1) scale); every other
        attribute scales (x p0)."""
        return self.attribute.startswith("offset_") or self.attribute == "along"


def beam(name: str, groups: str | Iterable[str], attribute: str,
         bounds: tuple[float, float] | None = None) -> Variable:
    """A material (E, G, rho) or section attribute (width, height, thickness, A, Iy, Iz, J, ...) of the
    beam groups named by ``groups`` (names or fnmatch patterns, see Model.add_beams(name=...))."""
    groups = (groups,) if isinstance(groups, str) else tuple(groups)
    return Variable(name, "beam", SECTION_ALIASES.get(attribute, attribute), groups, bounds)


def shell(name: str, groups: str | Iterable[str], attribute: str,
          bounds: tuple[float, float] | None = None) -> Variable:
    """A property attribute of the shell groups named by ``groups`` (names or fnmatch patterns, see
    Model.add_shells(name=...)): thickness (a PSHELL's T, or every ply of a laminate), E, G, rho
    (of the property's materials: every MAT1 it uses; rho also of a laminate's plies) or nsm."""
    groups = (groups,) if isinstance(groups, str) else tuple(groups)
    return Variable(name, "shell", attribute, groups, bounds)


def _named(kind: str, targets, ids) -> tuple[tuple, tuple[int, ...]]:
    """(names or positions, ids) of a mass or spring variable; positions warn (deprecated)."""
    targets = () if targets is None else ((targets,) if isinstance(targets, str) or np.isscalar(targets)
                                          else tuple(targets))
    ids = () if ids is None else ((ids,) if np.isscalar(ids) else tuple(ids))
    if any(not isinstance(t, str) for t in targets):
        renamed(f"flexgvt.updating.{kind}() with positions in model.{kind}{'es' if kind == 'mass' else 's'}",
                "names (ConcentratedMass.name, Spring.name, fnmatch patterns) or ids= (entity ids)", 4)
    return tuple(t if isinstance(t, str) else int(t) for t in targets), tuple(int(i) for i in ids)


def mass(name: str, masses: str | Iterable[str] | None = None, attribute: str = "mass",
         bounds: tuple[float, float] | None = None,
         scale: float = 0.01, configurations: Iterable[str] | None = None, *,
         ids: int | Iterable[int] | None = None) -> Variable:
    """Mass [kg] or one offset component [m] of concentrated masses; offsets shift by (x - 1) * scale [m].

    masses: names or fnmatch patterns of the masses (model.add_mass(name=...); positions in
    model.masses still work, deprecated); ids: their ids (a deck's CONM2 EIDs); with
    ``configurations``: the masses of each named configuration's own (Configuration.masses: what
    is present only in that test, such as suspension attachment hardware or a shaker's moving
    mass), one value shared by all of them."""
    targets, ids = _named("mass", masses, ids)
    return Variable(name, "mass", attribute, targets, bounds, scale,
                    configurations=None if configurations is None else tuple(configurations), ids=ids)


def spring(name: str, springs: str | Iterable[str] | None = None, attribute: str = "stiffness",
           bounds: tuple[float, float] | None = None, *, ids: int | Iterable[int] | None = None) -> Variable:
    """Stiffness or damping (all six components, or one: k1..k6, c1..c6) of springs named by
    ``springs`` (names or fnmatch patterns; positions in model.springs still work, deprecated) or
    with ``ids`` (a deck's CELAS/CBUSH EIDs)."""
    targets, ids = _named("spring", springs, ids)
    return Variable(name, "spring", attribute, targets, bounds, ids=ids)


def cord(name: str, cords: int | Iterable[int] | None = None, attribute: str = "stiffness",
         bounds: tuple[float, float] | None = None,
         configurations: Iterable[str] | None = None, scale: float = 0.01) -> Variable:
    """Stiffness, damping, attachment offset (offset_x/y/z: the attachment point's arm from its node
    [m], shifted by (x - 1) scale) or position ``along`` its element [m] (a cord with node_b: the
    attachment slides between the two nodes, shifted by (x - 1) scale) of suspension cords (indices in each
    configuration's suspension; None: all) in the named
    configurations (None: all)."""
    cords = () if cords is None else ((cords,) if np.isscalar(cords) else tuple(cords))
    return Variable(name, "cord", attribute, tuple(int(c) for c in cords), bounds, scale,
                    configurations=None if configurations is None else tuple(configurations))


@dataclass(frozen=True)
class Binding:
    """A variable resolved on a model: its targets as indices and their initial values."""

    variable: Variable
    indices: tuple  # beam group indices, mass/spring indices, or (configuration name, cord index)
    initial: np.ndarray  # initial value of the attribute at each target


class Parametrisation:
    """Design variables bound to a model and its configurations; applies a design point to a
    working copy of the model without rebuilding anything else."""

    def __init__(self, model: Model, configurations: Sequence[Configuration], variables: Sequence[Variable]):
        if not variables:
            raise ModelError("updating: give at least one design variable")
        names = [v.name for v in variables]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ModelError(f"updating: design variable names must be unique; repeated: {dup}")
        self.model = model
        self.configurations = {c.name: c for c in configurations}
        self.variables = tuple(variables)
        self.bindings = tuple(self._bind(v) for v in variables)
        seen: dict = {}
        for b in self.bindings:
            for idx in b.indices:
                key = (b.variable.kind, idx, b.variable.attribute)
                if key in seen:
                    raise ModelError(f"design variables '{seen[key]}' and '{b.variable.name}' both set "
                                     f"{b.variable.attribute} of the same {b.variable.kind} ({idx}); merge them")
                seen[key] = b.variable.name
        self.lower = np.array([v.bounds[0] for v in variables])
        self.upper = np.array([v.bounds[1] for v in variables])

    @property
    def names(self) -> list[str]:
        return [v.name for v in self.variables]

    def __len__(self) -> int:
        return len(self.variables)

    # ------------------------------------------------------------------ binding
    def _bind(self, v: Variable) -> Binding:
        where = f"design variable '{v.name}'"
        m = self.model
        if v.kind == "beam":
            names = [g.name for g in m.beams]
            idx = sorted({k for pat in v.targets for k, n in enumerate(names) if fnmatch.fnmatchcase(n, pat)})
            missing = [pat for pat in v.targets if not any(fnmatch.fnmatchcase(n, pat) for n in names)]
            if missing or not v.targets:
                raise ModelError(f"{where}: no beam group named {missing or '(none given)'} in model '{m.name}'; "
                                 f"groups: {sorted(set(names))}")
            initial = [self._beam_value(m.beams[k], v, where) for k in idx]
            return Binding(v, tuple(idx), np.array(initial))
        if v.kind == "shell":
            names = [g.name for g in m.shells]
            idx = sorted({k for pat in v.targets for k, n in enumerate(names) if fnmatch.fnmatchcase(n, pat)})
            missing = [pat for pat in v.targets if not any(fnmatch.fnmatchcase(n, pat) for n in names)]
            if missing or not v.targets:
                raise ModelError(f"{where}: no shell group named {missing or '(none given)'} in model '{m.name}'; "
                                 f"groups: {sorted(set(names))}")
            if v.attribute not in SHELL_ATTRIBUTES:
                raise ModelError(f"{where}: attribute '{v.attribute}' of a shell group must be one of "
                                 f"{SHELL_ATTRIBUTES}")
            return Binding(v, tuple(idx), np.array([shell_value(m.shells[k], v.attribute, where) for k in idx]))
        if v.kind == "mass" and v.configurations is not None:
            return self._bind_configuration_masses(v, where)
        if v.kind in ("mass", "spring"):
            items = m.masses if v.kind == "mass" else m.springs
            allowed = MASS_ATTRIBUTES if v.kind == "mass" else SPRING_ATTRIBUTES
            if v.attribute not in allowed:
                raise ModelError(f"{where}: attribute '{v.attribute}' of a {v.kind} must be one of {allowed}")
            idx = _positions(v, items, f"{where}: model '{m.name}'")
            initial = [self._point_value(items[i], v) for i in idx]
            if v.kind == "spring" and np.any(np.asarray(initial) <= 0):
                raise ModelError(f"{where}: a spring's {v.attribute} is zero; a zero value cannot be scaled")
            return Binding(v, idx, np.array(initial))
        # cords
        if v.attribute not in CORD_ATTRIBUTES:
            raise ModelError(f"{where}: attribute '{v.attribute}' of a cord must be one of {CORD_ATTRIBUTES}")
        idx, initial = [], []
        cfgs = self._configurations_of(v, where)
        for c in cfgs:
            cords = self.configurations[c].suspension
            chosen = range(len(cords)) if not v.targets else v.targets
            for i in chosen:
                if not 0 <= i < len(cords):
                    raise ModelError(f"{where}: configuration '{c}' has no cord {i} ({len(cords)} cords)")
                idx.append((c, i))
                if v.attribute == "along" and cords[i].node_b is None:
                    raise ModelError(f"{where}: cord {i} of configuration '{c}' hangs at a node; give it node_b "
                                     "(the element's other node) to move its attachment along the element")
                initial.append(cords[i].offset["xyz".index(v.attribute[-1])] if v.attribute.startswith("offset_")
                               else getattr(cords[i], v.attribute))
        if not idx:
            raise ModelError(f"{where}: no cord in configuration(s) {cfgs}")
        if not v.shifts and np.any(np.asarray(initial) <= 0):
            raise ModelError(f"{where}: a cord's {v.attribute} is zero; a zero value cannot be scaled")
        return Binding(v, tuple(idx), np.array(initial, float))

    def _configurations_of(self, v: Variable, where: str) -> list[str]:
        cfgs = list(self.configurations) if v.configurations is None else list(v.configurations)
        unknown = [c for c in cfgs if c not in self.configurations]
        if unknown:
            raise ModelError(f"{where}: unknown configuration(s) {unknown}; known: {list(self.configurations)}")
        return cfgs

    def _bind_configuration_masses(self, v: Variable, where: str) -> Binding:
        if v.attribute not in MASS_ATTRIBUTES:
            raise ModelError(f"{where}: attribute '{v.attribute}' of a mass must be one of {MASS_ATTRIBUTES}")
        if not v.targets and not v.ids:
            raise ModelError(f"{where}: give the names (or ids) of the masses in each configuration's masses")
        idx, initial = [], []
        for c in self._configurations_of(v, where):
            items = self.configurations[c].masses
            for i in _positions(v, items, f"{where}: configuration '{c}' (its own masses, Configuration.masses)",
                                f"{where}: configuration '{c}' has no mass {{}} ({len(items)} masses of its own, "
                                "Configuration.masses)"):
                idx.append((c, i))
                initial.append(self._point_value(items[i], v))
        if v.attribute == "mass" and np.any(np.asarray(initial) <= 0):
            raise ModelError(f"{where}: a mass is zero; a zero value cannot be scaled")
        return Binding(v, tuple(idx), np.array(initial, float))

    @staticmethod
    def _beam_value(group, v: Variable, where: str) -> float:
        if v.attribute in MATERIAL_ATTRIBUTES:
            value = group.material.shear_modulus if v.attribute == "G" else getattr(group.material, v.attribute)
        elif isinstance(group.section, TaperedSection):
            raise ModelError(f"{where}: beam group '{group.name}' has a TaperedSection (its values differ between the "
                             f"element ends), whose section values cannot be design variables; use its material's "
                             f"{MATERIAL_ATTRIBUTES} (they scale the whole element), or give the group a uniform "
                             "section")
        else:
            known = [f.name for f in fields(group.section)]
            if v.attribute not in known:
                raise ModelError(f"{where}: beam group '{group.name}' has a {type(group.section).__name__}, whose "
                                 f"attributes are {known} (and the material's {MATERIAL_ATTRIBUTES})")
            value = getattr(group.section, v.attribute)
        if not isinstance(value, (int, float)) or not value > 0:
            raise ModelError(f"{where}: {v.attribute} of beam group '{group.name}' is {value!r}; only a positive "
                             "number can be scaled")
        return float(value)

    @staticmethod
    def _point_value(item, v: Variable) -> float:
        a = v.attribute
        if a == "mass":
            return float(item.mass)
        if a.startswith("offset_"):
            return float(item.offset["xyz".index(a[-1])])
        arr = item.stiffness if a[0] == "k" or a == "stiffness" else item.damping
        return float(arr[int(a[1]) - 1]) if a[1:].isdigit() else float(np.max(arr))

    # ------------------------------------------------------------------ values
    def physical(self, b: Binding, x: float) -> np.ndarray:
        """Target values [SI] at normalised value x."""
        v = b.variable
        return b.initial + (x - 1.0) * v.scale if v.shifts else b.initial * x

    def check(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, float)
        if x.shape != (len(self),) or not np.all(np.isfinite(x)):
            raise ModelError(f"design point must be {len(self)} finite values, got {x}")
        return x

    def beam_entities(self, group: BeamGroup, b: Binding, idx: int, xk: float) -> tuple[Material, Section]:
        """(material, section) of beam group ``group`` (as it is at the current design point) with
        b's attribute at normalised value xk (target ``idx`` of b)."""
        value = float(self.physical(b, xk)[b.indices.index(idx)])
        a = b.variable.attribute
        if a in MATERIAL_ATTRIBUTES:
            return replace(group.material, **{a: value}), group.section
        return group.material, replace(group.section, **{a: value})

    def configuration_masses(self, configuration: str, x: np.ndarray) -> list:
        """The concentrated masses of ``configuration``'s own (not the model's) at design point x."""
        items = list(self.configurations[configuration].masses)
        for b, xi in zip(self.bindings, x):
            if b.variable.kind == "mass" and b.variable.per_configuration:
                for (c, i), value in zip(b.indices, self.physical(b, xi)):
                    if c == configuration:
                        items[i] = _set_mass(items[i], b.variable.attribute, float(value))
        return items

    def mass_entities(self, model: Model, b: Binding, xk: float, configuration: str | None = None,
                      x: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(masses (k,), offsets (k, 3)) of b's concentrated masses with its attribute at xk, the
        others as at design point x (model masses: as set in ``model``; for a variable on
        configuration masses: those of ``configuration``, with the other variables' values at x,
        as bound where x is None)."""
        if b.variable.per_configuration:
            keep = [k for k, (c, _) in enumerate(b.indices) if c == configuration]
            own = (self.configuration_masses(configuration, x) if x is not None
                   else self.configurations[configuration].masses)
            items = [own[b.indices[k][1]] for k in keep]
            values = self.physical(b, xk)[keep]
        else:
            items = [model.masses[i] for i in b.indices]
            values = self.physical(b, xk)
        masses = np.array([m.mass for m in items], float)
        offsets = np.array([m.offset for m in items], float).reshape(-1, 3)
        if b.variable.attribute == "mass":
            masses = values.astype(float)
        else:
            offsets[:, "xyz".index(b.variable.attribute[-1])] = values
        return masses, offsets

    def apply(self, model: Model, x: np.ndarray) -> dict[str, Configuration]:
        """Set ``model`` (a working copy of the bound model, same entities) to design point x and
        return the configurations at x (new objects where cords change)."""
        x = self.check(x)
        beams: dict[int, tuple[dict, dict]] = {}
        configs = dict(self.configurations)
        cords: dict[str, list] = {}
        own_masses: dict[str, list] = {}
        springs: dict[tuple[int, str], np.ndarray] = {}
        shells: dict[int, dict] = {}
        base = self.model
        for b, xi in zip(self.bindings, x):
            v = b.variable
            values = self.physical(b, xi)
            for idx, value in zip(b.indices, values):
                if v.kind == "beam":
                    mat, sec = beams.setdefault(idx, ({}, {}))
                    (mat if v.attribute in MATERIAL_ATTRIBUTES else sec)[v.attribute] = float(value)
                elif v.kind == "shell":
                    shells.setdefault(idx, {})[v.attribute] = float(value)
                elif v.kind == "mass" and v.per_configuration:
                    c, i = idx
                    lst = own_masses.setdefault(c, list(configs[c].masses))
                    lst[i] = _set_mass(lst[i], v.attribute, float(value))
                elif v.kind == "mass":
                    if v.attribute == "mass":
                        model.set_mass(idx, mass=value)
                    else:
                        off = np.array(model.masses[idx].offset, float)
                        off["xyz".index(v.attribute[-1])] = value
                        model.set_mass(idx, offset=off)
                elif v.kind == "spring":
                    which = "stiffness" if v.attribute[0] == "k" or v.attribute == "stiffness" else "damping"
                    # Several variables may set components of one spring (k1..k6): build on what the
                    # earlier ones of this design point set, from the bound model's values.
                    arr = springs.setdefault((idx, which), np.array(getattr(base.springs[idx], which), float))
                    if v.attribute[1:].isdigit():
                        arr[int(v.attribute[1]) - 1] = value
                    else:
                        arr *= value / max(np.max(arr), 1e-300)
                    model.set_spring(idx, **{which: arr})
                else:
                    c, i = idx
                    lst = cords.setdefault(c, list(configs[c].suspension))
                    if v.attribute.startswith("offset_"):
                        off = list(lst[i].offset)
                        off["xyz".index(v.attribute[-1])] = float(value)
                        lst[i] = replace(lst[i], offset=tuple(off))
                    else:
                        lst[i] = replace(lst[i], **{v.attribute: float(value)})
        for k, (mat, sec) in beams.items():
            group = base.beams[k]
            material = group.material
            if mat:
                g = mat.pop("G", None)
                material = replace(material, **mat)
                if g is not None:
                    material = replace(material, G=g)
            section = replace(group.section, **sec) if sec else group.section
            model.set_beam_group(k, material=material, section=section)
        for k, values in shells.items():
            model.set_shell_group(k, property=shell_property(base.shells[k].property, values))
        for c, lst in cords.items():
            configs[c] = configs[c].with_(suspension=tuple(lst))
        for c, lst in own_masses.items():
            configs[c] = configs[c].with_(masses=tuple(lst))
        return configs


def case_variables(case: Case) -> list[Variable]:
    """Variables of a built-in case's design-variable table, ``case.references['design_variables']``:
    plain rows (name, kind, targets, attribute, bounds), kind "beam" (targets: group names) or "spring"
    (targets: spring names), as flexgvt.cases.xhale lists its 30 variables."""
    rows = getattr(case, "references", {}).get("design_variables")
    if rows is None:
        raise ModelError(f"case '{getattr(case, 'name', case)}' lists no design variables "
                         "(references['design_variables']); build the Variables with flexgvt.updating.beam/spring/...")
    makers = {"beam": beam, "spring": spring}
    out = []
    for name, kind, targets, attribute, bounds in rows:
        if kind not in makers:
            raise ModelError(f"case '{case.name}', design variable '{name}': kind '{kind}' is not one of "
                             f"{sorted(makers)}")
        out.append(makers[kind](name, targets, attribute, bounds))
    return out


def _positions(v: Variable, items, where: str, absent: str | None = None) -> tuple[int, ...]:
    """Positions in ``items`` (masses or springs) of v's targets (names, patterns or positions) and
    ids, in the order given, each once; absent: the message of a position out of range ({} the position)."""
    kind = v.kind
    if not v.targets and not v.ids:
        raise ModelError(f"{where}: design variable '{v.name}' names no {kind}; give names or ids")
    out: list[int] = []
    for t in v.targets:
        if isinstance(t, str):
            out += find_items(items, t, where, kind)
        elif not 0 <= t < len(items):
            raise ModelError(absent.format(t) if absent else f"{where}: {kind} index {[t]} does not exist "
                             f"({len(items)} {kind}{'es' if kind == 'mass' else 's'})")
        else:
            out.append(int(t))
    for i in v.ids:
        out += find_items(items, i, where, kind)
    return tuple(dict.fromkeys(out))


def _materials(prop) -> list:
    """The distinct materials of a shell property (its MIDs, or its plies')."""
    found = [p.material for p in prop.plies] if isinstance(prop, Laminate) else \
        [prop.membrane, prop.bending, prop.shear, prop.coupling]
    return list({id(m): m for m in found if m is not None}.values())


def shell_value(group, attribute: str, where: str) -> float:
    """The value of a shell group's property ``attribute`` (SHELL_ATTRIBUTES) that a variable scales."""
    prop = group.property
    if attribute == "thickness":
        if group.corner_thickness is not None:
            raise ModelError(f"{where}: shell group '{group.name}' gives corner thicknesses (T1-T4), which a "
                             "thickness variable cannot scale; use E, G or rho, or give the group its property's "
                             "thickness")
        value = prop.thickness
    elif attribute == "nsm":
        value = prop.nsm
    else:
        mats = _materials(prop)
        usable = [m for m in mats if isinstance(m, Material)] if attribute in ("E", "G") else mats
        if attribute in ("E", "G") and len(usable) != len(mats):
            raise ModelError(f"{where}: shell group '{group.name}' uses anisotropic or orthotropic materials (MAT2, "
                             f"MAT8), whose '{attribute}' is not one value; use thickness or rho")
        values = {float(m.shear_modulus if attribute == "G" else getattr(m, attribute)) for m in usable}
        if len(values) != 1:
            raise ModelError(f"{where}: shell group '{group.name}' uses materials with different {attribute} "
                             f"({sorted(values)}); a variable scales one value: give the group one material")
        value = values.pop()
    if not isinstance(value, (int, float)) or not value > 0:
        raise ModelError(f"{where}: {attribute} of shell group '{group.name}' is {value!r}; only a positive number "
                         "can be scaled")
    return float(value)


def shell_property(prop, values: dict):
    """The shell property ``prop`` with the attributes in ``values`` (SHELL_ATTRIBUTES) set."""
    values = dict(values)
    swap: dict[int, Material] = {}
    for m in _materials(prop):
        changed = {a: values[a] for a in ("E", "G", "rho") if a in values}
        if "G" in changed:
            changed["nu"] = None  # G given: nu follows from E and G
        if changed and (isinstance(m, Material) or set(changed) == {"rho"}):
            swap[id(m)] = replace(m, **changed)

    def mat(m):
        return swap.get(id(m), m) if m is not None else None
    if isinstance(prop, Laminate):
        ratio = values["thickness"] / prop.thickness if "thickness" in values else 1.0
        plies = tuple(replace(p, material=mat(p.material), thickness=p.thickness * ratio) for p in prop.plies)
        return replace(prop, plies=plies, nsm=values.get("nsm", prop.nsm))
    return replace(prop, thickness=values.get("thickness", prop.thickness), nsm=values.get("nsm", prop.nsm),
                   membrane=mat(prop.membrane), bending=mat(prop.bending), shear=mat(prop.shear),
                   coupling=mat(prop.coupling))


def _set_mass(item: ConcentratedMass, attribute: str, value: float) -> ConcentratedMass:
    if attribute == "mass":
        return replace(item, mass=value)
    off = np.array(item.offset, float)
    off["xyz".index(attribute[-1])] = value
    return replace(item, offset=off)
