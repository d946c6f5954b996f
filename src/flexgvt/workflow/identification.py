"""Step 1: the measured modes of each configuration, identified from FRFs (PolyMAX + LSFD) or read
as already identified (UFF 55, CSV or JSON), with the sensors that map FE shapes onto them."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import FlexGVTError
from .projectbase import Project, ProjectError


@dataclass
class Identified:
    """Measured modes of one configuration.

    frequencies_hz, damping_ratio (n,); shapes (n, n_channels) or None; outputs (n_channels, 2)
    (test point, direction code); labels; stabilisation: the PolyMAX diagram when FRFs were
    identified (else None); frfs: those FRFs; source: the file(s) read."""

    configuration: str
    frequencies_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray | None
    outputs: np.ndarray | None
    labels: tuple[str, ...]
    source: str
    stabilisation: object | None = None
    frfs: object | None = None
    diagram: dict | None = None
    frequency_std_hz: np.ndarray | None = None
    damping_std: np.ndarray | None = None

    def measured(self, project: Project):
        """The flexgvt.updating.Measured of this configuration (sensors mapped to the FE nodes)."""
        from ..correlation import Sensors
        from ..updating import Measured
        sensors = None
        if self.shapes is not None:
            node_map, offsets = project.sensors.get(self.configuration, ({}, {}))
            try:
                sensors = Sensors.from_outputs(self.outputs, node_map or None, offsets or None)
            except FlexGVTError as exc:
                raise ProjectError(f"configuration '{self.configuration}' ({self.source}): {exc}") from None
        return Measured(self.configuration, self.frequencies_hz, self.shapes, sensors, labels=self.labels,
                        frequency_std_hz=self.frequency_std_hz)

    def as_dict(self) -> dict:
        """JSON layout (also read back as test data: modes = 'file.json')."""
        out = {"configuration": self.configuration, "source": self.source,
               "frequencies_hz": self.frequencies_hz.tolist(), "damping_ratio": self.damping_ratio.tolist(),
               "labels": list(self.labels)}
        if self.frequency_std_hz is not None:
            out["frequency_std_hz"] = self.frequency_std_hz.tolist()
        if self.damping_std is not None:
            out["damping_std"] = self.damping_std.tolist()
        if self.shapes is not None:
            out["outputs"] = np.asarray(self.outputs).astype(int).tolist()
            out["shapes_real"] = np.real(self.shapes).tolist()
            out["shapes_imag"] = np.imag(self.shapes).tolist()
        return out


def identify(project: Project, name: str) -> Identified:
    """The measured modes of configuration ``name`` as its [configurations.test] table says."""
    spec = next(c for c in project.spec.configurations if c.name == name)
    t = spec.test
    if t is None:
        raise ProjectError(f"{project.path}: configuration '{name}' has no test data")
    where = f"{project.path}: configurations '{name}' test"
    try:
        if t.frfs is not None:
            out = _from_frfs(project, name, t)
        else:
            out = read_modes(project.file(t.modes), name, t.key)
    except ProjectError:
        raise
    except FlexGVTError as exc:
        raise ProjectError(f"{where}: {exc}") from None
    keep = np.arange(len(out.frequencies_hz))
    if t.use_modes is not None:
        bad = [m for m in t.use_modes if not 1 <= m <= len(keep)]
        if bad:
            raise ProjectError(f"{where}.use_modes: modes {bad} do not exist ({len(keep)} identified; 1-based)")
        keep = np.asarray(t.use_modes, int) - 1
    labels = tuple(t.labels) if t.labels is not None else tuple(out.labels[k] for k in keep if k < len(out.labels))
    if t.labels is not None and len(t.labels) != len(keep):
        raise ProjectError(f"{where}.labels: {len(t.labels)} labels for {len(keep)} modes")
    pick = (lambda v: None if v is None else v[keep])  # noqa: E731
    return Identified(name, out.frequencies_hz[keep], out.damping_ratio[keep],
                      None if out.shapes is None else out.shapes[keep], out.outputs, labels, out.source,
                      out.stabilisation, out.frfs, frequency_std_hz=pick(out.frequency_std_hz),
                      damping_std=pick(out.damping_std))


def _from_frfs(project: Project, name: str, t) -> Identified:
    from ..ema import identify_wide_band, polymax
    from ..io.uff import assemble_frfs, read_uff
    files = [t.frfs] if isinstance(t.frfs, str) else list(t.frfs)
    functions = []
    for f in files:
        functions += [fn for fn in read_uff(project.file(f)).functions if fn.kind == "FRF"]
    if not functions:
        raise ProjectError(f"configuration '{name}': no FRF (dataset 58, function type 4) in {files}")
    frfs = assemble_frfs(functions, where=", ".join(files))
    band = tuple(t.band_hz) if t.band_hz is not None else None
    if t.wide:
        stab, modes = None, identify_wide_band(frfs, frequency_band=band, max_order=t.max_order,
                                               min_fraction=t.min_fraction)
    else:
        stab = polymax(frfs, max_order=t.max_order, frequency_band=band)
        modes = stab.select(frequencies_hz=t.select_hz, min_fraction=t.min_fraction, refine=t.refine)
    std = getattr(modes, "frequency_std_hz", None)
    return Identified(name, np.asarray(modes.frequencies_hz), np.asarray(modes.damping_ratio),
                      np.asarray(modes.shapes), np.asarray(modes.outputs), (), ", ".join(files), stab, frfs,
                      frequency_std_hz=None if std is None else np.asarray(std, float),
                      damping_std=(None if getattr(modes, "damping_std", None) is None
                                   else np.asarray(modes.damping_std)))


def read_modes(path: Path, name: str = "", key: str | None = None) -> Identified:
    """Identified modes from UFF 55 (.uff/.unv), CSV (mode,frequency_hz,damping_ratio[,label][,<point><+-XYZ>
    shape columns...]) or JSON (the layout Identified.as_dict writes, or any object with
    'frequencies_hz' or 'measured_hz'; ``key`` selects a sub-object, dotted for nesting)."""
    suffix = path.suffix.lower()
    if suffix in (".uff", ".unv"):
        from ..io.uff import read_uff
        data = read_uff(path)
        if data.modes is None:
            raise ProjectError(f"{path}: no modal dataset 55 in the file")
        m = data.modes
        comps = m.shapes[:, :, :3]
        outputs = np.array([(p, d + 1) for p in m.point_ids for d in range(3)])
        return Identified(name, m.frequencies_hz, m.damping_ratio, comps.reshape(len(comps), -1), outputs, (),
                          str(path))
    if suffix == ".csv":
        return _read_csv(path, name)
    if suffix == ".json":
        try:
            obj = json.loads(path.read_text())
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise ProjectError(f"{path}: not valid JSON: {exc}") from None
        for part in (key.split(".") if key else []):
            if not isinstance(obj, dict) or part not in obj:
                raise ProjectError(f"{path}: no key '{part}' (of '{key}'); keys: "
                                   f"{sorted(obj) if isinstance(obj, dict) else '(not an object)'}")
            obj = obj[part]
        return _from_json(obj, path, name)
    raise ProjectError(f"{path}: identified modes must be UFF (.uff/.unv, dataset 55), .csv or .json")


def _from_json(obj, path: Path, name: str) -> Identified:
    if not isinstance(obj, dict):
        raise ProjectError(f"{path}: expected an object with 'frequencies_hz'")
    f = obj.get("frequencies_hz", obj.get("measured_hz"))
    if f is None:
        raise ProjectError(f"{path}: no 'frequencies_hz' (or 'measured_hz') list; keys: {sorted(obj)}")
    if "shapes_real" in obj and "outputs" not in obj:
        raise ProjectError(f"{path}: 'shapes_real' without 'outputs' (the [point, direction] of each shape column)")
    try:
        f = np.asarray(f, float)
        z = np.asarray(obj.get("damping_ratio", np.zeros_like(f)), float)
        shapes = outputs = None
        if "shapes_real" in obj:
            shapes = np.asarray(obj["shapes_real"], float) + 1j * np.asarray(obj.get("shapes_imag", 0.0), float)
            outputs = np.asarray(obj["outputs"], int)
        labels = obj.get("labels", ())
        labels = tuple(str(s) for s in (labels if isinstance(labels, (list, tuple)) else [labels]))
    except (TypeError, ValueError, OverflowError) as exc:
        raise ProjectError(f"{path}: numbers expected: {exc}") from None
    if (f.ndim != 1 or z.shape != f.shape
            or (shapes is not None and (outputs.ndim != 2 or shapes.shape != (len(f), len(outputs))))):
        raise ProjectError(f"{path}: frequencies, damping, shapes and outputs do not agree in size")
    std = {}
    for key in ("frequency_std_hz", "damping_std"):
        if key in obj:
            v = np.asarray(obj[key], float)
            if v.shape != f.shape or not np.all(np.isfinite(v)) or np.any(v < 0):
                raise ProjectError(f"{path}: '{key}' must hold {len(f)} finite values >= 0")
            std[key] = v
    return Identified(name, f, z, shapes, outputs, labels, str(path), **std)


def _read_csv(path: Path, name: str) -> Identified:
    import re
    try:
        rows = list(csv.reader(path.read_text().splitlines()))
    except UnicodeDecodeError:
        raise ProjectError(f"{path}: not a text file") from None
    if len(rows) < 2 or len(rows[0]) < 2:
        raise ProjectError(f"{path}: expected a header (mode,frequency_hz,damping_ratio,...) and one row per mode")
    head = [h.strip() for h in rows[0]]
    if "frequency_hz" not in head:
        raise ProjectError(f"{path}: no 'frequency_hz' column in the header {head}")
    channels = [(k, re.fullmatch(r"(\d+)([+-])([XYZ])", h)) for k, h in enumerate(head)]
    channels = [(k, m) for k, m in channels if m]
    f, z, labels, shapes = [], [], [], []
    for i, r in enumerate(rows[1:], start=2):
        if not any(c.strip() for c in r):
            continue
        try:
            f.append(float(r[head.index("frequency_hz")]))
            z.append(float(r[head.index("damping_ratio")]) if "damping_ratio" in head else 0.0)
            shapes.append([float(r[k]) for k, _ in channels])
        except (ValueError, IndexError):
            raise ProjectError(f"{path}: line {i}: not a number where one is expected") from None
        if "label" in head:
            labels.append(r[head.index("label")])
    outputs = np.array([(int(m.group(1)), (1 if m.group(2) == "+" else -1) * (" XYZ".index(m.group(3))))
                        for _, m in channels]) if channels else None
    return Identified(name, np.asarray(f), np.asarray(z), np.asarray(shapes) if channels else None, outputs,
                      tuple(labels), str(path))
