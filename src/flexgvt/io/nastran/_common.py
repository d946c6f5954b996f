"""Shared pieces of the Nastran bulk data reader and writer: units, card locations, coordinate axes."""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import FileFormatError, ModelError


class UnsupportedCardsError(FileFormatError):
    """The deck holds cards (or card features) flexgvt cannot represent; ``unsupported`` maps card -> ids."""

    def __init__(self, message: str, unsupported: dict[str, list] | None = None):
        super().__init__(message)
        self.unsupported = dict(unsupported or {})


@dataclass(frozen=True)
class Units:
    """A consistent Nastran unit system, given by its length and force units in SI (time: seconds).

    Mass is then force * s^2 / length (after PARAM,WTMASS), e.g. tonne for mm-N-s.
    """

    name: str
    length: float  # m per deck length unit
    force: float  # N per deck force unit

    @property
    def mass(self) -> float:  # kg per deck mass unit
        return self.force / self.length

    @property
    def density(self) -> float:
        return self.mass / self.length**3

    @property
    def stress(self) -> float:
        return self.force / self.length**2

    @property
    def inertia(self) -> float:  # kg m^2 per deck unit
        return self.mass * self.length**2

    @property
    def moment(self) -> float:  # N m per deck unit (also rotational stiffness per rad)
        return self.force * self.length


UNIT_SYSTEMS = {
    "SI": Units("SI", 1.0, 1.0),
    "mm-N-t-s": Units("mm-N-t-s", 1e-3, 1.0),
    "in-lbf-s": Units("in-lbf-s", 0.0254, 4.4482216152605),
}


def get_units(units: str | Units) -> Units:
    if isinstance(units, Units):
        return units
    try:
        return UNIT_SYSTEMS[units]
    except KeyError:
        raise ModelError(f"units={units!r} is not known; use one of {sorted(UNIT_SYSTEMS)} or a Units(name, length, "
                         "force) giving the deck's length and force units in m and N") from None


_INCLUDE = re.compile(r"^\s*include\s+'([^']+)'", re.IGNORECASE)


class CardIndex:
    """Where each card (name, first field) sits in the deck and its includes: for messages only."""

    def __init__(self, path: Path):
        self.places: dict[tuple[str, str], list[tuple[str, int]]] = {}
        self.root = Path(path).resolve().parent
        self.missing_includes: list[tuple[str, int, str]] = []
        self.bad_includes: list[tuple[str, int, str]] = []  # INCLUDE lines not of the form INCLUDE 'path'
        from ._limits import ExpansionBudget

        self.budget = ExpansionBudget()  # raises at a THRU range or replication past its limit
        self._scan(Path(path), depth=0)

    def _scan(self, path: Path, depth: int) -> None:
        if depth > 20 or not path.is_file():
            return
        with open(path, "r", errors="replace") as handle:
            lines = handle.readlines()
        self.budget.scan(path, lines)
        for lineno, raw in enumerate(lines, start=1):
            line = raw.rstrip("\r\n")
            match = _INCLUDE.match(line)
            if match:
                inc = Path(match.group(1).strip())
                target = inc if inc.is_absolute() else self.root / inc
                if not target.is_file():
                    self.missing_includes.append((str(path), lineno, str(target)))
                self._scan(target, depth + 1)
                continue
            if line.lstrip().upper().startswith("INCLUDE"):
                self.bad_includes.append((str(path), lineno, line.strip()[:80]))
                continue
            if not line or not line[0].isalpha():
                continue
            name, first = split_first_fields(line)
            self.places.setdefault((name, first), []).append((str(path), lineno))

    def where(self, name: str, ident) -> str:
        """'file:line' of card ``name`` with first field ``ident`` (or '' when not found)."""
        hits = self.places.get((name.upper(), str(ident)), [])
        return f"{hits[0][0]}:{hits[0][1]}" if hits else ""

    def duplicates(self, names: tuple[str, ...]) -> dict[str, list[tuple[str, str, int]]]:
        """{id: [(card, file, line), ...]} for ids used more than once among cards ``names``."""
        seen: dict[str, list[tuple[str, str, int]]] = {}
        for (name, ident), hits in self.places.items():
            if name in names and ident:
                for f, ln in hits:
                    seen.setdefault(ident, []).append((name, f, ln))
        return {k: v for k, v in seen.items() if len(v) > 1}


