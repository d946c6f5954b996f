"""Universal File Format (UFF/UNV) in and out through pyuff: geometry (15, 2411), functions (58,
58b: FRFs, coherence, time data), modal results (55), units (164).

`read_uff(path)` returns a `UFFData` whose arrays can go straight to the EMA functions:
`data.frfs.frequencies_hz`, `data.frfs.H` (n_freq, n_outputs, n_inputs), `data.geometry`.
Coordinates are converted to SI with the 164 length factor (I-DEAS convention: divide by it); function ordinates are
kept in the
file's units, whose labels are carried with them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import FileFormatError, ModelError
from ..modal import FRFs, ModalSet

DIRECTIONS = {1: "+X", 2: "+Y", 3: "+Z", 4: "+RX", 5: "+RY", 6: "+RZ",
              -1: "-X", -2: "-Y", -3: "-Z", -4: "-RX", -5: "-RY", -6: "-RZ", 0: "scalar"}
FUNCTION_TYPES = {0: "general", 1: "time response", 2: "auto spectrum", 3: "cross spectrum", 4: "FRF",
                  5: "transmissibility", 6: "coherence", 7: "auto correlation", 8: "cross correlation",
                  9: "power spectral density", 10: "energy spectral density", 11: "probability density",
                  12: "spectrum", 13: "cumulative frequency distribution", 14: "peaks valley", 15: "stress/cycles",
                  16: "strain/cycles", 17: "orbit", 18: "mode indicator function", 19: "force pattern",
                  20: "partial power", 21: "partial coherence", 22: "eigenvalue", 23: "eigenvector",
                  24: "shock response spectrum", 25: "finite impulse response filter",
                  26: "multiple coherence", 27: "order function"}


@dataclass(frozen=True)
class TestGeometry:
    """Test points: ids (n,), coordinates xyz (n, 3) [m]."""

    __test__ = False  # not a pytest class

    point_ids: np.ndarray
    xyz: np.ndarray

    def index(self, point_id: int) -> int:
        hits = np.flatnonzero(self.point_ids == point_id)
        if not len(hits):
            raise FileFormatError(f"test point {point_id} is not in the geometry")
        return int(hits[0])


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


# The one FRFs and ModalSet types (flexgvt.modal). ModalResults, the former dataset-55 type, is the
# ModalSet constructor from per-point shapes: ModalResults(frequencies_hz, damping_ratio, shapes
# (n, n_points, 3 or 6), point_ids, frequency_std_hz=None, damping_std=None) -> ModalSet whose DOFs
# are (point, 1..3 or 1..6). UFF 55 has no field for standard deviations: flexgvt writes them on the
# fifth ID line of each dataset as 'STD FREQ_HZ=<f> DAMP=<z>' and reads them back from there.
ModalResults = ModalSet.from_points


@dataclass(frozen=True)
class UFFData:
    """Everything read from a UFF file."""

    path: str
    geometry: TestGeometry | None
    functions: tuple[Function, ...]
    modes: ModalSet | None
    units: dict = field(default_factory=dict)
    skipped: tuple[int, ...] = ()

    @property
    def frfs(self) -> FRFs:
        """The FRFs (function type 4) assembled into an (n_freq, n_outputs, n_inputs) matrix."""
        frf = [f for f in self.functions if f.kind == "FRF"]
        if not frf:
            raise FileFormatError(f"{self.path}: no FRF (dataset 58, function type 4) in the file")
        return assemble_frfs(frf, self.path)


def assemble_frfs(functions, where: str = "") -> FRFs:
    """Arrange FRF functions sharing one frequency axis into H (n_freq, n_outputs, n_inputs)."""
    x = functions[0].x
    for f in functions[1:]:
        if f.x.shape != x.shape or not np.allclose(f.x, x, rtol=1e-9, atol=0):
            raise FileFormatError(f"{where}: FRF {f.response} / {f.reference} has another frequency axis than "
                                  f"{functions[0].response} / {functions[0].reference}; resample them to one axis")
    outputs = sorted({f.response for f in functions})
    inputs = sorted({f.reference for f in functions})
    H = np.full((len(x), len(outputs), len(inputs)), np.nan + 0j)
    for f in functions:
        H[:, outputs.index(f.response), inputs.index(f.reference)] = f.data
    if np.isnan(H).any():
        missing = [(o, i) for a, o in enumerate(outputs) for b, i in enumerate(inputs) if np.isnan(H[0, a, b])]
        raise FileFormatError(f"{where}: the FRF matrix is incomplete: no function for (response, reference) "
                              f"{missing[:5]}; supply every pair or read the functions individually")
    return FRFs(np.asarray(x, float), H, np.array(outputs), np.array(inputs),
                f"{functions[0].ordinate_label}/{functions[0].denominator_label}")


def _read_sets(path: Path):
    import pyuff

    if "\x00" in str(path):
        raise FileFormatError(f"{str(path)!r}: a file name cannot contain a NUL character")
    try:
        found = path.is_file()
    except OSError as exc:  # a name too long, a permission
        raise FileFormatError(f"{str(path)[:200]}: cannot be opened ({exc.strerror})") from None
    if not found:
        raise FileFormatError(f"{path}: no such file" + (" (a folder)" if path.is_dir() else ""))
    try:
        uff = pyuff.UFF(str(path))
        types = list(uff.get_set_types())
    except Exception as exc:  # pyuff raises bare Exceptions on malformed files
        raise FileFormatError(f"{path}: not a readable UFF file ({exc}); check that it is a universal file with "
                              "'    -1' delimiters") from None
    if not types:
        raise FileFormatError(f"{path}: no UFF dataset found (datasets start and end with a '    -1' line)")
    sets = []
    for k in range(len(types)):
        try:
            sets.append(uff.read_sets(k))
        except Exception as exc:
            raise FileFormatError(f"{path}: dataset {k + 1} (type {int(types[k])}) is malformed or truncated: "
                                  f"{type(exc).__name__}: {exc}") from None
    return sets


def _get(s: dict, key: str, where: str):
    """A field of a pyuff dataset dict; missing -> FileFormatError naming the dataset and field."""
    if key not in s:
        raise FileFormatError(f"{where}: no field '{key}' (the dataset is incomplete or of a variant flexgvt "
                              "does not read); re-export the file")
    return s[key]


def _int(value, where: str, what: str) -> int:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: {what} {value!r} is not a number") from None
    if not np.isfinite(v) or v != int(v) or abs(v) > 2**31:
        raise FileFormatError(f"{where}: {what} {value!r} is not an integer id/code")
    return int(v)


def _ids(values, where: str, what: str = "node ids") -> np.ndarray:
    try:
        a = np.atleast_1d(np.asarray(values, float))
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: {what} are not numbers") from None
    if a.ndim != 1 or not np.all(np.isfinite(a)) or np.any(a != np.round(a)) or np.any(np.abs(a) > 2**31):
        raise FileFormatError(f"{where}: {what} must be integers")
    return a.astype(np.int64)


def _column(values, where: str, what: str, n: int | None = None, dtype=float) -> np.ndarray:
    try:
        a = np.atleast_1d(np.asarray(values, dtype))
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: {what} are not numbers (a field shifted or cut?)") from None
    if a.ndim != 1 or (n is not None and len(a) != n):
        raise FileFormatError(f"{where}: {len(a)} values of {what} for {n} nodes (a line is missing or a node "
                              "count changed); re-export the file")
    return a


def _geometry_set(s: dict, where: str, length: float) -> TestGeometry:
    ids = _ids(_get(s, "node_nums", where), where)
    cols = [_column(_get(s, c, where), where, f"{c} coordinates", len(ids)) for c in ("x", "y", "z")]
    xyz = np.column_stack(cols) / length
    if not np.all(np.isfinite(xyz)):
        raise FileFormatError(f"{where}: NaN or infinite coordinates")
    return TestGeometry(ids, xyz)


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
                    str(s.get("orddenom_axis_units_lab", "")).strip())


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


def read_uff(path: str | Path) -> UFFData:
    """Read geometry (15, 2411), functions (58/58b), modes (55) and units (164) from a UFF file.

    Raises FileFormatError naming the file and dataset for anything malformed (missing fields,
    ragged node lists, non-numeric or non-finite values)."""
    path = Path(path)
    sets = _read_sets(path)
    units = {}
    for k, s in enumerate(sets):
        if s.get("type") == 164:
            units = _units_set(s, f"{path}: dataset {k + 1} (type 164)")
    length = units.get("length", 1.0)
    geometry = None
    functions = []
    modes = []
    skipped = []
    for k, s in enumerate(sets):
        t = s.get("type")
        where = f"{path}: dataset {k + 1} (type {t})"
        if t in (15, 2411):
            g = _geometry_set(s, where, length)
            geometry = g if geometry is None else TestGeometry(np.r_[geometry.point_ids, g.point_ids],
                                                               np.r_[geometry.xyz, g.xyz])
        elif t == 58:
            functions.append(_function_set(s, where))
        elif t == 55:
            modes.append((k, s))
        elif t != 164:
            skipped.append(int(t) if isinstance(t, (int, np.integer)) else -1)
    return UFFData(str(path), geometry, tuple(functions), _modes(modes, path), units, tuple(skipped))


def _modes(sets, path) -> ModalSet | None:
    if not sets:
        return None
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
              modes: ModalSet | None = None, binary: bool = False) -> Path:
    """Write geometry (15), units (164, SI), FRFs (58, complex) and modes (55: a ModalSet with labelled
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
        sets.append(pyuff.prepare_15(node_nums=[int(i) for i in geometry.point_ids], def_cs=[0] * n,
                                     disp_cs=[0] * n, color=[1] * n, x=geometry.xyz[:, 0].tolist(),
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
