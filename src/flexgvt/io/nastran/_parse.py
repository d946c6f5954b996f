"""The card parser's side of reading a deck: where every card sits (file, line), INCLUDEs and the
expansion budget, and the parse itself (pyNastran's tokeniser: small, large and free field,
continuations, replication), with its errors translated into FileFormatErrors naming file, line
and card."""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

from ...errors import FileFormatError, FlexGVTError, ModelError
from ._limits import ExpansionBudget

# Id namespaces as pyNastran keeps them (Nastran accepts, e.g., an RBAR and a CONM2 with the same id).
ELEMENT_NAMESPACE = ("CBAR", "CBEAM", "CROD", "CONROD", "CTUBE", "CQUAD4", "CTRIA3", "CQUAD8", "CTRIA6", "CQUADR",
                     "CTRIAR", "CSHEAR", "CHEXA", "CPENTA", "CTETRA", "CELAS1", "CELAS2", "CELAS3", "CELAS4", "CDAMP1",
                     "CDAMP2", "CDAMP3", "CDAMP4", "CVISC", "CBUSH", "CBUSH1D", "CGAP")
MASS_NAMESPACE = ("CONM1", "CONM2", "CMASS1", "CMASS2", "CMASS3", "CMASS4")
RIGID_NAMESPACE = ("RBE2", "RBE3", "RBAR", "RBE1", "RROD", "RSPLINE")
PROPERTY_NAMESPACE = ("PBAR", "PBARL", "PBEAM", "PBEAML", "PROD", "PTUBE", "PSHELL", "PCOMP", "PCOMPG", "PSHEAR",
                      "PSOLID", "PELAS", "PDAMP", "PVISC", "PBUSH", "PBUSH1D", "PGAP", "PMASS")
MATERIAL_NAMESPACE = ("MAT1", "MAT2", "MAT8", "MAT9")
COORD_NAMESPACE = ("CORD2R", "CORD2C", "CORD2S", "CORD1R", "CORD1C", "CORD1S")

_INCLUDE = re.compile(r"^\s*include\s+'([^']+)'", re.IGNORECASE)


class CardIndex:
    """Where each card (name, first field) sits in the deck and its includes: for messages only."""

    def __init__(self, path: Path):
        self.places: dict[tuple[str, str], list[tuple[str, int]]] = {}
        self.root = Path(path).resolve().parent
        self.missing_includes: list[tuple[str, int, str]] = []
        self.bad_includes: list[tuple[str, int, str]] = []  # INCLUDE lines not of the form INCLUDE 'path'
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


def _safe_str(value) -> str:
    try:
        return str(value)
    except Exception:  # noqa: BLE001 - pyNastran objects whose str needs cross-referencing
        return type(value).__name__


class QuietLog:
    """Logger handed to pyNastran: keeps its messages (for error context) instead of printing them."""

    level = "error"

    def __init__(self):
        self.messages: list[str] = []

    def _keep(self, msg, *args, **kwargs):
        self.messages.append(exception_text(msg) if isinstance(msg, BaseException) else _safe_str(msg))

    debug = info = warning = error = exception = critical = _keep

    def __getattr__(self, name):  # any other cpylog method
        if name.startswith("__"):
            raise AttributeError(name)
        return self._keep

    def __deepcopy__(self, memo):
        return QuietLog()


def _is_begin_bulk(line: str) -> bool:
    return line.split("$", 1)[0].strip().upper().replace(" ", "") == "BEGINBULK"


def parse_bdf(path: Path, index: CardIndex, notes: list[str]):
    """pyNastran BDF of ``path`` (with or without executive/case control), errors as FileFormatError.
    A plain BEGIN BULK repeated inside the bulk data (a pasted deck) is ignored and noted."""
    from pyNastran.bdf.bdf import BDF

    if index.bad_includes:  # pyNastran would dump the deck to ./pyNastran_crash.bdf and fail
        f, ln, text = index.bad_includes[0]
        raise FileFormatError(f"{f}:{ln}: {text!r} is not an INCLUDE statement flexgvt reads; write INCLUDE 'path' "
                              "on one line, the path in single quotes")
    if index.missing_includes:
        f, ln, target = index.missing_includes[0]
        raise FileFormatError(f"{f}:{ln}: INCLUDE file {target} does not exist; fix the path (relative paths are "
                              "taken from the main deck's folder)")
    with open(path, "r", errors="replace") as handle:
        lines = handle.readlines()
    if not any(line.strip() and not line.lstrip().startswith("$") for line in lines):
        raise FileFormatError(f"{path}: the file is empty; give a Nastran bulk data deck")
    has_cend = any(line.strip().upper().startswith("CEND") for line in lines)
    has_begin = any(line.strip().upper().replace(" ", "").startswith("BEGINBULK") for line in lines)
    for k in [i for i, line in enumerate(lines) if _is_begin_bulk(line)][1:]:
        lines[k] = "$" + lines[k]  # a comment keeps the line numbers
        notes.append(f"{path}:{k + 1}: BEGIN BULK repeated inside the bulk data: ignored")
    lines = absolute_include_lines(lines, path.resolve().parent)
    punch = False
    if not has_cend:
        if has_begin:
            lines = ["CEND\n"] + lines
        else:
            punch = True
    log = QuietLog()
    bdf = BDF(log=log)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            bdf.read_bdf(io.StringIO("".join(lines)), xref=False, punch=punch, validate=True)
    except FlexGVTError:
        raise
    except Exception as exc:  # pyNastran raises many kinds; translate them into one message
        raise _parse_error(path, index, exc, log) from None
    bdf.bdf_filename = str(path)
    return bdf


