"""Tables (rows of dicts) as CSV files: the one CSV layout of the workflow's outputs and the
report's tables/*.csv (None as an empty cell, floats in full, arrays space-separated)."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np


def columns(rows: list[dict]) -> list[str]:
    """The keys of ``rows`` in first-seen order."""
    cols: list[str] = []
    for r in rows:
        cols += [k for k in r if k not in cols]
    return cols


def write_csv(rows: list[dict], path: Path) -> Path:
    """Rows of dicts as CSV with the raw keys as header; None as an empty cell, floats in full."""
    cols = columns(rows)

    def cell(v):
        if v is None:
            return ""
        if isinstance(v, (tuple, list, np.ndarray)):
            return " ".join(cell(x) for x in v)
        if isinstance(v, (np.floating, float)):
            return repr(float(v))
        if isinstance(v, np.integer):
            return str(int(v))
        return str(v)

    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for r in rows:
            w.writerow([cell(r.get(c)) for c in cols])
    return Path(path)
