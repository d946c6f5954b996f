"""Outputs of a run: the updated model as Nastran bulk data, identified and predicted modes as UFF 55,
and the prediction tables as CSV.

Every file is written atomically: into a temporary file in the same folder, then renamed over the
target (os.replace), so a run killed while writing leaves the previous file or the new one, never
half of one. A configuration's name becomes part of a file name through safe_name.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import warnings
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..model import Configuration
from ..io.tables import write_csv


_UNSAFE = re.compile(r"[^A-Za-z0-9._-]")
_RESERVED = {"CON", "PRN", "AUX", "NUL", *(f"COM{k}" for k in range(1, 10)), *(f"LPT{k}" for k in range(1, 10))}
MAX_NAME = 48  # characters kept of a name (with its 8-character digest, well below any file system's limit)


def safe_name(name: str) -> str:
    """A configuration name as a file-name part: kept as it is when it only holds letters, digits,
    '.', '_' and '-' (not first a '.', at most 48 characters, not a Windows device name); otherwise
    every other character becomes '_', it is cut to 48 characters and '-' plus the first 8 hex
    digits of the SHA-256 of the original name is appended. Two different names never map to one
    (kept names are distinct, changed ones carry their digest)."""
    name = str(name)
    if (name and not _UNSAFE.search(name) and not name.startswith(".") and len(name) <= MAX_NAME
            and name.split(".")[0].upper() not in _RESERVED):
        return name
    base = _UNSAFE.sub("_", name).lstrip(".")[:MAX_NAME] or "_"
    return f"{base}-{hashlib.sha256(name.encode('utf-8', 'surrogatepass')).hexdigest()[:8]}"


_TEMPORARY = re.compile(r"\..+\.\d+\.tmp(\.[^.]*)?")


def _temporary(path: Path) -> Path:
    """A temporary name beside ``path`` with its suffix (writers that look at it still see it)."""
    return path.with_name(f".{path.stem}.{os.getpid()}.tmp{path.suffix}")


@contextmanager
def atomic(path: Path):
    """Yield a temporary path beside ``path``; once the block has written it, rename it to ``path``
    (removed instead if the block fails)."""
    path = Path(path)
    tmp = _temporary(path)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def write_text_atomic(path: Path, text: str) -> Path:
    """``text`` (UTF-8) to ``path``, atomically and flushed to disk before the rename."""
    with atomic(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
    return Path(path)


def write_json_atomic(path: Path, obj, **kw) -> Path:
    return write_text_atomic(path, json.dumps(obj, **kw))


def remove_temporaries(*folders: Path) -> None:
    """Delete the temporary files a killed run left in ``folders`` (this process holds the run lock)."""
    for folder in folders:
        for tmp in Path(folder).glob(".*.tmp*"):
            if tmp.is_file() and _TEMPORARY.fullmatch(tmp.name):
                tmp.unlink(missing_ok=True)
        for tmp in Path(folder).glob(".report-*"):
            if tmp.is_dir():
                shutil.rmtree(tmp, ignore_errors=True)


def write_outputs(res, out: Path) -> dict[str, str]:
    """Write what the project's [outputs] table asks for into ``out``; returns {name: path}."""
    spec = res.project.spec.outputs
    files: dict[str, str] = {}
    if spec.bdf and (res.update is not None or getattr(res, "stages", None)):
        files["bdf"] = str(_atomically(write_updated_bdf, res, out / "updated.bdf"))
    if spec.uff:
        for name, item in res.identified.items():
            path = _atomically(lambda p, item=item: write_identified_uff(res.project, item, p),
                               out / f"identified-{safe_name(name)}.uff")
            if path is not None:
                files[f"identified {name}"] = str(path)
        for key, pred in res.predictions.items():
            files[f"prediction {key}"] = str(_atomically(write_modes_uff, pred.free,
                                                         out / f"predicted-free-free-{key}.uff"))
    for key, pred in res.predictions.items():
        # flexgvt.report's CSV: None as an empty cell, numbers rounded to what they support
        path = _atomically(lambda p, pred=pred: write_csv(round_rows(pred.rows), p), out / f"prediction-{key}.csv")
        files[f"prediction table {key}"] = str(path)
    return files