_CARD_IN_MSG = re.compile(r"card\s*=\s*\[\s*'([A-Za-z0-9*]+)'\s*,\s*'?([^',\]]*)'?")


def exception_text(exc: BaseException) -> str:
    """str(exc), or its class name when pyNastran's message itself fails (it prints cards)."""
    try:
        return str(exc).strip()
    except Exception:  # noqa: BLE001 - e.g. a LOAD card whose repr needs cross-referencing
        return type(exc).__name__


def _card_in_traceback(exc: BaseException) -> tuple[str, str]:
    """(card name, first field) of the card pyNastran was adding when ``exc`` was raised, from the
    innermost frame of its card parser (its own message may name none, or fail to print)."""
    name, ident, tb = "", "", exc.__traceback__
    while tb is not None:
        lines = tb.tb_frame.f_locals.get("card_lines")
        if isinstance(lines, list) and lines and isinstance(lines[0], str):
            name, ident = split_first_fields(lines[0])
        tb = tb.tb_next
    return name, ident


def _parse_error(path: Path, index: CardIndex, exc: Exception, log: QuietLog) -> FileFormatError:
    text = exception_text(exc)
    where = str(path)
    card = ""
    found = _CARD_IN_MSG.search(text) or next((m for m in (_CARD_IN_MSG.search(x) for x in log.messages[::-1]) if m),
                                              None)
    if found is None:
        for msg in log.messages[::-1]:
            if msg.startswith("problem adding"):
                found = re.search(r"\[\s*'([A-Za-z0-9*]+)'\s*,\s*'?([^',\]]*)'?", msg)
                if found:
                    break
    if found is not None:
        name, ident = found.group(1).upper().rstrip("*"), found.group(2).strip()
    else:
        name, ident = _card_in_traceback(exc)
    if name:
        place = index.where(name, ident)
        where = place or where
        card = f" in {name} {ident}"
    first = text.splitlines()[0] if text else type(exc).__name__
    hint = "fix the field named above (see the Nastran Quick Reference Guide for the card's format)"
    if first == type(exc).__name__:  # pyNastran gave no message (a bare assert) or one that fails to print
        first = f"pyNastran refused the card ({first})"
        hint = "check its fields against the Nastran Quick Reference Guide (ids above 0, references, real or integer)"
    if isinstance(exc, (AssertionError,)) and ("old_" in text or "duplicate" in text.lower()):
        return FileFormatError(f"{where}: duplicate id{card}: {first}; give every card a unique id")
    return FileFormatError(f"{where}: cannot read the deck{card}: {first}; {hint}")


def check_duplicates(path: Path, index: CardIndex) -> None:
    problems = []
    for label, names in (("node", ("GRID",)), ("element", ELEMENT_NAMESPACE), ("mass element", MASS_NAMESPACE),
                         ("rigid element", RIGID_NAMESPACE), ("property", PROPERTY_NAMESPACE),
                         ("material", MATERIAL_NAMESPACE), ("coordinate system", COORD_NAMESPACE)):
        for ident, hits in index.duplicates(names).items():
            places = ", ".join(f"{card} at {f}:{ln}" for card, f, ln in hits[:4])
            problems.append(f"{label} id {ident} is defined {len(hits)} times ({places})")
    if problems:
        raise ModelError(f"{path}: duplicate ids: " + "; ".join(problems[:10]) +
                         ("; ..." if len(problems) > 10 else "") + ". Give every node, element, property, material "
                         "and coordinate system a unique id")
