"""Step 1: the measured modes of each configuration, identified from FRFs (PolyMAX + LSFD) or read
as already identified (UFF 55, CSV or JSON), with the sensors that map FE shapes onto them."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import FlexGVTError
from ..modal import ModalSet
from .projectbase import Project, ProjectError


@dataclass(frozen=True, eq=False)
class Identified(ModalSet):
    """The measured modes of one configuration: a flexgvt.modal.ModalSet (name: the configuration,
    also read as .configuration; source: the file(s) read; dofs (.outputs): the (test point,
    direction code) of each shape column; stabilisation and frfs: those of an identification from
    FRFs; info['diagram'] (.diagram): the stabilisation diagram's plain data kept for the report).
    It adds nothing but the former method measured(project), kept for old callers."""

    def measured(self, project: Project):
        """Deprecated: flexgvt.workflow.measured(item, project)."""
        import warnings

        warnings.warn("Identified.measured(project) is deprecated: use flexgvt.workflow.measured(item, project)",
                      DeprecationWarning, stacklevel=2)
        return measured(self, project)


def measured(item: ModalSet, project: Project):
    """The flexgvt.updating.Measured of a configuration's identified modes (sensors mapped to the FE
    nodes by the project's [sensors] tables)."""
    from ..correlation import Sensors
    from ..updating import Measured
    sensors = None
    if item.shapes is not None:
        node_map, offsets = project.sensors.get(item.name, ({}, {}))
        try:
            sensors = Sensors.from_outputs(item.dofs, node_map or None, offsets or None)
        except FlexGVTError as exc:
            raise ProjectError(f"configuration '{item.name}' ({item.source}): {exc}") from None
    return Measured(item.name, item.frequencies_hz, item.shapes, sensors, labels=item.labels,
                    frequency_std_hz=item.frequency_std_hz)


def identify_configuration(project: Project, name: str) -> ModalSet:
    """The measured modes of configuration ``name`` as its [configurations.test] table says."""
    spec = next(c for c in project.spec.configurations if c.name == name)
    t = spec.test
    if t is None:
        raise ProjectError(f"{project.path}: configuration '{name}' has no test data")
    where = f"{project.path}: configurations '{name}' test"
    try:
        if t.frfs is not None or t.time is not None:
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
    return Identified(out.frequencies_hz[keep], out.damping_ratio[keep], pick(out.shapes), dofs=out.dofs,
                    frequency_std_hz=pick(out.frequency_std_hz), damping_std=pick(out.damping_std), labels=labels,
                    name=name, source=out.source, stabilisation=out.stabilisation, frfs=out.frfs,
                    info={k: v for k, v in out.info.items() if k == "dropped"})


def identify(project: Project, name: str) -> ModalSet:
    """Deprecated name of :func:`identify_configuration` (flexgvt.ema.identify is the EMA one)."""
    import warnings

    warnings.warn("flexgvt.workflow.identify is deprecated: use flexgvt.workflow.identify_configuration (the "
                  "EMA identification of FRFs is flexgvt.ema.identify)", DeprecationWarning, stacklevel=2)
    return identify_configuration(project, name)


_DIRECTION = {"X": 1, "Y": 2, "Z": 3, "RX": 4, "RY": 5, "RZ": 6}


def parse_dof(text: str, what: str = "a channel") -> tuple[int, int]:
    """'100+Z' -> (100, 3), '7-RY' -> (7, -5), '12:3' -> (12, 3): a test point and its UFF direction code;
    ModelError (``what`` names the key or option) for any other text."""
    import re

    from ..errors import ModelError
    m = re.fullmatch(r"\s*(\d+)\s*(?:([+-]?)\s*(RX|RY|RZ|X|Y|Z)|:\s*([+-]?[1-6]))\s*", str(text).upper())
    if m is None:
        raise ModelError(f"{what} {text!r} is not a test point and direction; write it as POINT+DIRECTION, e.g. "
                         "100+Z, 100-X, 7+RY (or POINT:CODE with the UFF direction code 1..6, e.g. 100:3)")
    if m.group(4) is not None:
        return int(m.group(1)), int(m.group(4))
    return int(m.group(1)), (-1 if m.group(2) == "-" else 1) * _DIRECTION[m.group(3)]


def project_hint(contents, key: str) -> str:
    """What to do, in project keys, with a UFF file (its describe_uff contents) given as test.``key``."""
    fc = contents.function_counts()
    if "time response" in fc and key != "time":
        return ("it holds time histories: give it as test.time (FRFs are estimated from them, with test.references "
                "and test.estimator), or estimate them with `flexgvt ema frf`")
    if "FRF" in fc and key != "frfs":
        return "it holds FRFs: give it as test.frfs"
    if contents.n_modes and key != "modes":
        return "it holds modes: give it as test.modes"
    if contents.n_points or contents.n_coordinate_systems:
        what = "test geometry" + (" and coordinate systems" if contents.n_coordinate_systems else "")
        return (f"it holds {what} only, no measurements: give the FRFs (test.frfs), time histories (test.time) or "
                "identified modes (test.modes) from another file exported by the test system")
    return "export the FRFs, time histories or modes from the test system"


def measured_frfs(project: Project, t, where: str = ""):
    """(FRFs, files, dropped lines) of a [configurations.test] table: the FRFs of its ``frfs`` files (one
    matrix), or those estimated from its ``time`` histories; incomplete channels left out (and listed)
    with ``drop_incomplete``. ProjectError when a file holds no FRFs, saying what it holds."""
    import warnings

    from ..ema import estimate_frf_from_time
    from ..errors import FlexGVTWarning
    from ..io.uff import assemble_frfs, describe_uff, drop_incomplete_channels, read_uff
    if t.time is not None:
        path = project.file(t.time)
        data = read_uff(path)
        if not any(fn.kind == "time response" for fn in data.functions):
            c = describe_uff(path)
            raise ProjectError(f"{where}.time: no time history (dataset 58, function type 1) in '{t.time}': it holds "
                               f"{c.summary()}: {project_hint(c, 'time')}")
        try:
            refs = [parse_dof(r, f"{where}.references:") for r in t.references] if t.references else None
        except FlexGVTError as exc:
            raise ProjectError(str(exc)) from None
        try:
            frfs = estimate_frf_from_time(data.time_histories, references=refs, estimator=t.estimator,
                                          nperseg=t.nperseg)
        except FlexGVTError as exc:
            raise ProjectError(f"{where}.time: '{t.time}': {exc}") from None
        return frfs, [t.time], ()
    files = [t.frfs] if isinstance(t.frfs, str) else list(t.frfs)
    functions, empty = [], []
    for f in files:
        found = [fn for fn in read_uff(project.file(f)).functions if fn.kind == "FRF"]
        functions += found
        if not found:
            empty.append(f)
    if not functions:
        held = "; ".join(f"'{f}' holds {c.summary()}: {project_hint(c, 'frfs')}"
                         for f in files for c in [describe_uff(project.file(f))])
        raise ProjectError(f"{where}.frfs: no FRF (dataset 58, function type 4) in {files}: {held}")
    dropped: tuple = ()
    if t.drop_incomplete:
        functions, dropped = drop_incomplete_channels(functions, ", ".join(files))
        if dropped:
            warnings.warn(f"{where}: incomplete FRF channels dropped: {'; '.join(dropped)}", FlexGVTWarning,
                          stacklevel=2)
    return assemble_frfs(functions, where=", ".join(files)), files, dropped


def _from_frfs(project: Project, name: str, t) -> ModalSet:
    from ..ema import identify_wide_band, polymax
    frfs, files, dropped = measured_frfs(project, t, f"configuration '{name}' test")
    band = tuple(t.band_hz) if t.band_hz is not None else None
    if t.wide:
        stab, modes = None, identify_wide_band(frfs, frequency_band=band, max_order=t.max_order,
                                               min_fraction=t.min_fraction)
    else:
        stab = polymax(frfs, max_order=t.max_order, frequency_band=band)
        modes = stab.select(frequencies_hz=t.select_hz, min_fraction=t.min_fraction, refine=t.refine)
    std = modes.frequency_std_hz
    return Identified(np.asarray(modes.frequencies_hz), np.asarray(modes.damping_ratio), np.asarray(modes.shapes),
                    dofs=np.asarray(modes.dofs), frequency_std_hz=None if std is None else np.asarray(std, float),
                    damping_std=None if modes.damping_std is None else np.asarray(modes.damping_std),
                    name=name, source=", ".join(files), stabilisation=stab, frfs=frfs,
                    info={"dropped": dropped} if dropped else {})


def read_modes(path: Path, name: str = "", key: str | None = None) -> ModalSet:
    """Identified modes from UFF 55 (.uff/.unv), CSV (mode,frequency_hz,damping_ratio[,label][,<point><+-XYZ>
    shape columns...]; lines starting with '#' are comments, e.g. the data's source) or JSON (the layout
    ModalSet.as_dict writes, or any object with 'frequencies_hz' or 'measured_hz'; ``key`` selects a sub-object,
    dotted for nesting)."""
    suffix = path.suffix.lower()
    if suffix in (".uff", ".unv"):
        from ..io.uff import read_uff
        data = read_uff(path)
        if data.modes is None:
            from ..io.uff import describe_uff
            c = describe_uff(path)
            raise ProjectError(f"{path}: no modes (dataset 55 or 2414) in the file; it holds {c.summary()}: "
                               f"{project_hint(c, 'modes')}")
        m = data.modes
        translations = np.abs(m.dofs[:, 1]) <= 3  # UFF 55 lays out (point, 1..3 or 1..6) per point
        return Identified(m.frequencies_hz, m.damping_ratio, m.shapes[:, translations], dofs=m.dofs[translations],
                        name=name, source=str(path))
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


def _from_json(obj, path: Path, name: str) -> ModalSet:
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
    return Identified(f, z, shapes, dofs=outputs, labels=labels, name=name, source=str(path), **std)


def _read_csv(path: Path, name: str) -> ModalSet:
    import re
    try:
        lines = [(n, s) for n, s in enumerate(path.read_text().splitlines(), start=1)
                 if not s.lstrip().startswith("#")]  # comments: e.g. the data's source
    except UnicodeDecodeError:
        raise ProjectError(f"{path}: not a text file") from None
    rows = list(csv.reader(s for _, s in lines))
    if len(rows) < 2 or len(rows[0]) < 2:
        raise ProjectError(f"{path}: expected a header (mode,frequency_hz,damping_ratio,...) and one row per mode")
    head = [h.strip() for h in rows[0]]
    if "frequency_hz" not in head:
        raise ProjectError(f"{path}: no 'frequency_hz' column in the header {head}")
    channels = [(k, re.fullmatch(r"(\d+)([+-])([XYZ])", h)) for k, h in enumerate(head)]
    channels = [(k, m) for k, m in channels if m]
    f, z, labels, shapes = [], [], [], []
    for (i, _), r in zip(lines[1:], rows[1:]):
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
    return Identified(np.asarray(f), np.asarray(z), np.asarray(shapes) if channels else None, dofs=outputs,
                    labels=tuple(labels), name=name, source=str(path))
