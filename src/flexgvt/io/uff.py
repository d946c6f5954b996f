"""Universal File Format (UFF/UNV) in and out through pyuff: geometry (15, 2411), functions (58,
58b: FRFs, coherence, time data), modal results (55), units (164).

`read_uff(path)` returns a `UFFData` whose arrays can go straight to the EMA functions:
`data.frfs.frequencies_hz`, `data.frfs.H` (n_freq, n_outputs, n_inputs), `data.geometry`.
Coordinates are converted to SI with the 164 length factor (I-DEAS convention: divide by it); function ordinates are kept in the
file's units, whose labels are carried with them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import FileFormatError

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


@dataclass(frozen=True)
class FRFs:
    """FRF matrix on a common frequency axis.

    frequencies_hz (n_freq,); H (n_freq, n_outputs, n_inputs) complex; outputs/inputs:
    (n, 2) arrays of (point id, direction code); units: ordinate/denominator labels.
    """

    frequencies_hz: np.ndarray
    H: np.ndarray
    outputs: np.ndarray
    inputs: np.ndarray
    units: str = ""


@dataclass(frozen=True)
class ModalResults:
    """Dataset 55 modes: frequencies_hz (n,), damping_ratio (n,), shapes (n, n_points, 3 or 6), point_ids;
    frequency_std_hz, damping_std (n,) or None. UFF 55 has no field for standard deviations: flexgvt
    writes them on the fifth ID line of each dataset as 'STD FREQ_HZ=<f> DAMP=<z>' and reads them back
    from there (other readers show the line as text)."""

    frequencies_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    point_ids: np.ndarray
    frequency_std_hz: np.ndarray | None = None
    damping_std: np.ndarray | None = None


@dataclass(frozen=True)
class UFFData:
    """Everything read from a UFF file."""

    path: str
    geometry: TestGeometry | None
    functions: tuple[Function, ...]
    modes: ModalResults | None
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

    if not path.exists():
        raise FileFormatError(f"{path}: no such file")
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


def read_uff(path: str | Path) -> UFFData:
    """Read geometry (15, 2411), functions (58/58b), modes (55) and units (164) from a UFF file."""
    path = Path(path)
    sets = _read_sets(path)
    units = {}
    for s in sets:
        if s["type"] == 164:
            units = {"description": str(s.get("units_description", "")).strip(), "length": float(s["length"]),
                     "force": float(s["force"]), "temperature": float(s["temp"])}
    length = units.get("length", 1.0)
    geometry = None
    functions = []
    modes = []
    skipped = []
    for k, s in enumerate(sets):
        t = s["type"]
        where = f"{path}: dataset {k + 1} (type {t})"
        if t in (15, 2411):
            ids = np.asarray(s["node_nums"], float).astype(int)
            xyz = np.column_stack([s["x"], s["y"], s["z"]]).astype(float) / length
            if not np.all(np.isfinite(xyz)):
                raise FileFormatError(f"{where}: NaN or infinite coordinates")
            geometry = TestGeometry(ids, xyz) if geometry is None else TestGeometry(
                np.r_[geometry.point_ids, ids], np.r_[geometry.xyz, xyz])
        elif t == 58:
            data = np.asarray(s["data"])
            x = np.asarray(s["x"], float)
            if data.shape != x.shape or len(x) == 0:
                raise FileFormatError(f"{where}: {len(data)} ordinates for {len(x)} abscissa values")
            if not (np.all(np.isfinite(x)) and np.all(np.isfinite(data))):
                raise FileFormatError(f"{where}: NaN or infinite values in function "
                                      f"{int(s['rsp_node'])}{DIRECTIONS.get(int(s['rsp_dir']), '?')} / "
                                      f"{int(s['ref_node'])}{DIRECTIONS.get(int(s['ref_dir']), '?')}; remove or "
                                      "re-export the channel")
            kind = FUNCTION_TYPES.get(int(s["func_type"]), f"type {int(s['func_type'])}")
            functions.append(Function(kind, (int(s["rsp_node"]), int(s["rsp_dir"])),
                                      (int(s["ref_node"]), int(s["ref_dir"])), x, data,
                                      str(s.get("abscissa_axis_units_lab", "")).strip(),
                                      str(s.get("ordinate_axis_units_lab", "")).strip(),
                                      str(s.get("orddenom_axis_units_lab", "")).strip()))
        elif t == 55:
            modes.append(s)
        elif t != 164:
            skipped.append(int(t))
    return UFFData(str(path), geometry, tuple(functions), _modes(modes, path), units, tuple(skipped))


def _modes(sets, path) -> ModalResults | None:
    if not sets:
        return None
    freqs, damps, shapes, fstd, zstd = [], [], [], [], []
    ids = np.asarray(sets[0]["node_nums"], float).astype(int)
    for s in sets:
        if not np.array_equal(np.asarray(s["node_nums"], float).astype(int), ids):
            raise FileFormatError(f"{path}: modal datasets 55 do not share one point list")
        freqs.append(float(s.get("freq", np.nan)))
        damps.append(float(s.get("modal_damp_vis", 0.0)))
        cols = [np.asarray(s[f"r{i}"]) for i in range(1, 7) if f"r{i}" in s]
        shapes.append(np.column_stack(cols))
        fs = zs = np.nan
        for key in ("id5", "id4"):
            text = str(s.get(key, ""))
            if text.strip().startswith("STD "):
                try:
                    parts = dict(p.split("=", 1) for p in text.split()[1:])
                    fs, zs = float(parts["FREQ_HZ"]), float(parts["DAMP"])
                except (KeyError, ValueError):
                    raise FileFormatError(f"{path}: mode {len(freqs)}: unreadable standard deviations '{text.strip()}'; "
                                          "expected 'STD FREQ_HZ=<f> DAMP=<z>'") from None
        fstd.append(fs)
        zstd.append(zs)
    has_std = np.all(np.isfinite(fstd))
    return ModalResults(np.array(freqs), np.array(damps), np.array(shapes), ids,
                        np.array(fstd) if has_std else None, np.array(zstd) if has_std else None)


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
              modes: ModalResults | None = None, binary: bool = False) -> Path:
    """Write geometry (15), units (164, SI), FRFs (58, complex) and modes (55) to a new UFF file."""
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
        for m in range(len(modes.frequencies_hz)):
            shp = modes.shapes[m]
            cols = {f"r{i + 1}": shp[:, i] for i in range(shp.shape[1])}
            std = {}
            if modes.frequency_std_hz is not None and modes.damping_std is not None:
                std["id5"] = f"STD FREQ_HZ={float(modes.frequency_std_hz[m]):.6g} DAMP={float(modes.damping_std[m]):.6g}"
            sets.append(pyuff.prepare_55(**std, model_type=1, analysis_type=2, data_ch=2, spec_data_type=8, data_type=2,
                                         n_data_per_node=shp.shape[1], load_case=1, mode_n=m + 1,
                                         freq=float(modes.frequencies_hz[m]), modal_m=1.0,
                                         modal_damp_vis=float(modes.damping_ratio[m]), modal_damp_his=0.0,
                                         node_nums=[int(i) for i in modes.point_ids], **cols))
    uff.write_sets(sets, mode="add")
    return path
