"""`run(project)`: identification -> updating -> check -> suspension removal and prediction ->
outputs and report, resumable from the project's results store (a second run picks up what is done).

Every step is a public function (flexgvt.workflow.identify, update_model, check, predict,
write_outputs, write_project_report); the runner only orders them and caches their results.
"""

from __future__ import annotations

import hashlib
import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ..updating.result import jsonable
from .identification import Identified, identify, read_modes
from .project import Project, load_project
from .steps import Prediction, check, predict, update_model


@dataclass
class RunResult:
    """Everything one run produced: identified modes per configuration, the UpdateResult (None when
    nothing is updated), checks of the 'check' configurations for the initial and updated models,
    the free-flying predictions of both models, the files written and step timings [s]."""

    project: Project
    identified: dict[str, Identified]
    update: object | None
    checks: dict = field(default_factory=dict)
    predictions: dict[str, Prediction] = field(default_factory=dict)
    files: dict[str, str] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    resumed: list[str] = field(default_factory=list)

    @property
    def model(self):
        """The updated model (the initial one when nothing was updated)."""
        return self.project.model if self.update is None else self.update.model

    def as_dict(self) -> dict:
        """The documented --json layout of `flexgvt run`."""
        up = self.update
        return jsonable({
            "project": str(self.project.path), "timings_s": self.timings, "resumed": self.resumed,
            "identified": {n: {"frequencies_hz": i.frequencies_hz, "damping_ratio": i.damping_ratio,
                               "labels": list(i.labels), "source": i.source} for n, i in self.identified.items()},
            "updating": None if up is None else {k: v for k, v in up.as_dict().items() if k != "mac"},
            "checks": self.checks,
            "prediction": {k: p.rows for k, p in self.predictions.items()},
            "files": self.files})


def _digest(*parts) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else json.dumps(p, sort_keys=True, default=str).encode())
    return h.hexdigest()[:20]


def _identification_key(project: Project, name: str) -> str:
    spec = next(c for c in project.spec.configurations if c.name == name).test
    files = [spec.frfs] if isinstance(spec.frfs, str) else list(spec.frfs or []) + ([spec.modes] if spec.modes else [])
    return _digest(spec.model_dump(), *[project.file(f).read_bytes() for f in files])


def identify_all(project: Project, store: Path | None = None, log: Callable[[str], None] = lambda s: None,
                 resumed: list | None = None) -> dict[str, Identified]:
    """identify() for every configuration with test data; cached in ``store`` (a folder) by a digest of
    the test settings and the files' bytes, so a second run reads them back."""
    out = {}
    for spec in project.spec.configurations:
        if spec.test is None:
            continue
        key = _identification_key(project, spec.name)
        cache = None if store is None else store / f"identified-{spec.name}.json"
        if cache is not None and cache.is_file():
            saved = json.loads(cache.read_text())
            if saved.get("key") == key:
                item = read_modes(cache, spec.name, "data")
                item.source = saved["data"]["source"]
                item.diagram = saved.get("diagram")
                out[spec.name] = item
                if resumed is not None:
                    resumed.append(f"identification {spec.name}")
                log(f"identification '{spec.name}': {len(item.frequencies_hz)} modes (from the store)")
                continue
        t0 = time.perf_counter()
        item = identify(project, spec.name)
        item.diagram = diagram(item)
        out[spec.name] = item
        log(f"identification '{spec.name}': {len(item.frequencies_hz)} modes from {item.source} "
            f"({time.perf_counter() - t0:.1f} s)")
        if cache is not None:
            cache.write_text(json.dumps(jsonable({"key": key, "data": item.as_dict(), "diagram": item.diagram})))
    return out


def diagram(item: Identified) -> dict | None:
    """A stabilisation diagram as flat arrays (orders, poles_hz, damping, stable), with the summed FRF
    magnitude and the selected frequencies: what the report draws, small enough for the store."""
    stab = item.stabilisation
    if stab is None:
        return None
    orders, f, z, ok = [], [], [], []
    for order, poles, stable in zip(stab.orders, stab.poles, stab.stable):
        for s, st in zip(poles, stable):
            orders.append(int(order))
            f.append(abs(s) / (2 * np.pi))
            z.append(-s.real / abs(s) if abs(s) else 0.0)
            ok.append(bool(st))
    return {"frequencies_hz": np.asarray(stab.frequencies_hz).tolist(),
            "indicator": np.abs(stab.H).sum(axis=(1, 2)).tolist(), "orders": orders, "poles_hz": f,
            "damping_ratio": z, "stable": ok, "selected_hz": item.frequencies_hz.tolist()}


def run(project: Project | str | Path, log: Callable[[str], None] | None = None,
        report: bool | None = None) -> RunResult:
    """Run a project end to end; results and outputs go to its output folder. log: a callable that
    receives one line per step and per optimiser iteration (the CLI prints them)."""
    from ..updating import ResultsStore
    log = log or (lambda s: None)
    t_all = time.perf_counter()
    if not isinstance(project, Project):
        project = load_project(project)
    out = project.output
    store = out / "store"
    store.mkdir(parents=True, exist_ok=True)
    timings: dict[str, float] = {}
    resumed: list[str] = []

    t0 = time.perf_counter()
    identified = identify_all(project, store, log, resumed)
    timings["identification"] = time.perf_counter() - t0

    result = None
    if project.to_update:
        t0 = time.perf_counter()
        db = ResultsStore(store / "updating.sqlite")
        log(f"updating {len(project.variables)} variables on {project.to_update} "
            f"({project.spec.optimiser.method})")

        def progress(row):
            log(f"  iteration {row.get('iteration', '?')}: objective {row['objective']:.6g}")
        try:
            result = update_model(project, identified, store=db, callback=progress)
        finally:
            db.close()
        if any(s.get("resumed") for s in result.starts):
            resumed.append("updating")
        log(result.summary())
        timings["updating"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    model = project.model if result is None else result.model
    checks = {"initial": check(project, project.model, identified)}
    if result is not None:
        checks["updated"] = check(project, model, identified)
    timings["check"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    predictions = {}
    if project.spec.prediction.free_free:
        configs = project.configurations if result is None else {**project.configurations, **result.configurations}
        predictions["initial"] = predict(project, project.model, project.configurations)
        if result is not None:
            predictions["updated"] = predict(project, model, configs)
        log(f"prediction: {len(predictions[list(predictions)[-1]].rows)} free-free elastic modes")
    timings["prediction"] = time.perf_counter() - t0

    res = RunResult(project, identified, result, checks, predictions, {}, timings, resumed)
    t0 = time.perf_counter()
    from .outputs import write_outputs
    res.files.update(write_outputs(res, out))
    do_report = project.spec.outputs.report if report is None else report
    if do_report:
        from .report import write_project_report
        res.files["report"] = str(write_project_report(res, out))
    timings["outputs"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_all
    (out / "results.json").write_text(json.dumps(res.as_dict(), indent=1))
    res.files["results"] = str(out / "results.json")
    return res