def _significant(v: float, digits: int) -> float:
    return float(f"{v:.{digits}g}")


def round_value(key: str, value, row: dict | None = None):
    """A table cell rounded to what it supports (for CSV), by its column name: a frequency (*_hz) to
    two significant digits of its standard deviation (the column <name>_std_hz of the same row) or to
    5 significant digits without one, a standard deviation to 2 significant digits, MAC-like
    measures (mac, comac, mpc, frac) to 3 decimals, percentages to 2 decimals, angles (*_deg) to 0.1,
    other floats to 6 significant digits. Anything not a finite float is returned as it is."""
    if isinstance(value, (list, tuple)):
        return type(value)(round_value(key, v, row) for v in value)
    if isinstance(value, (bool, np.bool_, int, np.integer)) or not isinstance(value, (float, np.floating)):
        return value
    v = float(value)
    if not np.isfinite(v) or v == 0.0:
        return v
    k = key.lower()
    if "_std" in k or k.startswith("std"):
        return _significant(v, 2)
    if k.endswith("_hz"):
        std = (row or {}).get(k[:-3] + "_std_hz")
        if isinstance(std, (float, np.floating)) and np.isfinite(std) and std > 0:
            return round(v, max(0, 1 - int(np.floor(np.log10(float(std))))))
        return _significant(v, 5)
    if any(m in k.split("_") for m in ("mac", "comac", "mpc", "frac")):
        return round(v, 3)
    if k.endswith("percent"):
        return round(v, 2)
    if k.endswith("_deg"):
        return round(v, 1)
    return _significant(v, 6)


def round_rows(rows: list[dict]) -> list[dict]:
    """Rows with every number rounded by round_value (for CSV files: the report's and the prediction's)."""
    return [{k: round_value(k, v, r) for k, v in r.items()} for r in rows]


def _atomically(writer, *args):
    """writer(*args[:-1], temporary path), flushed to disk and renamed to args[-1]; None (and nothing
    renamed) when the writer wrote nothing."""
    *first, path = args
    path = Path(path)
    tmp = _temporary(path)
    try:
        if writer(*first, tmp) is None:
            return None
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
        return path
    finally:
        if tmp.exists():
            tmp.unlink()


def write_updated_bdf(res, path: Path) -> Path:
    """The user's deck with updated values, or a compact deck (one free-free subcase) for a built-in model."""
    from ..io import write_bdf
    project = res.project
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the writer's notes on split properties are expected here
        if project.deck is not None:
            return write_bdf(res.model, path, template=project.deck)
        return write_bdf(res.model, path, configurations=[Configuration("free_free")],
                         n_modes=project.spec.prediction.n_modes + 6)


def write_identified_uff(project, item, path: Path) -> Path | None:
    """Identified modes as UFF 55 at the test points (with their geometry, dataset 15)."""
    from ..io.uff import ModalResults, TestGeometry, shapes_at_points, write_uff
    if item.shapes is None:
        return None
    points, shapes = shapes_at_points(np.real(item.shapes), item.outputs)
    node_map, offsets = project.sensors.get(item.configuration, ({}, {}))
    model = project.model
    xyz = []
    for p in points:
        node = node_map.get(int(p), int(p))
        try:
            base = model.xyz[model.index_of([node])[0]]
        except Exception:  # a test point with no FE node: geometry left at the origin
            base = np.zeros(3)
        xyz.append(base + np.asarray(offsets.get(int(p), np.zeros(3)), float))
    return write_uff(path, geometry=TestGeometry(np.asarray(points), np.asarray(xyz)),
                     modes=ModalResults(item.frequencies_hz, item.damping_ratio, shapes, np.asarray(points)))


def write_modes_uff(modes, path: Path) -> Path:
    """FE modes (translations at every node, deformed geometry) as UFF 15 + 55."""
    from ..io.uff import ModalResults, TestGeometry, write_uff
    ids = np.asarray(modes.node_ids)
    return write_uff(path, geometry=TestGeometry(ids, np.asarray(modes.state.positions)),
                     modes=ModalResults(np.asarray(modes.frequencies_hz), np.zeros(len(modes.frequencies_hz)),
                                        np.asarray(modes.shapes)[:, :, :3], ids))
