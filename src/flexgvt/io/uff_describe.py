"""describe_uff: what a UFF file holds, read leniently (a cut-off file up to its last complete dataset)."""

from __future__ import annotations

import contextlib
import io
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

from ..errors import FileFormatError
from .uff_scan import DIRECTIONS, FUNCTION_TYPES, UFFContents, cut_message, read_blocks


def _name(node, code) -> str:
    try:
        return f"{int(node)}{DIRECTIONS.get(int(code), '?')}" if int(code) else f"{int(node)} (scalar)"
    except (TypeError, ValueError):
        return "?"


def _units_text(units: dict) -> str:
    if not units:
        return ""
    return f"{units.get('description', '')} (length factor {units.get('length', 1.0):g})".strip()


def contents_of(path, sets, blocks, geometry, modes, units: dict, functions=None) -> UFFContents:
    """The contents of a file read by read_uff (functions as io.uff.Function) or by describe (raw dicts)."""
    counts = Counter(int(s.get("type", -1)) if isinstance(s.get("type"), (int, np.integer)) else -1 for s in sets)
    if functions is None:
        functions = []
        for s in sets:
            if s.get("type") != 58:
                continue
            try:
                kind = FUNCTION_TYPES.get(int(s.get("func_type", -1)), f"type {s.get('func_type')}")
            except (TypeError, ValueError):
                kind = "type ?"
            functions.append((kind, _name(s.get("rsp_node"), s.get("rsp_dir")),
                              _name(s.get("ref_node"), s.get("ref_dir")), int(np.size(s.get("x", ())))))
    else:
        functions = [(f.kind, _name(*f.response), _name(*f.reference), len(f.x)) for f in functions]
    n_cs = sum(len(np.atleast_1d(s.get("CS_sys_labels", s.get("cs_num", ())))) for s in sets
               if s.get("type") in (18, 2420))
    n_traces = sum(1 for s in sets if s.get("type") == 82)
    n_el = sum(len(v) for s in sets if s.get("type") == 2412 for k, v in s.items()
               if isinstance(k, (int, np.integer)) and isinstance(v, list))
    n_points = 0 if geometry is None else len(geometry.point_ids)
    if geometry is None:
        n_points = sum(len(np.atleast_1d(s.get("node_nums", ()))) for s in sets if s.get("type") in (15, 2411))
    n_modes = modes.n_modes if modes is not None else sum(1 for s in sets if s.get("type") in (55, 2414))
    return UFFContents(str(path), dict(sorted(counts.items())), tuple(functions), n_points, n_cs, n_traces, n_el,
                       n_modes, _units_text(units), cut_message(path, blocks))


def describe(path: Path) -> UFFContents:
    import pyuff

    try:
        found = path.is_file()
    except (OSError, ValueError):
        found = False
    if not found:
        raise FileFormatError(f"{path}: no such file")
    data, blocks = read_blocks(path)
    complete = [b for b in blocks if b.last_line is not None]
    sets = []
    with tempfile.TemporaryDirectory(prefix="flexgvt_uff_") as tmp:
        source = path
        if complete and len(complete) < len(blocks):  # read the complete part of a cut-off file
            lines = data.split(b"\n")
            source = Path(tmp) / "complete.uff"
            source.write_bytes(b"\n".join(lines[:complete[-1].last_line]) + b"\n")
        if complete:
            try:
                with contextlib.redirect_stdout(io.StringIO()):
                    uff = pyuff.UFF(str(source))
                    for k in range(len(uff.get_set_types())):
                        try:
                            sets.append(uff.read_sets(k))
                        except Exception:  # noqa: BLE001 - a damaged dataset is described by its number only
                            sets.append({"type": complete[k].number if k < len(complete) else -1})
            except Exception:  # noqa: BLE001 - pyuff's bare exceptions: describe from the scan
                sets = [{"type": b.number} for b in complete]
    units = {}
    for s in sets:
        if s.get("type") == 164:
            try:
                units = {"description": str(s.get("units_description", "")).strip(), "length": float(s["length"])}
            except (KeyError, TypeError, ValueError):
                units = {}
    return contents_of(path, sets, blocks, None, None, units)
