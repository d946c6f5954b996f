"""`run(project)`: identification -> updating -> check -> suspension removal and prediction ->
outputs, resumable from the project's results store (a second run picks up what is done).

Every step is a public function (flexgvt.workflow.identify_configuration, update_model, check, predict,
write_outputs); the runner only orders them and caches their results. It returns results and never
renders: the report is the face's (flexgvt.report.write_project_report(result), which `flexgvt run`
calls when the project's [outputs] report is on).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import FlexGVTError
from ..updating.result import jsonable
from ..updating.settings import renamed
from .identification import Identified, _from_json, identify_configuration
from .outputs import remove_temporaries, safe_name, write_json_atomic, write_text_atomic
from .project import Project, ProjectError, load_project
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
    report_wanted: bool = False  # the project's [outputs] report: flexgvt.report.write_project_report(result)
    stages: list = field(default_factory=list)  # StageResult per [[stages]] entry (update: the last one's)

    @property
    def model(self):
        """The updated model (the final stage's; the initial one when nothing was updated)."""
        if self.stages:
            return self.stages[-1].model
        return self.project.model if self.update is None else self.update.model

    def to_dict(self) -> dict:
        """The documented --json layout of `flexgvt run`."""
        up = self.update
        return jsonable({
            "project": str(self.project.path), "timings_s": self.timings, "resumed": self.resumed,
            "identified": {n: {"frequencies_hz": i.frequencies_hz, "damping_ratio": i.damping_ratio,
                               "labels": list(i.labels), "source": i.source,
                               **({"dropped_channels": list(i.info["dropped"])} if i.info.get("dropped") else {})}
                           for n, i in self.identified.items()},
            "updating": None if up is None else {k: v for k, v in up.to_dict().items() if k != "mac"},
            "checks": self.checks,
            "prediction": {k: p.rows for k, p in self.predictions.items()},
            "prediction_modes": {k: p.modes for k, p in self.predictions.items()},
            "prediction_uncertainty": {k: p.uncertainty for k, p in self.predictions.items()},
            "files": self.files, **({"stages": [s.to_dict() for s in self.stages]} if self.stages else {})})

    def as_dict(self) -> dict:
        """Deprecated: to_dict()."""
        renamed("RunResult.as_dict()", "RunResult.to_dict()")
        return self.to_dict()


def _digest(*parts) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else json.dumps(p, sort_keys=True, default=str).encode())
    return h.hexdigest()[:20]


def _identification_key(project: Project, name: str) -> str:
    spec = next(c for c in project.spec.configurations if c.name == name).test
    files = ([spec.frfs] if isinstance(spec.frfs, str) else list(spec.frfs or [])) + \
        [f for f in (spec.time, spec.modes) if f]
    return _digest(spec.model_dump(), *[project.file(f).read_bytes() for f in files])


def identify_all(project: Project, store: Path | None = None, progress: Callable[[str], None] = lambda s: None,
                 resumed: list | None = None, *, log: Callable[[str], None] | None = None) -> dict[str, Identified]:
    """identify_configuration() for every configuration with test data; cached in ``store`` (a folder) by a
    digest of the test settings and the files' bytes, so a second run reads them back. A cache that cannot be
    read (cut off, not JSON, wrongly shaped) is identified again, with a one-line notice. progress:
    receives one line per configuration (``log``: its deprecated name)."""
    if log is not None:
        renamed("identify_all(log=...)", "identify_all(progress=...)")
        progress = log
    log = progress
    out = {}
    for spec in project.spec.configurations:
        if spec.test is None:
            continue
        key = _identification_key(project, spec.name)
        cache = None if store is None else store / f"identified-{safe_name(spec.name)}.json"
        if cache is not None and cache.is_file():
            item, why = _read_cache(cache, key, spec.name)
            if item is not None:
                out[spec.name] = item
                for line in item.info.get("dropped", ()):
                    log(f"identification '{spec.name}': dropped {line} (from the store)")
                if resumed is not None:
                    resumed.append(f"identification {spec.name}")
                log(f"identification '{spec.name}': {len(item.frequencies_hz)} modes (from the store)")
                continue
            if why:
                log(f"identification '{spec.name}': the stored result {cache.name} is unusable ({why}); "
                    "identifying again")
        t0 = time.perf_counter()
        item = identify_configuration(project, spec.name)
        item = item.with_info(diagram=diagram(item))
        out[spec.name] = item
        for line in item.info.get("dropped", ()):
            log(f"identification '{spec.name}': dropped {line}")
        log(f"identification '{spec.name}': {len(item.frequencies_hz)} modes from {item.source} "
            f"({time.perf_counter() - t0:.1f} s)")
        if cache is not None:
            write_json_atomic(cache, jsonable({"key": key, "data": item.as_dict(), "diagram": item.diagram,
                                               "dropped": list(item.info.get("dropped", ()))}))
    return out


