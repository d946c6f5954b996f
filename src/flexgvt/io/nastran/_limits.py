"""Bounds on what a deck may hold: expansions (THRU ranges, card replication) checked on the raw
lines before pyNastran expands them, ids within Nastran's range and real fields that are finite
and small enough for their products to stay finite."""

from __future__ import annotations

import contextlib
import io
import math
import re
from pathlib import Path

from ...errors import FileFormatError

MAX_ID = 99_999_999  # Nastran: 0 < id < 100,000,000 for grids, elements, properties, materials
MAX_EXPANDED_IDS = 10_000_000  # ids all THRU ranges of a deck may expand to (pyNastran: ~0.5 GB, ~2 s)
MAX_REPLICATED_CARDS = 100_000  # cards "=(n)" replication may create (pyNastran: ~4 s per 100,000)
MAX_COORDINATE_M = 1e6  # |basic coordinate| [m]: element lengths enter to the third power and more
MAX_SECTION_RATIO = 1e12  # largest / smallest nonzero of a section's Iy, Iz, J
MAX_ENFORCED_SIZES = 10.0  # |enforced translation| / the structure's largest extent
MAX_VALUE = 1e30  # |real field|: stiffness, mass and their products (E I / L^3, K / M, squares) stay finite

_REPLICATE = re.compile(r"^=\((\d+)\)")
_CC_TOKENS = re.compile(r"[\s,=()/]+")


def _int(text) -> int | None:
    s = str(text).strip()
    return int(s) if re.fullmatch(r"[+-]?\d+", s) else None


def _line_fields(line: str) -> tuple[str, list[str]]:
    """First field (card name or continuation marker) and the data fields of a bulk data line."""
    s = line.split("$", 1)[0].rstrip("\r\n")
    if "," in s:
        parts = s.split(",")
        return parts[0].strip(), [p.strip() for p in parts[1:]]
    if "\t" in s:
        s = s.expandtabs(8)
    head = s[:8].strip()
    width = 16 if head.endswith("*") else 8
    body = s[8:72]
    return head, [body[i:i + width].strip() for i in range(0, len(body), width)]


class ExpansionBudget:
    """Counts, over every file of a deck, the ids its THRU ranges and the cards its replications
    will expand to; raises a FileFormatError at the first card past a limit."""

    def __init__(self):
        self.ids = 0
        self.replicated = 0

    def scan(self, path: Path, lines: list[str]) -> None:
        bulk = not any(ln.upper().lstrip().startswith(("CEND", "BEGIN")) for ln in lines)
        card: list[str] = []
        start, name = 0, ""
        for lineno, line in enumerate(lines, start=1):
            if not line.strip() or line.lstrip().startswith("$"):
                continue
            upper = line.upper().replace(" ", "")
            if not bulk:
                if upper.startswith("BEGINBULK"):
                    bulk = True
                elif "THRU" in upper:
                    self._ranges(_CC_TOKENS.split(line.split("$", 1)[0].upper()), path, lineno, "case control SET")
                continue
            head, fields = _line_fields(line)
            replicate = _REPLICATE.match(head.replace(" ", ""))
            if replicate:
                self.replicated += int(replicate.group(1))
                if self.replicated > MAX_REPLICATED_CARDS:
                    raise FileFormatError(
                        f"{path}:{lineno}: replication {head.strip()} brings the deck to {self.replicated:,} "
                        f"replicated cards, more than the {MAX_REPLICATED_CARDS:,} flexgvt expands; write the cards "
                        "out or fix the count")
            if head and head[0] not in "+*" and not head.startswith("="):
                self._card(card, path, start, name)
                card, start, name = [], lineno, head.rstrip("*").upper()
            card.extend(fields)
        self._card(card, path, start, name)

    def _card(self, fields: list[str], path: Path, lineno: int, name: str) -> None:
        if any(f.upper() == "THRU" for f in fields):
            self._ranges([f.upper() for f in fields], path, lineno, name)

    def _ranges(self, tokens: list[str], path: Path, lineno: int, name: str) -> None:
        for k, tok in enumerate(tokens):
            if tok != "THRU" or k == 0 or k + 1 >= len(tokens):
                continue
            lo, hi = _int(tokens[k - 1]), _int(tokens[k + 1])
            if lo is None or hi is None or hi < lo:
                continue  # pyNastran reports a malformed range itself
            step = _int(tokens[k + 3]) if k + 3 < len(tokens) and tokens[k + 2] == "BY" else None
            count = (hi - lo) // (abs(step) if step else 1) + 1
            self.ids += count
            if self.ids > MAX_EXPANDED_IDS:
                raise FileFormatError(
                    f"{path}:{lineno}: {name} {tokens[k - 1]} THRU {tokens[k + 1]} expands to {count:,} ids, which "
                    f"brings the deck past the {MAX_EXPANDED_IDS:,} ids flexgvt expands from THRU ranges; "
                    "check the range (Nastran ids are at most 99999999)")


# Names of raw fields pyNastran's _field_map leaves out, for messages.
_FIELD_NAMES = {
    "GRID": {3: "X1", 4: "X2", 5: "X3"},
    "CBAR": {5: "X1", 6: "X2", 7: "X3"}, "CBEAM": {5: "X1", 6: "X2", 7: "X3"},
    "PROD": {3: "A", 4: "J", 5: "C", 6: "NSM"}, "CONROD": {5: "A", 6: "J", 7: "C", 8: "NSM"},
    "PBAR": {3: "A", 4: "I1", 5: "I2", 6: "J", 7: "NSM", 9: "C1", 10: "C2", 11: "D1", 12: "D2", 13: "E1", 14: "E2",
             15: "F1", 16: "F2", 17: "K1", 18: "K2", 19: "I12"},
    "CONM2": {4: "M", 5: "X1", 6: "X2", 7: "X3", 9: "I11", 10: "I21", 11: "I22", 12: "I31", 13: "I32", 14: "I33"},
    "FORCE": {4: "F", 5: "N1", 6: "N2", 7: "N3"}, "MOMENT": {4: "M", 5: "N1", 6: "N2", 7: "N3"},
    "GRAV": {3: "A", 4: "N1", 5: "N2", 6: "N3"}, "CELAS2": {2: "K"}, "PELAS": {2: "K", 3: "GE", 4: "S"},
}


def field_label(card, index: int) -> str:
    """'field 6 (RHO)' for raw field ``index`` of a pyNastran card (continuation lines counted)."""
    line, field = divmod(index - 1, 8)
    name = (getattr(card, "_field_map", None) or {}).get(index) or _FIELD_NAMES.get(card.type, {}).get(index)
    where = f"field {field + 2}" + (f" of continuation {line}" if line else "")
    return where + (f" ({str(name).upper()})" if name else "")


def bad_reals(card) -> list[tuple[int, float]]:
    """(raw field index, value) of the real fields of ``card`` that are not finite or exceed MAX_VALUE."""
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # pyNastran prints before raising on bad nodes
            fields = card.raw_fields()
    except Exception:  # noqa: BLE001 - a card pyNastran cannot print is checked where it is read
        return []
    out = []
    for k, v in enumerate(fields):
        if isinstance(v, float) and not (math.isfinite(v) and abs(v) <= MAX_VALUE):
            out.append((k, v))
    return out
