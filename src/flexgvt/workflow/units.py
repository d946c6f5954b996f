"""Quantities in project files: a number is SI; a string carries its unit ("17.6 N/m", "4.3 GPa").

The unit's dimension is checked against what the key expects, so "stiffness = '17.6 kg'" stops
with a unit mismatch naming the key instead of silently becoming a wrong model.
"""

from __future__ import annotations

import math
import re

from ..errors import ModelError

# Dimensions as exponents of (kg, m, s, rad); value: SI factor.
_BASE = {
    "kg": (1.0, (1, 0, 0, 0)), "g": (1e-3, (1, 0, 0, 0)), "t": (1e3, (1, 0, 0, 0)),
    "m": (1.0, (0, 1, 0, 0)), "mm": (1e-3, (0, 1, 0, 0)), "cm": (1e-2, (0, 1, 0, 0)), "km": (1e3, (0, 1, 0, 0)),
    "s": (1.0, (0, 0, 1, 0)), "ms": (1e-3, (0, 0, 1, 0)), "min": (60.0, (0, 0, 1, 0)),
    "N": (1.0, (1, 1, -2, 0)), "kN": (1e3, (1, 1, -2, 0)),
    "Pa": (1.0, (1, -1, -2, 0)), "kPa": (1e3, (1, -1, -2, 0)), "MPa": (1e6, (1, -1, -2, 0)),
    "GPa": (1e9, (1, -1, -2, 0)),
    "Hz": (1.0, (0, 0, -1, 0)), "rad": (1.0, (0, 0, 0, 1)), "deg": (math.pi / 180, (0, 0, 0, 1)),
    "J": (1.0, (1, 2, -2, 0)),
    "in": (0.0254, (0, 1, 0, 0)), "ft": (0.3048, (0, 1, 0, 0)),
    "lbf": (4.4482216152605, (1, 1, -2, 0)), "kip": (4448.2216152605, (1, 1, -2, 0)),
    "lbm": (0.45359237, (1, 0, 0, 0)), "slug": (14.593902937206364, (1, 0, 0, 0)),
}

DIMENSIONS = {
    "mass": (1, 0, 0, 0), "length": (0, 1, 0, 0), "time": (0, 0, 1, 0), "frequency": (0, 0, -1, 0),
    "force": (1, 1, -2, 0), "stiffness": (1, 0, -2, 0), "damping": (1, 0, -1, 0), "modulus": (1, -1, -2, 0),
    "density": (1, -3, 0, 0), "angle": (0, 0, 0, 1), "force_per_length": (1, 0, -2, 0),
    "rotational_stiffness": (1, 2, -2, -1), "moment": (1, 2, -2, 0), "inertia": (1, 2, 0, 0),
    "acceleration": (0, 1, -2, 0),
}

_TOKEN = re.compile(r"([A-Za-z]+)(?:\^?(-?\d+))?")


def _parse_unit(text: str) -> tuple[float, tuple[int, ...]]:
    """'N s/m' -> (1.0, (1, 0, -1, 0)); products by spaces, '*' or '.', one '/' for the denominator."""
    factor, dims = 1.0, [0, 0, 0, 0]
    num, _, den = text.replace("*", " ").replace("·", " ").partition("/")
    for part, sign in ((num, 1), (den, -1)):
        for tok in part.split():
            m = _TOKEN.fullmatch(tok)
            if not m or m.group(1) not in _BASE:
                raise KeyError(tok)
            f, d = _BASE[m.group(1)]
            p = int(m.group(2) or 1) * sign
            factor *= f ** p
            dims = [a + p * b for a, b in zip(dims, d)]
    return factor, tuple(dims)


def unit_dimensions(unit: str) -> tuple[int, ...]:
    """Exponents of (kg, m, s, rad) of a unit ('N s/m' -> (1, 0, -1, 0)); ModelError for an unknown one."""
    try:
        return _parse_unit(unit)[1]
    except KeyError as exc:
        raise ModelError(f"unknown unit {exc.args[0]!r} in {unit!r}; known: {sorted(_BASE)}") from None


def quantity(value, dimension: str, where: str = "") -> float:
    """SI value of ``value`` (a number, SI; or 'number unit') of the given dimension (DIMENSIONS);
    ``where`` prefixes the error messages."""
    where = f"{where}: " if where else ""
    if isinstance(value, bool):
        raise ModelError(f"{where}expected a {dimension}, got {value!r}")
    if isinstance(value, (int, float)):
        out = float(value)
    elif isinstance(value, str):
        m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*", value)
        if not m:
            raise ModelError(f"{where}{value!r} is not a number with a unit (e.g. '17.6 N/m')")
        try:
            factor, dims = _parse_unit(m.group(2)) if m.group(2) else (1.0, (0, 0, 0, 0))
        except KeyError as exc:
            raise ModelError(f"{where}unknown unit {exc.args[0]!r} in {value!r}; use SI numbers or one of "
                             f"{sorted(_BASE)}") from None
        want = DIMENSIONS[dimension]
        # Radians are dimensionless: compare without them when one side has none.
        if dims != want and not (dims[:3] == want[:3] and 0 in (dims[3], want[3])):
            raise ModelError(f"{where}unit mismatch: {value!r} is not a {dimension} (expected units like "
                             f"{_example(dimension)})")
        out = float(m.group(1)) * factor
    else:
        raise ModelError(f"{where}expected a {dimension} (number in SI or 'value unit'), got {value!r}")
    if not math.isfinite(out):
        raise ModelError(f"{where}{value!r} is not finite")
    return out