_DIAGRAM_KEYS = ("frequencies_hz", "indicator", "orders", "poles_hz", "damping_ratio", "stable", "selected_hz")


def _read_cache(cache: Path, key: str, name: str) -> tuple[Identified | None, str]:
    """The cached identification if it is whole and for these settings and files: (item, ''), else
    (None, why) (why empty when it is merely out of date)."""
    try:
        saved = json.loads(cache.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        return None, f"not readable JSON: {exc}"
    if not isinstance(saved, dict) or not isinstance(saved.get("data"), dict):
        return None, "not an identification record"
    if saved.get("key") != key:
        return None, ""
    try:
        item = _from_json(saved["data"], cache, name)
    except FlexGVTError as exc:
        return None, str(exc)
    if item.shapes is not None and (item.outputs.ndim != 2 or item.outputs.shape[1] != 2):
        return None, "sensor outputs are not (point, direction) pairs"
    if not np.all(np.isfinite(item.frequencies_hz)) or not np.all(item.frequencies_hz > 0):
        return None, "frequencies must be finite and positive"
    source = saved["data"].get("source")
    d = saved.get("diagram")
    if not isinstance(source, str):
        return None, "no source"
    if d is not None and not _diagram_ok(d):
        return None, "a malformed stabilisation diagram"
    dropped = saved.get("dropped", [])
    if not isinstance(dropped, list) or not all(isinstance(s, str) for s in dropped):
        return None, "a malformed list of dropped channels"
    return replace(item, source=source).with_info(diagram=d, dropped=tuple(dropped)), ""


def _diagram_ok(d) -> bool:
    if not isinstance(d, dict) or any(not isinstance(d.get(k), list) for k in _DIAGRAM_KEYS):
        return False
    try:
        arrays = {k: np.asarray(d[k], float) for k in _DIAGRAM_KEYS}
    except (TypeError, ValueError):
        return False
    n = len(arrays["orders"])
    return (all(a.ndim == 1 and np.all(np.isfinite(a)) for a in arrays.values())
            and len(arrays["frequencies_hz"]) == len(arrays["indicator"])
            and all(len(arrays[k]) == n for k in ("poles_hz", "damping_ratio", "stable")))


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


class RunInterrupted(KeyboardInterrupt):
    """A run stopped by Ctrl-C (KeyboardInterrupt): ``message`` says where it stopped (the step; in
    the updating the evaluations stored and the best objective) and that a rerun resumes."""

    def __init__(self, message: str, step: str, status: dict | None = None):
        super().__init__(message)
        self.message, self.step, self.status = message, step, status or {}


def run(project: Project | str | Path, progress: Callable[[str], None] | None = None,
        report: bool | None = None, *, log: Callable[[str], None] | None = None,
        iterations: Callable[[dict], None] | None = None, fresh: bool = False) -> RunResult:
    """Run a project end to end; results and outputs go to its output folder. progress: a callable
    that receives one line per step and, unless ``iterations`` is given, per optimiser iteration
    (the CLI prints them; ``log``: its deprecated name); iterations: receives each accepted
    iterate's history row instead (iteration, objective, ...).

    Resumes by default: identified modes and the updating are read back from the results store
    (store/ in the output folder) when the data and settings are unchanged; a run stopped at its
    limits is continued from its stored point when max_iterations or tolerance change; fresh=True
    discards the store first. The previous run's outputs are moved to ``stale-outputs/`` while the
    run goes on (removed when it completes), so an interrupted run never leaves them looking
    current. Ctrl-C raises RunInterrupted (a KeyboardInterrupt) saying where the run stopped.

    The report is not written here (the workflow never renders): ``result.report_wanted`` says
    whether the project's [outputs] report asks for one, and flexgvt.report.write_project_report
    (result) writes it. report: deprecated (it overrode [outputs] report; now only sets
    report_wanted and warns)."""
    if report is not None:
        warnings.warn("flexgvt.workflow.run(report=...) is deprecated: the workflow returns results and never "
                      "renders; write the report with flexgvt.report.write_project_report(result)",
                      DeprecationWarning, stacklevel=2)
    from ..updating.store import acquire_lock
    if log is not None:
        renamed("run(log=...)", "run(progress=...)")
        progress = log
    log = progress or (lambda s: None)
    t_all = time.perf_counter()
    if not isinstance(project, Project):
        project = load_project(project)
    out = project.output
    store = out / "store"
    try:
        store.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ProjectError(f"{project.path}: cannot create the output folder {store} ({exc.strerror}); set "
                           "[outputs] directory to a writable folder") from None
    # One run of a project at a time: held until this run returns (the system releases it if the
    # process dies), so a second run refuses at once instead of interleaving its history.
    lock = acquire_lock(store / "run.lock", out)
    try:
        if fresh:
            discard_store(store, log)
        return _run_locked(project, out, store, log, report, t_all, iterations)
    finally:
        if lock is not None:
            lock.close()


def _run_locked(project: Project, out: Path, store: Path, log, report, t_all: float, iterations=None) -> RunResult:
    """run() once it holds the project's lock."""
    remove_temporaries(out, store)  # a killed run's; this process holds the lock
    if project.to_update and project.spec.prediction.free_free:
        from .bounds import require
        require(project.spec.prediction.uncertainty, str(project.path))
    stale = set_aside_outputs(out)
    if stale is not None:
        log(f"the previous run's outputs moved to {stale} until this run completes")
    timings: dict[str, float] = {}
    resumed: list[str] = []

    t0 = time.perf_counter()
    try:
        identified = identify_all(project, store, log, resumed)
    except KeyboardInterrupt:
        raise RunInterrupted("interrupted during the identification; the configurations identified so far are "
                             f"stored in {store}: a rerun resumes from them", "identification") from None
    timings["identification"] = time.perf_counter() - t0

    result = None
    staged: list = []
    if project.stages:
        t0 = time.perf_counter()
        staged = run_stages(project, identified, store, log, iterations, resumed)
        result = next((s.update for s in reversed(staged) if s.update is not None), None)
        timings["updating"] = time.perf_counter() - t0
    elif project.to_update:
        t0 = time.perf_counter()
        result = _update(project, identified, store, log, iterations)
        if any(s.get("resumed") for s in result.starts):
            resumed.append("updating")
        log(result.summary())
        if not result.success:
            log(limit_note(result, project))
        timings["updating"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    model = project.model if result is None else result.model
    final_configs = project.configurations if result is None else {**project.configurations, **result.configurations}
    if staged:
        model, final_configs = staged[-1].model, staged[-1].configurations
    checks = {"initial": check(project, project.model, identified)}
    if result is not None or staged:
        checks["updated"] = check(project, model, identified)
    timings["check"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    predictions = {}
    if project.spec.prediction.free_free:
        predictions["initial"] = predict(project, project.model, project.configurations)
        if result is not None or staged:
            predictions["updated"] = predict(project, model, final_configs)
        log(f"prediction: {len(predictions[list(predictions)[-1]].rows)} free-free elastic modes")
    timings["prediction"] = time.perf_counter() - t0
    bounds_on = staged[-1].project if staged else project  # the final stage's variables, start model and data
    if staged and staged[-1].update is None and "updated" in predictions:
        log("prediction: no confidence bounds: the final stage only sets fixed inputs (the bounds come from the "
            "variables an updating final stage identifies)")
        bounds_on = None
    if (result is not None and bounds_on is not None and "updated" in predictions
            and project.spec.prediction.uncertainty.method != "none"):
        from .bounds import add_bounds
        t0 = time.perf_counter()
        add_bounds(bounds_on, result, predictions["updated"], identified, progress=log)
        timings["bounds"] = time.perf_counter() - t0

    res = RunResult(project, identified, result, checks, predictions, {}, timings, resumed, stages=staged)
    t0 = time.perf_counter()
    from .outputs import write_outputs
    res.files.update(write_outputs(res, out))
    res.report_wanted = project.spec.outputs.report if report is None else bool(report)
    timings["outputs"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_all
    write_results(res, out)
    if stale is not None:
        shutil.rmtree(stale, ignore_errors=True)
    return res


def run_stages(project: Project, identified: dict, store: Path, log, iterations=None,
               resumed: list | None = None) -> list:
    """The project's [[stages]] in order, each from the model and configurations the previous one
    produced (its fixed inputs set first), each with its own results store
    (store/stage-<n>-<name>.sqlite, discarded when the stage's start changed); returns a
    flexgvt.workflow.stages.StageResult per stage."""
    from .stages import StageResult, apply_fixed, stage_view, start_digest
    model, configs = project.model, dict(project.configurations)
    out, digest, previous = [], "", None
    for stage in project.stages:
        t0 = time.perf_counter()
        title = f"stage {stage.index + 1} of {len(project.stages)} ('{stage.name}')"
        model, configs, fixed = apply_fixed(stage, model, configs)
        for r in fixed:
            log(f"{title}: {r['name']} ({r['kind']} {r['attribute']}) set to {r['value']:.6g} (was {r['before']:.6g})")
        view = stage_view(project, stage, model, configs)
        digest = start_digest(digest, stage, previous)
        up, again = None, False
        if stage.updates:
            base = f"stage-{stage.index + 1}-{safe_name(stage.name)}"
            _start_store(store, base, digest, title, log)
            up = _update(view, identified, store, log, iterations, f"{base}.sqlite", title)
            again = any(s.get("resumed") for s in up.starts)
            if again and resumed is not None:
                resumed.append(f"updating {stage.name}")
            log(up.summary())
            if not up.success:
                log(limit_note(up, view))
            model = up.model.copy(project.model.name)
            configs = {**configs, **up.configurations}
        previous = StageResult(stage, view, up, model, dict(configs), fixed, again, time.perf_counter() - t0)
        out.append(previous)
    return out


def _start_store(store: Path, base: str, digest: str, title: str, log) -> None:
    """Discard a stage's stored runs when its start (the previous stages' answers, its fixed inputs) changed."""
    start = store / f"{base}.start.json"
    db = store / f"{base}.sqlite"
    try:
        saved = json.loads(start.read_text(encoding="utf-8")).get("start")
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, AttributeError):
        saved = None
    if saved != digest and db.is_file():
        from ..updating import ResultsStore
        with ResultsStore(db) as s:
            s.clear()
        log(f"{title}: the stage starts from another model than its stored runs (an earlier stage or its fixed "
            "inputs changed): starting it again")
    write_json_atomic(start, {"start": digest})


def _update(project: Project, identified: dict, store: Path, log, iterations, name: str = "updating.sqlite",
            title: str = ""):
    """The updating step with its results store; Ctrl-C -> RunInterrupted with the store's status."""
    from ..updating import ResultsStore
    db = ResultsStore(store / name, progress=log)
    opt = project.spec.optimiser
    data = project.to_update or "the measured mass properties"
    log(f"{title + ': ' if title else ''}updating {len(project.variables)} variables on {data} "
        f"({opt.method}, at most {opt.max_iterations} evaluations, tolerance {opt.tolerance:g})")

    def progress(row):
        if iterations is not None:
            iterations(row)
        else:
            log(f"  iteration {row.get('iteration', '?')}: objective {row['objective']:.6g}")
    try:
        return update_model(project, identified, store=db, progress=progress)
    except KeyboardInterrupt:
        st = db.status() if db.problem else {"evaluations": 0, "iterations": 0, "best_objective": None}
        best = "" if st["best_objective"] is None else f", best objective {st['best_objective']:.6g}"
        raise RunInterrupted(f"interrupted in the updating after {st['evaluations']} stored evaluations "
                             f"({st['iterations']} accepted iterations{best}); they are in {db.path}: a rerun "
                             "resumes from there (answering them without solving), `--fresh` starts again",
                             "updating", st) from None
    finally:
        db.close()


def limit_note(result, project: Project) -> str:
    """Why an updating stopped before its tolerance, and what to do: the line the run prints."""
    opt = project.spec.optimiser
    message = str(result.message).rstrip(".")
    hist = [r["objective"] for r in result.history]
    tail = ""
    if len(hist) > 10 and hist[-11] > 0:
        tail = (f"; the objective fell {100 * (hist[-11] - hist[-1]) / hist[-11]:.2g} % over the last 10 "
                "iterations")
    if "maximum number" in message.lower() or "iteration limit" in message.lower():
        advice = (f"Raise [optimiser] max_iterations (now {opt.max_iterations}) or the tolerance and rerun: the "
                  "run continues from its stored point")
    else:
        advice = "The answer is the best point reached; see the optimiser's message above"
    return f"note: the updating stopped before its tolerance ({opt.tolerance:g}): {message}{tail}. {advice}"


STALE = "stale-outputs"


def set_aside_outputs(out: Path) -> Path | None:
    """Move the outputs a previous run listed in its results.json (the report's figures/ and tables/
    with it) into ``out/stale-outputs/`` with a README saying why; returns that folder, or None when
    there was nothing. A folder left by an interrupted run is kept (its outputs are the last ones)."""
    out = Path(out)
    stale = out / STALE
    results = out / "results.json"
    if not results.is_file():
        return stale if stale.is_dir() else None
    try:
        files = json.loads(results.read_text(encoding="utf-8")).get("files", {})
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, AttributeError):
        files = {}
    names = {results}
    for f in files.values() if isinstance(files, dict) else ():
        path = Path(str(f))
        path = path if path.is_absolute() else out / path
        if path.parent.resolve() == out.resolve() and path.is_file():
            names.add(path)
    if "report" in files:
        names |= {out / sub for sub in ("figures", "tables") if (out / sub).is_dir()}
    if stale.exists():
        shutil.rmtree(stale, ignore_errors=True)
    stale.mkdir()
    for path in names:
        os.replace(path, stale / path.name)
    write_text_atomic(stale / "README.txt",
                      f"These are the outputs of an earlier run. A new run started on "
                      f"{time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime())} and has not completed, so they "
                      "may not match the project and its store any more. The folder is removed when a run "
                      "completes.\n")
    return stale


def discard_store(store: Path, log: Callable[[str], None]) -> None:
    """--fresh: remove the stored identifications and updating runs (this process holds the run lock)."""
    gone = [p for p in store.glob("identified-*.json") if p.is_file()]
    for p in gone:
        p.unlink()
    for db in [store / "updating.sqlite", *sorted(store.glob("stage-*.sqlite"))]:
        if db.is_file():
            from ..updating import ResultsStore
            with ResultsStore(db) as s:
                s.clear()
            gone.append(db)
    log(f"fresh run: discarded the stored results ({', '.join(p.name for p in gone)})" if gone else
        "fresh run: nothing stored yet")


def write_results(res: RunResult, out: Path | None = None) -> Path:
    """results.json (the documented --json layout, RunResult.to_dict) in ``out`` (default: the
    project's output folder), written atomically; listed in res.files."""
    out = Path(res.project.output if out is None else out)
    write_text_atomic(out / "results.json", json.dumps(res.to_dict(), indent=1))
    res.files["results"] = str(out / "results.json")
    return out / "results.json"
