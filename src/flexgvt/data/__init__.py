"""Measured tables from published GVTs of very flexible structures, shipped with flexgvt.

    import flexgvt as fg
    fg.data.names()                       # ['a3tb_wt', 'strip_366_gvt', 'xhale_lab_gvt']
    gvt = fg.data.load("strip_366_gvt")   # the parsed table (a new dict on every call)
    fg.data.source("strip_366_gvt")       # where its figures come from

Figures are as published, in the unit and rounding of the source (each table's 'about' entry
says which); README.md beside the tables records how they came into the project.
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path

from ..errors import FileFormatError, FlexGVTError

__all__ = ["UnknownTableError", "load", "names", "read", "source"]

_HANDED = "handed to the project as shared/data/{name}.json on 2026-11-26; figures unchanged"
_SOURCES = {
    "strip_366_gvt": "Impact GVT of the 3.66 m aluminium strip hung outboard and inboard (15 measured elastic "
                     "frequencies and damping ratios per layout, setup, suspension points, the original work's "
                     "tuned-model frequencies), as published in the doctoral study docs/method.md summarises",
    "xhale_lab_gvt": "Laboratory GVT of the X-HALE flying wing on its spring-and-pulley suspension, outboard and "
                     "inboard (8 measured frequencies per layout with mode types, airframe data, suspension as "
                     "identified, the original work's 30 design variables and its initial and updated model "
                     "frequencies, the free-flying test's bungees), as published in the doctoral study "
                     "docs/method.md summarises",
    "a3tb_wt": "The 3D-printed swept wing (half model of the A3TB UAV): geometry, materials, FE model, boundary "
               "conditions, GVT setup and tables 5.1-5.9, design variables and updating procedure, as published "
               "in chapter 5 of the doctoral study docs/method.md summarises (what was not published: "
               "'missing_for_rebuild')",
}


class UnknownTableError(FlexGVTError, LookupError):
    """No shipped table has that name."""


def names() -> list[str]:
    """The names of the shipped tables, sorted."""
    return sorted(p.name[:-5] for p in resources.files(__name__).iterdir() if p.name.endswith(".json"))


def _check(name: str) -> None:
    if not isinstance(name, str) or name not in names():
        raise UnknownTableError(f"no shipped table {name!r}; available: {', '.join(names())} "
                                "(flexgvt.data.names())")


def load(name: str) -> dict:
    """The shipped table ``name`` (see names()) parsed from its JSON file: a new dict each call."""
    _check(name)
    return json.loads(resources.files(__name__).joinpath(f"{name}.json").read_text(encoding="utf-8"))


def source(name: str) -> str:
    """Where the figures of table ``name`` come from and how they came into the project."""
    _check(name)
    return f"{_SOURCES[name]}; {_HANDED.format(name=name)}"


def read(path: str | Path) -> dict:
    """A table of the same form as the shipped ones from a JSON file of your own (an object at the
    top). Raises FileFormatError naming the file when it is missing, unreadable or not a JSON object."""
    path = Path(path)
    shown = _shown(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileFormatError(f"{shown}: no such file; give the path of a measured table (.json)") from None
    except IsADirectoryError:
        raise FileFormatError(f"{shown}: is a folder, not a measured table (.json)") from None
    except UnicodeDecodeError as exc:
        raise FileFormatError(f"{shown}: not a text (UTF-8) file ({exc.reason} at byte {exc.start}); "
                              "a measured table is JSON") from None
    except (OSError, ValueError) as exc:
        raise FileFormatError(f"{shown}: cannot be read "
                              f"({exc.strerror if isinstance(exc, OSError) else exc})") from None
    try:
        obj = json.loads(text)
    except json.JSONDecodeError as exc:
        raise FileFormatError(f"{shown}, line {exc.lineno}, column {exc.colno}: not valid JSON ({exc.msg})") from None
    except RecursionError:
        raise FileFormatError(f"{shown}: JSON nested too deeply") from None
    if not isinstance(obj, dict):
        raise FileFormatError(f"{shown}: a measured table is a JSON object ({{...}}), not a {type(obj).__name__}")
    return obj


def _shown(path: Path) -> str:
    """The path as a message shows it: quoted when it holds control characters, shortened past 200."""
    text = str(path)
    if any(ord(c) < 32 for c in text):
        text = repr(text)
    return text if len(text) <= 200 else f"{text[:90]}...{text[-90:]} ({len(text)} characters)"
