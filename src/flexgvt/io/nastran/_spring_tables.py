"""Force-deflection tables of nonlinear springs (model.SpringTable) in bulk data: TABLED1 read into
a table and written from one, with Nastran's sign conventions turned into flexgvt's.

flexgvt's spring deflection is node b's motion relative to node a (a grounded spring's: its node's).
Nastran's: CBUSH / CBUSH1D (PBUSHT KN, PBUSH1D SPRING TABLE) U = U(GB) - U(GA), so a grounded one
(GB blank) deflects by -U(GA); CELAS1 (PELAST TKNID) F = f(u1 - u2), so a grounded one deflects by
u1. Where the two differ the table is mirrored: f'(d) = -f(-d).
"""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import SpringTable
from ._common import Units
from ._deck import Deck


def mirrored(x: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The table f'(d) = -f(-d)."""
    return -np.asarray(x, float)[::-1], -np.asarray(f, float)[::-1]


def read_table(deck: Deck, tid: int, rotation: bool, mirror: bool, user: str) -> SpringTable:
    """The TABLED1 ``tid`` as a SpringTable in SI (deflection [m or rad], force [N or N m]) for
    ``user`` (the referencing card's place); mirror: Nastran's deflection is minus flexgvt's."""
    tables = getattr(deck.bdf, "tables_d", None) or {}
    table = tables.get(tid)
    if table is None:
        raise ModelError(f"{user}: references table {tid}, which is not in the deck; add its TABLED1 "
                         "(deflection against force)")
    where = deck.at(table.type, tid)
    if table.type != "TABLED1":
        raise ModelError(f"{where}: a spring's force-deflection table must be a TABLED1 (x: deflection, y: force); "
                         f"{table.type} is not read for springs")
    axes = (str(getattr(table, "xaxis", "LINEAR") or "LINEAR"), str(getattr(table, "yaxis", "LINEAR") or "LINEAR"))
    if axes != ("LINEAR", "LINEAR"):
        raise ModelError(f"{where}: XAXIS/YAXIS {axes[0]}/{axes[1]}: only LINEAR/LINEAR force-deflection tables "
                         "are read; tabulate the curve on linear axes")
    if int(getattr(table, "extrap", 0) or 0) != 0:
        raise ModelError(f"{where}: EXTRAP=1 holds the end forces outside the table; flexgvt extrapolates the end "
                         "slopes (EXTRAP=0). Extend the table over the deflections the spring reaches, with EXTRAP=0")
    u = deck.units
    x = np.asarray(table.x, float) * (1.0 if rotation else u.length)
    f = np.asarray(table.y, float) * (u.moment if rotation else u.force)
    if mirror:
        x, f = mirrored(x, f)
    try:
        return SpringTable.make(x, f, name=f"TABLED1 {tid}")
    except ModelError as exc:
        raise ModelError(f"{where} (used by {user.split(': ')[-1]}): {exc}") from None


def table_rows(table: SpringTable, scale: float, rotation: bool, mirror: bool, u: Units) -> tuple[list, list]:
    """(x, y) of a TABLED1 in the deck's units for ``table`` times ``scale``."""
    x, f = np.asarray(table.x, float), scale * np.asarray(table.f, float)
    if mirror:
        x, f = mirrored(x, f)
    return (list(x / (1.0 if rotation else u.length)), list(f / (u.moment if rotation else u.force)))


def linear_rate(table: SpringTable, scale: float) -> float:
    """The rate a linear Nastran solution uses for a table component (PELAS K, PBUSH Ki, PBUSH1D K):
    the scaled table's slope at zero deflection [SI]."""
    return float(scale * table.evaluate(0.0)[1])


class TableIds:
    """New TABLED1 ids (above the deck's) for written tables, one per distinct (table, scale, sense)."""

    def __init__(self, bdf) -> None:
        self.bdf = bdf
        self.next = max(list(getattr(bdf, "tables_d", None) or {}) + [0]) + 1
        self.made: dict[tuple, int] = {}

    def add(self, table: SpringTable, scale: float, rotation: bool, mirror: bool, u: Units) -> int:
        key = (id(table), float(scale), rotation, mirror)
        if key not in self.made:
            x, y = table_rows(table, scale, rotation, mirror, u)
            self.bdf.add_tabled1(self.next, x, y)
            self.made[key] = self.next
            self.next += 1
        return self.made[key]
