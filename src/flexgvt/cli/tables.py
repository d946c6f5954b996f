"""Console tables a test engineer can paste: every number in full, every unit shown, and no wider
than the console (80 columns in a log or a pipe unless COLUMNS says otherwise).

A table wider than the console is split by columns into parts that each repeat the key columns
(mode, label ...), instead of letting the terminal library shrink the columns to "0.89…". Cells
and headers are plain text, never markup: "[kg]" shows as "[kg]".
"""

from __future__ import annotations

from typing import Sequence

from rich.console import Console
from rich.table import Table
from rich.text import Text

_RIGHT = "right"


def _cell(v, digits: int = 4) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.{digits}f}"
    return str(v)


WRAP = 40  # text cells longer than this (with spaces) wrap at spaces; numbers never do


def _column_width(header: str, cells: Sequence[str]) -> int:
    """The narrowest width that shows every number on one line, wraps text longer than WRAP
    characters at spaces and breaks the header only at spaces."""
    words = [len(w) for text in (header, *cells) for w in text.split()]
    lines = [len(line) if " " not in line else min(len(line), WRAP) for c in cells for line in c.splitlines()]
    return max([0, *words, *lines])


def _table_width(widths: Sequence[int]) -> int:
    """Width of a rich table with the default box (an edge and a rule between columns, one space of
    padding each side)."""
    return sum(widths) + 3 * len(widths) + 1


def split_columns(widths: Sequence[int], key: int, width: int) -> list[list[int]]:
    """Column indices of each part: the first ``key`` columns in every part, the others packed in
    order while the part fits ``width`` (a single column wider than that gets a part of its own)."""
    keys = list(range(min(key, len(widths))))
    parts: list[list[int]] = []
    part = list(keys)
    for j in range(len(keys), len(widths)):
        if len(part) > len(keys) and _table_width([widths[i] for i in part + [j]]) > width:
            parts.append(part)
            part = list(keys)
        part.append(j)
    if len(part) > len(keys) or not parts:
        parts.append(part)
    return parts


def _widen(widths: list[int], full: list[int], width: int) -> list[int]:
    """Column widths grown from ``widths`` towards ``full`` (headers unbroken) while the table fits
    ``width``; the spare columns go to the headers that need the fewest."""
    out = list(widths)
    spare = width - _table_width(out)
    for k in sorted(range(len(out)), key=lambda k: full[k] - out[k]):
        grow = min(max(spare, 0), full[k] - out[k])
        out[k] += grow
        spare -= grow
    return out


def tables(title: str, headers: Sequence[str], rows: Sequence[Sequence], *, key: int = 1, width: int = 80,
           justify: Sequence[str] | None = None) -> list[Table]:
    """``rows`` (cells: str, int, float with 4 decimals, None as blank) under ``headers`` as one rich
    Table, or several when wider than ``width`` columns, each repeating the first ``key`` columns
    and titled "(part i of n)". Text is never read as markup."""
    cells = [[_cell(v) for v in r] for r in rows]
    widths = [_column_width(h, [r[j] for r in cells if j < len(r)]) for j, h in enumerate(headers)]
    full = [max(w, len(h)) for w, h in zip(widths, headers)]  # the header on one line
    parts = split_columns(widths, key, width)
    out = []
    for n, part in enumerate(parts):
        name = title if len(parts) == 1 else f"{title} (part {n + 1} of {len(parts)})"
        t = Table(title=Text(name), title_justify="left")
        fixed = _widen([widths[j] for j in part], [full[j] for j in part], width)
        for j, w in zip(part, fixed):
            t.add_column(Text(headers[j]), justify=(justify[j] if justify else _RIGHT), width=w, overflow="fold")
        for r in cells:
            t.add_row(*[Text(r[j] if j < len(r) else "") for j in part])
        out.append(t)
    return out


def print_table(console: Console, title: str, headers: Sequence[str], rows: Sequence[Sequence], *, key: int = 1,
                justify: Sequence[str] | None = None) -> None:
    """tables(...) printed to ``console`` at its width."""
    for t in tables(title, headers, rows, key=key, width=console.width, justify=justify):
        console.print(t)


def header(key: str) -> str:
    """A results key as a column header with its unit: 'free_hz' -> 'free [Hz]',
    'error_percent' -> 'error [%]', 'mass_kg' -> 'mass [kg]'."""
    for suffix, unit in (("_percent", "[%]"), ("_hz", "[Hz]"), ("_kg", "[kg]"), ("_m", "[m]"), ("_s", "[s]")):
        if key.endswith(suffix):
            return f"{key[: -len(suffix)].replace('_', ' ')} {unit}"
    return key.replace("_", " ")