def _example(dimension: str) -> str:
    return {"mass": "kg", "length": "m or mm", "time": "s", "frequency": "Hz", "force": "N", "stiffness": "N/m",
            "damping": "N s/m", "modulus": "Pa or GPa", "density": "kg/m^3", "angle": "rad or deg",
            "rotational_stiffness": "N m/rad", "moment": "N m", "inertia": "kg m^2",
            "acceleration": "m/s^2"}.get(dimension, "SI")


# Consistent unit systems by the names engineers write: (length [m], force [N]); time is seconds and
# mass the consistent one (force s^2 / length: tonne for mm-N, lbf s^2/in for in-lbf, slug for ft-lbf).
UNIT_SYSTEM_NAMES = {
    "SI": (1.0, 1.0), "m-kg-s": (1.0, 1.0), "m-N-kg-s": (1.0, 1.0), "m-kg-N-s": (1.0, 1.0), "m-N-s": (1.0, 1.0),
    "mm-N-t-s": (1e-3, 1.0), "mm-t-s": (1e-3, 1.0), "mm-t-N-s": (1e-3, 1.0), "mm-N-s": (1e-3, 1.0),
    "in-lbf-s": (0.0254, 4.4482216152605), "in-lbf-lbfs2/in-s": (0.0254, 4.4482216152605),
    "ft-lbf-s": (0.3048, 4.4482216152605), "ft-slug-s": (0.3048, 4.4482216152605),
    "ft-lbf-slug-s": (0.3048, 4.4482216152605),
}
_SYSTEM_KEYS = ("length", "force", "mass", "time")


def _at(where: str, key: str = "") -> str:
    """'where.key: ', 'key: ', 'where: ' or ''."""
    at = ".".join(p for p in (where, key) if p)
    return f"{at}: " if at else ""


def _unit_of(value, dimension: str, key: str, where: str) -> float:
    if not isinstance(value, str):
        raise ModelError(f"{_at(where, key)}expected a unit name in quotes (e.g. \"{_example(dimension)}\"), got "
                         f"{value!r}")
    try:
        factor, dims = _parse_unit(value)
    except KeyError as exc:
        raise ModelError(f"{_at(where, key)}unknown unit {exc.args[0]!r}; use one of {sorted(_BASE)}") from None
    if dims != DIMENSIONS[dimension]:
        raise ModelError(f"{_at(where, key)}{value!r} is not a unit of {dimension} (e.g. {_example(dimension)})")
    return factor


def unit_system(value, where: str = "units") -> tuple[str, float, float]:
    """(name, length [m], force [N]) of a deck's consistent unit system: a name ("SI", "m-kg-s",
    "mm-N-t-s", "mm-t-s", "in-lbf-s", "ft-lbf-s"; case and spaces ignored) or a table of units,
    {length = "mm", force = "N"} or {length = "mm", mass = "t", time = "s"} (the force derived; given
    both, they must agree). Time must be seconds. ModelError, naming ``where``, for anything else."""
    names = ", ".join(f'"{n}"' for n in ("SI", "m-kg-s", "mm-N-t-s", "mm-t-s", "in-lbf-s", "ft-lbf-s"))
    if isinstance(value, str):
        key = {n.lower().replace(" ", ""): n for n in UNIT_SYSTEM_NAMES}.get(value.lower().replace(" ", ""))
        if key is None:
            raise ModelError(f"{_at(where)}unknown unit system {value!r}; write one of {names}, or a table such as "
                             '{length = "mm", force = "N"} or {length = "mm", mass = "t", time = "s"}')
        return key, *UNIT_SYSTEM_NAMES[key]
    if not isinstance(value, dict):
        raise ModelError(f"{_at(where)}expected a unit system name ({names}) or a table such as "
                         f'{{length = "mm", force = "N"}}, got {value!r}')
    unknown = [k for k in value if k not in _SYSTEM_KEYS]
    if unknown:
        raise ModelError(f"{_at(where)}unknown key(s) {unknown} in the unit table; keys: {list(_SYSTEM_KEYS)}")
    if "length" not in value or not ({"force", "mass"} & set(value)):
        raise ModelError(f"{_at(where)}give 'length' and 'force' (or 'mass'), e.g. "
                         '{length = "mm", force = "N"} or {length = "mm", mass = "t", time = "s"}')
    length = _unit_of(value["length"], "length", "length", where)
    if "time" in value and _unit_of(value["time"], "time", "time", where) != 1.0:
        raise ModelError(f"{_at(where, 'time')}{value['time']!r}: decks are read in seconds only; convert the deck's "
                         "time unit or use a system in seconds")
    force = _unit_of(value["force"], "force", "force", where) if "force" in value else None
    if "mass" in value:
        derived = _unit_of(value["mass"], "mass", "mass", where) * length  # mass length / s^2
        if force is not None and not math.isclose(force, derived, rel_tol=1e-6):
            raise ModelError(f"{_at(where)}{value['force']!r} is not {value['mass']!r} {value['length']}/s^2 "
                             f"({derived:.6g} N against {force:.6g} N): the system is not consistent; give "
                             "'force' or 'mass', not both")
        force = derived
    name = "-".join(str(value[k]) for k in _SYSTEM_KEYS if k in value)
    return name, length, force
