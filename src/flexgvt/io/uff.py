"""Universal File Format (UFF/UNV) in and out through pyuff: geometry (15, 2411), functions (58,
58b: FRFs, coherence, time data), modal results (55), units (164).

`read_uff(path)` returns a `UFFData` whose arrays can go straight to the EMA functions:
`data.frfs.frequencies_hz`, `data.frfs.H` (n_freq, n_outputs, n_inputs), `data.geometry`.
Coordinates are converted to SI with the 164 length factor (I-DEAS convention: divide by it); function ordinates are
kept in the
file's units, whose labels are carried with them.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..errors import FileFormatError, FlexGVTWarning, ModelError
from ..modal import FRFs, ModalSet

from . import uff_describe, uff_geometry, uff_modes
from .uff_geometry import TestGeometry
from .uff_scan import DIRECTIONS, FUNCTION_TYPES, UFFContents, cut_message, read_blocks
from .uff_time import TimeHistories
from .uff_time import assemble as assemble_time
from .uff_scan import as_column as _column
from .uff_scan import as_ids as _ids
from .uff_scan import as_int as _int
from .uff_scan import get_field as _get


@dataclass(frozen=True)
class Function:
    """One dataset 58: abscissa x (n,), data (n,) real or complex, response and reference DOF."""

    kind: str
    response: tuple[int, int]  # (point id, direction code +-1..6)
    reference: tuple[int, int]
    x: np.ndarray
    data: np.ndarray
    abscissa_label: str = ""
    ordinate_label: str = ""
    denominator_label: str = ""
    spec_type: int = 0  # ordinate specific data type (13 force, 12 acceleration, 8 displacement...)
    name: str = ""


# The one FRFs and ModalSet types (flexgvt.modal). ModalResults, the former dataset-55 type, is the
# ModalSet constructor from per-point shapes: ModalResults(frequencies_hz, damping_ratio, shapes
# (n, n_points, 3 or 6), point_ids, frequency_std_hz=None, damping_std=None) -> ModalSet whose DOFs
# are (point, 1..3 or 1..6). UFF 55 has no field for standard deviations: flexgvt writes them on the
# fifth ID line of each dataset as 'STD FREQ_HZ=<f> DAMP=<z>' and reads them back from there.
ModalResults = ModalSet.from_points


@dataclass(frozen=True)
class UFFData:
    """Everything read from a UFF file: geometry (points in global axes with their displacement
    systems, trace lines, elements), functions (58), modes (55 or 2414), units (164), the dataset
    numbers skipped, and ``dropped``: the incomplete FRF channels read_uff(drop_incomplete=True) left
    out, as text lines."""

    path: str
    geometry: TestGeometry | None
    functions: tuple[Function, ...]
    modes: ModalSet | None
    units: dict = field(default_factory=dict)
    skipped: tuple[int, ...] = ()
    dropped: tuple[str, ...] = ()
    contents: UFFContents | None = field(default=None, repr=False)

    def describe(self) -> str:
        """What the file holds (datasets, functions with their DOFs, geometry, modes)."""
        return str(self.contents) if self.contents is not None else self.path

    def _missing(self, what: str, wanted: str) -> FileFormatError:
        hint = self.contents.hint(wanted) if self.contents is not None else "export it from the test system"
        held = self.contents.summary() if self.contents is not None else "nothing flexgvt reads"
        return FileFormatError(f"{self.path}: no {what} in the file; it holds {held}: {hint}")

    @property
    def frfs(self) -> FRFs:
        """The FRFs (function type 4) assembled into an (n_freq, n_outputs, n_inputs) matrix."""
        frf = [f for f in self.functions if f.kind == "FRF"]
        if not frf:
            raise self._missing("FRF (dataset 58, function type 4)", "frf")
        return assemble_frfs(frf, self.path)

    @property
    def time_histories(self) -> TimeHistories:
        """The time histories (function type 1) as simultaneous channels (flexgvt.ema.estimate_frf_from_time)."""
        th = [f for f in self.functions if f.kind == "time response"]
        if not th:
            raise self._missing("time history (dataset 58, function type 1)", "time")
        return assemble_time(th, self.path)

    def require_modes(self) -> ModalSet:
        """The modes, or an error saying what the file holds instead."""
        if self.modes is None:
            raise self._missing("modes (dataset 55 or 2414)", "modes")
        return self.modes


def missing_pairs(functions) -> tuple[list, list, list]:
    """(outputs, inputs, missing (response, reference) pairs) of FRF functions."""
    outputs = sorted({f.response for f in functions})
    inputs = sorted({f.reference for f in functions})
    have = {(f.response, f.reference) for f in functions}
    return outputs, inputs, [(o, i) for o in outputs for i in inputs if (o, i) not in have]


def _dof(d) -> str:
    return f"{d[0]}{DIRECTIONS.get(d[1], '?')}"


def drop_incomplete_channels(functions, where: str = "") -> tuple[list, tuple[str, ...]]:
    """FRF functions with the incomplete channels left out: repeatedly drop the response (row) or
    reference (column) missing the most pairs, preferring responses, until the matrix is complete.
    Returns (kept functions, lines saying what was dropped and why)."""
    frf = [f for f in functions if f.kind == "FRF"]
    outputs, inputs, missing = missing_pairs(frf)
    dropped = []
    while missing:
        row = {o: sum(m[0] == o for m in missing) for o in outputs}
        col = {i: sum(m[1] == i for m in missing) for i in inputs}
        o, no = max(row.items(), key=lambda kv: kv[1])
        i, ni = max(col.items(), key=lambda kv: kv[1])
        # a reference goes only when it misses more pairs than there are references left to lose rows for
        if ni > len(outputs) / 2 and len(inputs) > 1:
            lost = [m for m in missing if m[1] == i]
            dropped.append(f"reference {_dof(i)}: no FRF for {len(lost)} of {len(outputs)} responses "
                           f"({', '.join(_dof(m[0]) for m in lost[:6])}{'...' if len(lost) > 6 else ''})")
            frf = [f for f in frf if f.reference != i]
        else:
            lost = [m for m in missing if m[0] == o]
            dropped.append(f"response {_dof(o)}: no FRF for reference {', '.join(_dof(m[1]) for m in lost)}")
            frf = [f for f in frf if f.response != o]
        if not frf:
            raise FileFormatError(f"{where}: dropping the incomplete channels leaves no FRF ({'; '.join(dropped)})")
        outputs, inputs, missing = missing_pairs(frf)
    kept = set(map(id, frf))
    return [f for f in functions if f.kind != "FRF" or id(f) in kept], tuple(dropped)


def assemble_frfs(functions, where: str = "") -> FRFs:
    """Arrange FRF functions sharing one frequency axis into H (n_freq, n_outputs, n_inputs)."""
    x = functions[0].x
    for f in functions[1:]:
        if f.x.shape != x.shape or not np.allclose(f.x, x, rtol=1e-9, atol=0):
            raise FileFormatError(f"{where}: FRF {f.response} / {f.reference} has another frequency axis than "
                                  f"{functions[0].response} / {functions[0].reference}; resample them to one axis")
    outputs, inputs, missing = missing_pairs(functions)
    if missing:
        names = ", ".join(f"{_dof(o)} / {_dof(i)}" for o, i in missing[:8]) + (" ..." if len(missing) > 8 else "")
        raise FileFormatError(f"{where}: the FRF matrix is incomplete: {len(missing)} of {len(outputs) * len(inputs)} "
                              f"(response / reference) pairs have no FRF: {names}; supply them, or drop the "
                              "incomplete channels (read_uff(path, drop_incomplete=True); flexgvt ema frf/identify "
                              "--drop-incomplete; project key drop_incomplete = true)")
    H = np.zeros((len(x), len(outputs), len(inputs)), complex)
    seen = set()
    for f in functions:
        key = (f.response, f.reference)
        if key in seen:
            raise FileFormatError(f"{where}: two FRFs for {_dof(key[0])} / {_dof(key[1])}; keep one per pair")
        seen.add(key)
        H[:, outputs.index(f.response), inputs.index(f.reference)] = f.data
    return FRFs(np.asarray(x, float), H, np.array(outputs), np.array(inputs),
                f"{functions[0].ordinate_label}/{functions[0].denominator_label}")


def _also_cut(cut: str | None) -> str:
    return f" (and the file is cut off: {cut.split(': ', 1)[1].split(';')[0]})" if cut else ""


def _read_sets(path: Path):
    """(pyuff dataset dicts, the file's dataset blocks, the cut-off message or None); a file pyuff
    cannot read because it is cut off is refused naming its last complete dataset."""
    import pyuff

    if "\x00" in str(path):
        raise FileFormatError(f"{str(path)!r}: a file name cannot contain a NUL character")
    try:
        found = path.is_file()
    except OSError as exc:  # a name too long, a permission
        raise FileFormatError(f"{str(path)[:200]}: cannot be opened ({exc.strerror})") from None
    if not found:
        raise FileFormatError(f"{path}: no such file" + (" (a folder)" if path.is_dir() else ""))
    _, blocks = read_blocks(path)
    cut = cut_message(path, blocks)
    try:
        uff = pyuff.UFF(str(path))
        types = list(uff.get_set_types())
    except Exception as exc:  # pyuff raises bare Exceptions on malformed files
        if cut:
            raise FileFormatError(cut) from None
        raise FileFormatError(f"{path}: not a readable UFF file ({exc}); check that it is a universal file with "
                              "'    -1' delimiters") from None
    if not types:
        if cut:
            raise FileFormatError(cut)
        raise FileFormatError(f"{path}: no UFF dataset found (datasets start and end with a '    -1' line)")
    sets = []
    for k in range(len(types)):
        try:
            sets.append(uff.read_sets(k))
        except Exception as exc:
            if cut and k >= len(blocks) - 1:
                raise FileFormatError(cut) from None
            line = f", starting at line {blocks[k].first_line}" if k < len(blocks) else ""
            raise FileFormatError(f"{path}: dataset {k + 1} (type {int(types[k])}{line}) is malformed or truncated: "
                                  f"{type(exc).__name__}: {exc}{_also_cut(cut)}") from None
    return sets, blocks, cut


def _function_set(s: dict, where: str) -> Function:
    if "data" not in s or "x" not in s:
        raise FileFormatError(f"{where}: no ordinate data (ordinate data type {s.get('ord_data_type', '?')!r} "
                              "is not one of 2, 4, 5, 6, or the binary record is damaged); re-export the function")
    rsp = (_int(_get(s, "rsp_node", where), where, "response node"),
           _int(_get(s, "rsp_dir", where), where, "response direction"))
    ref = (_int(_get(s, "ref_node", where), where, "reference node"),
           _int(_get(s, "ref_dir", where), where, "reference direction"))
    try:
        data = np.asarray(s["data"])
        x = np.asarray(s["x"], float)
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: function values are not numbers") from None
    if data.ndim != 1 or data.shape != x.shape or len(x) == 0 or not np.issubdtype(data.dtype, np.number):
        raise FileFormatError(f"{where}: {data.size} ordinates for {x.size} abscissa values")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(data))):
        raise FileFormatError(f"{where}: NaN or infinite values in function {rsp[0]}{DIRECTIONS.get(rsp[1], '?')} / "
                              f"{ref[0]}{DIRECTIONS.get(ref[1], '?')}; remove or re-export the channel")
    func_type = _int(_get(s, "func_type", where), where, "function type")
    return Function(FUNCTION_TYPES.get(func_type, f"type {func_type}"), rsp, ref, x, data,
                    str(s.get("abscissa_axis_units_lab", "")).strip(),
                    str(s.get("ordinate_axis_units_lab", "")).strip(),
                    str(s.get("orddenom_axis_units_lab", "")).strip(),
                    _int(s.get("ordinate_spec_data_type", 0), where, "ordinate data type"),
                    str(s.get("rsp_ent_name", "")).strip())


def _units_set(s: dict, where: str) -> dict:
    out = {"description": str(s.get("units_description", "")).strip()}
    for key, name in (("length", "length"), ("force", "force"), ("temp", "temperature")):
        try:
            out[name] = float(_get(s, key, where))
        except (TypeError, ValueError):
            raise FileFormatError(f"{where}: unit factor '{key}' is not a number") from None
    if not (np.isfinite(out["length"]) and out["length"] > 0):
        raise FileFormatError(f"{where}: length unit factor {out['length']!r} must be a positive finite number")
    return out


def _is_nx(sets) -> bool:
    return any(s.get("type") == 151 and "NX" in f"{s.get('db_app', '')} {s.get('program', '')}" for s in sets)


def read_uff(path: str | Path, *, drop_incomplete: bool = False, coordinates: str = "auto") -> UFFData:
    """Read a UFF file: geometry (15, 2411 nodes in global axes through the coordinate systems 18 and
    2420, each node's displacement axes; 82 trace lines, 2412 elements), functions (58/58b), modes
    (55; 2414 normal modes as NX writes them, turned into global axes) and units (164: lengths -> m).

    drop_incomplete: leave out the FRF channels (responses, or a reference) whose (response,
    reference) pairs are not all present; ``.dropped`` and a FlexGVTWarning say what went.
    coordinates: 'definition' (the format: node coordinates in each node's definition system, 2414
    result components in its displacement system), 'global' (both taken as global; the systems still
    give each point's measured directions), 'auto' (definition, except files written by NX, which
    writes both in global components whatever the systems: docs/uff.md).
    Raises FileFormatError naming the file and dataset for anything malformed or cut off."""
    if coordinates not in ("auto", "definition", "global"):
        raise FileFormatError(f"coordinates={coordinates!r} must be 'auto', 'definition' or 'global'")
    path = Path(path)
    sets, blocks, cut = _read_sets(path)
    try:
        data = _parse(path, sets, blocks, drop_incomplete, coordinates)
    except FileFormatError as exc:
        if not cut or str(exc).endswith(_also_cut(cut)):
            raise
        found = re.search(r": dataset (\d+) \(type", str(exc))
        if found is None or int(found.group(1)) >= len(blocks):  # the error is in the cut dataset
            raise FileFormatError(cut) from None
        raise FileFormatError(f"{exc}{_also_cut(cut)}") from None
    if cut:
        raise FileFormatError(cut)
    return data


def _parse(path: Path, sets, blocks, drop_incomplete: bool, coordinates: str) -> UFFData:
    units = {}
    for k, s in enumerate(sets):
        if s.get("type") == 164:
            units = _units_set(s, f"{path}: dataset {k + 1} (type 164)")
    length = units.get("length", 1.0)
    systems: dict = {}
    for k, s in enumerate(sets):  # 2420 first: 18 may refer to them
        if s.get("type") == 2420:
            systems.update(uff_geometry.systems_2420(s, f"{path}: dataset {k + 1} (type 2420)", length))
    for k, s in enumerate(sets):
        if s.get("type") == 18:
            systems = uff_geometry.systems_18(s, f"{path}: dataset {k + 1} (type 18)", length, systems)
    as_global = coordinates == "global" or (coordinates == "auto" and _is_nx(sets))
    geometry = None
    traces: tuple = ()
    elements: tuple = ()
    functions = []
    modes, modes_2414 = [], []
    skipped = []
    for k, s in enumerate(sets):
        t = s.get("type")
        where = f"{path}: dataset {k + 1} (type {t})"
        if t in (15, 2411):
            g = uff_geometry.nodes(s, where, length, systems, as_global)
            geometry = g if geometry is None else geometry.merged(g)
        elif t == 82:
            traces += uff_geometry.traces(s, where)
        elif t == 2412:
            elements += uff_geometry.elements(s, where)
        elif t == 58:
            functions.append(_function_set(s, where))
        elif t == 55:
            modes.append((k, s))
        elif t == 2414:
            modes_2414.append((k, s))
        elif t not in (164, 18, 2420, 151, 2400):
            skipped.append(int(t) if isinstance(t, (int, np.integer)) else -1)
    if geometry is not None:
        notes = (("node coordinates and 2414 result components taken as global (NX writes them so)",)
                 if as_global and coordinates == "auto" else ())
        if not units:
            notes += ("no units dataset 164: coordinates taken as metres",)
        geometry = replace(geometry, traces=traces, elements=elements, coordinate_systems=systems, notes=notes)
    elif traces or elements:
        geometry = TestGeometry(np.zeros(0, int), np.zeros((0, 3)), traces=traces, elements=elements,
                                coordinate_systems=systems)
    if modes and modes_2414:
        raise FileFormatError(f"{path}: modes as both dataset 55 ({len(modes)}) and 2414 ({len(modes_2414)}); "
                              "export one set of modes per file")
    mode_set = _modes(modes, path) if modes else uff_modes.modes_2414(modes_2414, path, geometry, as_global)
    dropped: tuple = ()
    if drop_incomplete:
        functions, dropped = drop_incomplete_channels(functions, str(path))
        if dropped:
            warnings.warn(f"{path}: incomplete FRF channels dropped: {'; '.join(dropped)}", FlexGVTWarning,
                          stacklevel=3)
    contents = uff_describe.contents_of(path, sets, blocks, geometry, mode_set, units, functions)
    return UFFData(str(path), geometry, tuple(functions), mode_set, units, tuple(skipped), dropped, contents)


def describe_uff(path: str | Path) -> UFFContents:
    """What a UFF file holds: datasets by number with counts, the functions (58) by type with their
    response/reference DOFs, points, coordinate systems, trace lines, elements, modes, units; a cut-off
    file is described up to its last complete dataset. ``str()`` of the result is one readable line."""
    return uff_describe.describe(Path(path))


def read_time_histories(path: str | Path) -> TimeHistories:
    """The time histories (58, function type 1) of a file as simultaneous channels; estimate FRFs with
    flexgvt.ema.estimate_frf_from_time(histories, references=..., estimator='H1', nperseg=...)."""
    return read_uff(path).time_histories


def _modes(sets, path) -> ModalSet | None:
    freqs, damps, shapes, fstd, zstd = [], [], [], [], []
    ids = None
    for k, s in sets:
        where = f"{path}: dataset {k + 1} (type 55)"
        nodes = _ids(_get(s, "node_nums", where), where)
        if ids is None:
            ids = nodes
        elif not np.array_equal(nodes, ids):
            raise FileFormatError(f"{where}: modal datasets 55 do not share one point list ({len(nodes)} points "
                                  f"against {len(ids)} in the first); export every mode on the same points")
        try:
            f = float(s.get("freq", np.nan))
            z = float(s.get("modal_damp_vis", 0.0))
        except (TypeError, ValueError):
            raise FileFormatError(f"{where}: frequency or damping is not a number") from None
        if not (np.isfinite(f) and np.isfinite(z)):
            raise FileFormatError(f"{where}: frequency {f!r} or damping {z!r} is not finite (only normal modes, "
                                  "analysis type 2, are read)")
        raw = [s[f"r{i}"] for i in range(1, 7) if f"r{i}" in s]
        if not raw:
            raise FileFormatError(f"{where}: no shape values (r1...r6)")
        kind = complex if any(np.iscomplexobj(r) for r in raw) else float
        shape = np.column_stack([_column(r, where, "shape values", len(ids), kind) for r in raw])
        if shapes and shape.shape != shapes[0].shape:
            raise FileFormatError(f"{where}: {shape.shape[1]} values per node against {shapes[0].shape[1]} in the "
                                  "first mode; export every mode alike")
        if not np.all(np.isfinite(shape)):
            raise FileFormatError(f"{where}: NaN or infinite shape values")
        freqs.append(f)
        damps.append(z)
        shapes.append(shape)
        fs = zs = np.nan
        for key in ("id5", "id4"):
            text = str(s.get(key, ""))
            if text.strip().startswith("STD "):
                try:
                    parts = dict(p.split("=", 1) for p in text.split()[1:])
                    fs, zs = float(parts["FREQ_HZ"]), float(parts["DAMP"])
                except (KeyError, ValueError):
                    raise FileFormatError(f"{where}: mode {len(freqs)}: unreadable standard deviations "
                                          f"'{text.strip()}'; expected 'STD FREQ_HZ=<f> DAMP=<z>'") from None
        fstd.append(fs)
        zstd.append(zs)
    has_std = np.all(np.isfinite(fstd))
    return ModalSet.from_points(np.array(freqs), np.array(damps), np.array(shapes), ids,
                                np.array(fstd) if has_std else None, np.array(zstd) if has_std else None,
                                source=str(path))


def shapes_at_points(shapes: np.ndarray, outputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Channel shapes (n_modes, n_outputs) -> per-point translations (n_modes, n_points, 3) using each
    channel's (point id, direction code +-1..3); returns (point ids, shapes)."""
    outputs = np.asarray(outputs).astype(int)
    points = np.unique(outputs[:, 0])
    out = np.zeros((shapes.shape[0], len(points), 3), dtype=shapes.dtype)
    for k, (pt, d) in enumerate(outputs):
        if abs(d) not in (1, 2, 3):
            raise FileFormatError(f"output {k} (point {pt}, direction {d}) is not a translation; UFF 55 export "
                                  "of rotational channels is not supported")
        out[:, np.searchsorted(points, pt), abs(d) - 1] += np.sign(d) * shapes[:, k]
    return points, out


def write_uff(path: str | Path, *, geometry: TestGeometry | None = None, frfs: FRFs | None = None,
              modes: ModalSet | None = None, binary: bool = False,
              time_histories: TimeHistories | None = None) -> Path:
    """Write geometry (15; points whose displacement axes are turned get a dataset 18 system each),
    units (164, SI), FRFs (58, complex), time histories (58 type 1, real
    double; force channels marked with ordinate type 13) and modes (55: a ModalSet with labelled
    translation or rotation DOFs, laid out per point) to a new UFF file."""
    import pyuff

    for name, arr in (("geometry", None if geometry is None else geometry.xyz),
                      ("FRFs", None if frfs is None else frfs.H), ("modes", None if modes is None else modes.shapes)):
        if arr is not None and not np.all(np.isfinite(arr)):
            raise FileFormatError(f"{path}: cannot write {name} containing NaN or infinity (pyuff would store "
                                  "them as zeros); clean the data first")
    path = Path(path)
    if path.exists():
        path.unlink()
    uff = pyuff.UFF(str(path))
    sets = [pyuff.prepare_164(units_code=1, units_description="SI", temp_mode=1, length=1.0, force=1.0, temp=1.0,
                              temp_offset=273.15)]
    if geometry is not None:
        n = len(geometry.point_ids)
        disp = [0] * n
        turned = [k for k in range(n) if not np.allclose(geometry.axes[k], np.eye(3), atol=1e-12)]
        if turned:  # each point's displacement axes as a dataset 18 system (origin, +x point, +xz point)
            o = geometry.xyz[turned]
            R = geometry.axes[turned]
            disp = [0] * n
            for j, k in enumerate(turned):
                disp[k] = j + 1
            sets.append(pyuff.prepare_18(cs_num=list(range(1, len(turned) + 1)), cs_type=[0] * len(turned),
                                         ref_cs_num=[0] * len(turned), color=[1] * len(turned),
                                         method=[1] * len(turned), cs_name=[f"P{int(geometry.point_ids[k])}"
                                                                            for k in turned],
                                         ref_o=o.tolist(), x_point=(o + R[:, 0]).tolist(),
                                         xz_point=(o + R[:, 2]).tolist()))
        sets.append(pyuff.prepare_15(node_nums=[int(i) for i in geometry.point_ids], def_cs=[0] * n,
                                     disp_cs=disp, color=[1] * n, x=geometry.xyz[:, 0].tolist(),
                                     y=geometry.xyz[:, 1].tolist(), z=geometry.xyz[:, 2].tolist()))
    if frfs is not None:
        f = frfs.frequencies_hz
        uniform = len(f) > 1 and np.allclose(np.diff(f), f[1] - f[0])
        for a, (pt, d) in enumerate(frfs.outputs):
            for b, (rp, rd) in enumerate(frfs.inputs):
                sets.append(pyuff.prepare_58(binary=int(binary), func_type=4, rsp_node=int(pt), rsp_dir=int(d),
                                             ref_node=int(rp), ref_dir=int(rd), ord_data_type=6, num_pts=len(f),
                                             abscissa_spacing=int(uniform), abscissa_min=float(f[0]),
                                             abscissa_inc=float(f[1] - f[0]) if len(f) > 1 else 0.0,
                                             abscissa_spec_data_type=18, ordinate_spec_data_type=12,
                                             orddenom_spec_data_type=13, id1="FRF", data=frfs.H[:, a, b], x=f))
    if time_histories is not None:
        th = time_histories
        if not np.all(np.isfinite(th.data)):
            raise FileFormatError(f"{path}: cannot write time histories containing NaN or infinity")
        for k, (pt, d) in enumerate(np.asarray(th.dofs, int)):
            spec = int(th.spec_types[k]) if k < len(th.spec_types) else 0
            unit = str(th.units[k]) if k < len(th.units) else ""
            sets.append(pyuff.prepare_58(binary=int(binary), func_type=1, rsp_node=int(pt), rsp_dir=int(d),
                                         ref_node=0, ref_dir=0, ord_data_type=4, num_pts=th.n_samples,
                                         abscissa_spacing=1, abscissa_min=float(th.t0_s),
                                         abscissa_inc=1.0 / float(th.sample_rate_hz), abscissa_spec_data_type=17,
                                         abscissa_axis_units_lab="s", ordinate_spec_data_type=spec,
                                         ordinate_axis_units_lab=unit, orddenom_spec_data_type=0, id1="time",
                                         data=np.asarray(th.data[k], float),
                                         x=th.t0_s + np.arange(th.n_samples) / th.sample_rate_hz))
    if modes is not None:
        try:
            point_ids, point_shapes = modes.point_shapes()
        except ModelError as exc:
            raise FileFormatError(f"{path}: cannot write the modes as dataset 55: {exc}") from None
        for m in range(len(modes.frequencies_hz)):
            shp = point_shapes[m]
            cols = {f"r{i + 1}": shp[:, i] for i in range(shp.shape[1])}
            std = {}
            if modes.frequency_std_hz is not None and modes.damping_std is not None:
                std["id5"] = (f"STD FREQ_HZ={float(modes.frequency_std_hz[m]):.6g} "
                              f"DAMP={float(modes.damping_std[m]):.6g}")
            sets.append(pyuff.prepare_55(**std, model_type=1, analysis_type=2, data_ch=2, spec_data_type=8, data_type=2,
                                         n_data_per_node=shp.shape[1], load_case=1, mode_n=m + 1,
                                         freq=float(modes.frequencies_hz[m]), modal_m=1.0,
                                         modal_damp_vis=float(modes.damping_ratio[m]), modal_damp_his=0.0,
                                         node_nums=[int(i) for i in point_ids], **cols))
    uff.write_sets(sets, mode="add")
    return path