def split_first_fields(line: str) -> tuple[str, str]:
    """Card name and first data field of a bulk data line (free, small or large field)."""
    line = line.expandtabs(8) if "\t" in line and "," not in line else line
    if "," in line:
        parts = line.split(",")
        name = parts[0].strip().upper().rstrip("*")
        first = parts[1].strip() if len(parts) > 1 else ""
        return name, first
    name = line[:8].strip().upper()
    if name.endswith("*"):
        return name.rstrip("*"), line[8:24].strip()
    return name, line[8:16].strip()


def where_prefix(index: CardIndex | None, name: str, ident) -> str:
    place = index.where(name, ident) if index is not None else ""
    return f"{place}: {name} {ident}" if place else f"{name} {ident}"


def coord_axes(bdf, cid: int | None, xyz_basic: np.ndarray, what: str) -> np.ndarray:
    """3x3 matrix whose columns are the axes of coordinate system ``cid`` at basic point ``xyz_basic``.

    Rectangular systems give constant axes; cylindrical (r, theta, z) and spherical (r, theta, phi)
    systems give the local axes at the point (Nastran's convention for displacement/load components).
    """
    if cid is None or cid == 0:
        return np.eye(3)
    coord = bdf.coords.get(cid)
    if coord is None:
        raise ModelError(f"{what}: coordinate system {cid} is not defined; add its CORD2R/CORD2C/CORD1R card")
    beta = np.asarray(coord.beta(), dtype=float)  # rows: local axes in basic
    kind = coord.Type
    if kind == "R":
        return beta.T.copy()
    local = beta @ (np.asarray(xyz_basic, float) - np.asarray(coord.origin, float))
    x, y, z = local
    if kind == "C":
        if math.hypot(x, y) < 1e-12 * max(1.0, abs(z)):
            raise ModelError(f"{what}: point lies on the axis of cylindrical system {cid}, where its r/theta "
                             "directions are undefined; use a rectangular system")
        t = math.atan2(y, x)
        axes = np.array([[math.cos(t), -math.sin(t), 0.0], [math.sin(t), math.cos(t), 0.0], [0.0, 0.0, 1.0]])
    elif kind == "S":
        r = math.sqrt(x * x + y * y + z * z)
        if math.hypot(x, y) < 1e-12 * max(1.0, r):
            raise ModelError(f"{what}: point lies on the polar axis of spherical system {cid}; use a rectangular "
                             "system")
        th, ph = math.acos(z / r), math.atan2(y, x)
        e_r = [math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)]
        e_t = [math.cos(th) * math.cos(ph), math.cos(th) * math.sin(ph), -math.sin(th)]
        e_p = [-math.sin(ph), math.cos(ph), 0.0]
        axes = np.array([e_r, e_t, e_p]).T
    else:  # pragma: no cover - pyNastran only has R, C, S
        raise ModelError(f"{what}: coordinate system {cid} of type {kind!r} is not supported")
    return beta.T @ axes


def absolute_include_lines(lines: list[str], folder: Path) -> list[str]:
    """Rewrite relative single-line INCLUDE statements of the main file to absolute paths."""
    out = []
    for line in lines:
        match = _INCLUDE.match(line)
        if match and not os.path.isabs(match.group(1).strip()):
            out.append(f"INCLUDE '{(folder / match.group(1).strip()).resolve()}'\n")
        else:
            out.append(line)
    return out


@dataclass(frozen=True)
class EigenMethod:
    """A subcase's real eigenvalue method (EIGRL, or EIGR with its METHOD).

    nd: number of modes (None: all in the window); f1, f2: frequency window [Hz] (None: open);
    norm: 'MASS' (phi^T M phi = 1), 'MAX' (largest component 1) or 'POINT' (component
    ``point`` = (grid, component 1-6) equal to 1). For EIGR with GIV/HOU/MGIV/MHOU, Nastran
    uses the window only when ND is blank; ``window_with_nd`` says whether both apply.
    """

    card: str
    sid: int
    method: str = "LAN"
    nd: int | None = None
    f1: float | None = None
    f2: float | None = None
    norm: str = "MASS"
    point: tuple[int, int] | None = None
    window_with_nd: bool = True
