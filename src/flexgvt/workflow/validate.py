"""Checks of everything a project file names, run by load_project before any long step.

Paths (no NUL, no over-long name, output folder inside the project), and every named file opened
and parsed: UFF FRFs (readable, one frequency axis, the band inside it), identified modes (UFF 55,
CSV, JSON: sizes that agree), test point CSV files and the reference JSON. A bad file fails in the
first second, naming the project file, the key and the file, never after an hour of updating.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

from ..errors import FlexGVTError
from .projectbase import ProjectError

MAX_NAME_BYTES = 255  # one path component (ext4, xfs, apfs, ntfs)
MAX_PATH_BYTES = 4000  # a whole path (Linux PATH_MAX is 4096)
MAX_JSON_BYTES = 50_000_000  # a reference or modes JSON larger than this is not one


def checked_path(folder: Path, value: str, where: str, what: str) -> Path:
    """``value`` (relative to ``folder`` unless absolute) as a Path; ProjectError for a NUL character,
    an over-long path or name, or an unknown '~user'."""
    if "\x00" in value:
        raise ProjectError(f"{where}: the {what} path {value!r} contains a NUL character; remove it")
    encoded = os.fsencode(value)
    if len(encoded) > MAX_PATH_BYTES or any(len(os.fsencode(p)) > MAX_NAME_BYTES for p in Path(value).parts):
        raise ProjectError(f"{where}: the {what} path is too long ({len(value)} characters; a file or folder name may "
                           f"have at most {MAX_NAME_BYTES} bytes, a path {MAX_PATH_BYTES}); shorten it")
    try:
        p = Path(value).expanduser()
    except RuntimeError:
        raise ProjectError(f"{where}: the {what} path {value!r} names an unknown user's home folder") from None
    return p if p.is_absolute() else folder / p


def need_file(path: Path, where: str, what: str) -> Path:
    """``path`` if it is an existing regular file, else ProjectError naming it."""
    try:
        ok = path.is_file()
    except OSError as exc:
        raise ProjectError(f"{where}: {what} '{_short(path)}' cannot be opened ({exc.strerror})") from None
    if not ok:
        raise ProjectError(f"{where}: {what} '{_short(path)}' not found (paths are relative to the project file's "
                           "folder)")
    return path


def output_dir(folder: Path, value: str, allow_outside: bool, where: str) -> Path:
    """The output folder: inside the project folder unless ``allow_outside``; not an existing file."""
    out = checked_path(folder, value, where, "output directory")
    if not allow_outside:
        base = folder.resolve()
        try:
            inside = out.resolve().is_relative_to(base)
        except (OSError, RuntimeError):  # a symlink loop
            inside = False
        if not inside:
            raise ProjectError(f"{where}: '{value}' is outside the project folder {base}; give a folder inside it "
                               "(e.g. \"results\"), or set outputs.allow_outside = true to write there on purpose")
    try:
        if out.exists() and not out.is_dir():
            raise ProjectError(f"{where}: '{value}' exists and is not a folder; give another output directory")
    except OSError as exc:
        raise ProjectError(f"{where}: '{_short(out)}' cannot be used ({exc.strerror})") from None
    return out


def _short(path: Path, n: int = 120) -> str:
    s = str(path)
    return s if len(s) <= n else s[: n // 2] + "..." + s[-n // 2:]


def read_json(path: Path, where: str):
    """The parsed JSON document of ``path``; ProjectError for binary, non-JSON or oversized files."""
    try:
        if path.stat().st_size > MAX_JSON_BYTES:
            raise ProjectError(f"{where}: {path} is larger than {MAX_JSON_BYTES // 1_000_000} MB; not a JSON table")
        text = path.read_bytes()[: MAX_JSON_BYTES + 1].decode("utf-8")
    except UnicodeDecodeError:
        raise ProjectError(f"{where}: {path} is not a text file (expected JSON)") from None
    except OSError as exc:
        raise ProjectError(f"{where}: {path} cannot be read ({exc.strerror})") from None
    try:
        return json.loads(text)
    except ValueError as exc:  # JSONDecodeError
        raise ProjectError(f"{where}: {path} is not valid JSON ({exc}); expected "
                           '{"free_free": {"frequencies_hz": [...], "labels": [...]}}') from None
    except RecursionError:
        raise ProjectError(f"{where}: {path}: JSON nested too deeply") from None


def reference_table(reference, where: str) -> tuple[np.ndarray, list[str]]:
    """(frequencies_hz (n,), labels) of a reference document {'free_free': {'frequencies_hz': [...],
    'labels': [...]}} (or the inner object itself); ProjectError naming the key on any other layout."""
    ref = reference.get("free_free", reference) if isinstance(reference, dict) else reference
    if not isinstance(ref, dict):
        raise ProjectError(f"{where}: expected an object {{'free_free': {{'frequencies_hz': [...]}}}}, got "
                           f"{type(ref).__name__}")
    f = ref.get("frequencies_hz", [])
    if not isinstance(f, list) or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in f):
        raise ProjectError(f"{where}: 'frequencies_hz' must be a flat list of numbers [Hz]")
    f = np.asarray(f, float)
    if not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ProjectError(f"{where}: 'frequencies_hz' must hold finite frequencies > 0 [Hz]")
    labels = ref.get("labels", [])
    if not isinstance(labels, list) or not all(isinstance(s, str) for s in labels):
        raise ProjectError(f"{where}: 'labels' must be a list of strings")
    if labels and len(labels) != len(f):
        raise ProjectError(f"{where}: {len(labels)} labels for {len(f)} frequencies")
    return f, labels


def read_reference(path: Path, where: str) -> tuple[np.ndarray, list[str]]:
    """The reference frequencies [Hz] and labels of a JSON file (see reference_table)."""
    return reference_table(read_json(path, where), f"{where}: {path}")


def test_points(path: Path, where: str) -> np.ndarray:
    """Rows (point, node[, dx, dy, dz]) of a test point CSV file with a header line; integer ids."""
    try:
        text = path.read_bytes().decode("utf-8")
    except UnicodeDecodeError:
        raise ProjectError(f"{where}: {path} is not a text file (expected CSV point,node,dx,dy,dz)") from None
    except OSError as exc:
        raise ProjectError(f"{where}: {path} cannot be read ({exc.strerror})") from None
    rows = []
    for i, line in enumerate(text.splitlines()[1:], start=2):
        if not line.strip():
            continue
        try:
            rows.append([float(v) for v in line.split(",")])
        except ValueError:
            raise ProjectError(f"{where}: {path} line {i}: not a number where one is expected (columns "
                               "point,node,dx,dy,dz [m])") from None
        if len(rows[-1]) not in (2, 5) or len(rows[-1]) != len(rows[0]):
            raise ProjectError(f"{where}: {path} line {i}: {len(rows[-1])} columns; expected point,node or "
                               "point,node,dx,dy,dz on every line")
    if not rows:
        raise ProjectError(f"{where}: {path}: no test point (a header line, then point,node[,dx,dy,dz] lines)")
    a = np.array(rows)
    ids = a[:, :2]
    if not np.all(np.isfinite(a)) or np.any(ids != np.round(ids)) or np.any(np.abs(ids) > 2**31):
        raise ProjectError(f"{where}: {path}: point and node ids must be integers and offsets finite")
    if len(np.unique(ids[:, 0])) != len(ids):
        raise ProjectError(f"{where}: {path}: a test point is listed twice")
    return a


def check_test_data(project, k: int, c, where: str) -> None:
    """Open and parse the test data of configuration ``c`` (its [configurations.test] table)."""
    from .identification import read_modes
    t = c.test
    loc = f"{where}: configurations[{k}] ('{c.name}').test"
    if t.band_hz is not None and not 0 <= t.band_hz[0] < t.band_hz[1]:
        raise ProjectError(f"{loc}.band_hz: {t.band_hz} must be [low, high] with 0 <= low < high [Hz]")
    if t.select_hz is not None and not all(math.isfinite(v) and v > 0 for v in t.select_hz):
        raise ProjectError(f"{loc}.select_hz: frequencies must be finite and > 0 [Hz]")
    if t.frfs is not None or t.time is not None:
        import warnings

        from ..errors import FlexGVTWarning
        from .identification import measured_frfs
        if t.frfs is not None and not t.frfs:
            raise ProjectError(f"{loc}.frfs: no file given")
        try:
            with warnings.catch_warnings():  # the run says what it drops
                warnings.simplefilter("ignore", FlexGVTWarning)
                frfs, files, _ = measured_frfs(project, t, loc)
        except ProjectError:
            raise
        except FlexGVTError as exc:
            raise ProjectError(f"{loc}.{'frfs' if t.frfs is not None else 'time'}: {exc}") from None
        f = frfs.frequencies_hz
        if len(f) < 8 or np.any(np.diff(f) <= 0):
            raise ProjectError(f"{loc}.{'frfs' if t.frfs is not None else 'nperseg'}: {len(f)} frequency lines, not "
                               "strictly increasing or fewer than 8")
        if t.band_hz is not None and (t.band_hz[1] <= f[0] or t.band_hz[0] >= f[-1]):
            raise ProjectError(f"{loc}.band_hz: {t.band_hz} Hz is outside the FRFs' {f[0]:.4g}-{f[-1]:.4g} Hz")
        _check_sensors(project, c.name, frfs.outputs, f"{loc}.points", ", ".join(files))
        return
    try:
        modes = read_modes(project.file(t.modes), c.name, t.key)
    except FlexGVTError as exc:
        raise ProjectError(f"{loc}.modes: {exc}") from None
    f = np.asarray(modes.frequencies_hz)
    if f.ndim != 1 or len(f) == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ProjectError(f"{loc}.modes: {modes.source}: frequencies must be finite and > 0 [Hz], one or more")
    if not np.all(np.isfinite(np.asarray(modes.damping_ratio, float))):
        raise ProjectError(f"{loc}.modes: {modes.source}: damping ratios must be finite")
    if modes.shapes is not None:
        sh, out = np.asarray(modes.shapes), np.asarray(modes.outputs)
        if sh.ndim != 2 or out.ndim != 2 or out.shape[1] != 2 or sh.shape != (len(f), len(out)) \
                or not np.all(np.isfinite(sh)):
            raise ProjectError(f"{loc}.modes: {modes.source}: shapes must be (modes, channels) finite values with "
                               "one (point, direction) output per channel")
    if modes.shapes is not None:
        _check_sensors(project, c.name, modes.outputs, f"{loc}.points", modes.source)
    n = len(f)
    if t.use_modes is not None:
        bad = [m for m in t.use_modes if not 1 <= m <= n]
        if bad:
            raise ProjectError(f"{loc}.use_modes: modes {bad} do not exist ({n} in {modes.source}; 1-based)")
        n = len(t.use_modes)
    if t.labels is not None and len(t.labels) != n:
        raise ProjectError(f"{loc}.labels: {len(t.labels)} labels for {n} modes")


def _check_sensors(project, name: str, outputs, where: str, source: str) -> None:
    """Every measured channel maps to a model node (test point -> FE node) in a translation direction."""
    from ..correlation import Sensors
    node_map, offsets = project.sensors.get(name, ({}, {}))
    try:
        sensors = Sensors.from_outputs(np.asarray(outputs), node_map or None, offsets or None)
        sensors.rows(project.model.node_ids)
    except FlexGVTError as exc:
        raise ProjectError(f"{where}: {source}: {exc}") from None
