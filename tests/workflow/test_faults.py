"""Faults in `flexgvt run`: SIGKILL during identification, optimisation and output writing, then a
rerun, gives the numbers of an uninterrupted run exactly and an intact store; two runs of one
project at once: the second refuses; a broken identification cache is identified again.

The project is a 20-element 3.66 m strip with synthetic FRFs (two configurations, two variables)
so that a run takes a few seconds. The kills land at points seen from outside, by polling the
output folder and the SQLite store read-only: the code has no test hook.
"""

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.io.uff import TestGeometry, write_uff
from flexgvt.workflow import load_project
from flexgvt.workflow.synthetic import synthetic_gvt

PROJECT = """
[project]
name = "strip, faults"
[model]
case = "strip_366"
[model.options]
n_elements = 20
[[configurations]]
name = "outboard"
from = "outboard"
[configurations.test]
frfs = "outboard.uff"
points = "case"
band_hz = [0.2, 12.0]
max_order = 24
[[configurations]]
name = "inboard"
from = "inboard"
role = "check"
[configurations.test]
frfs = "inboard.uff"
points = "case"
band_hz = [0.2, 12.0]
max_order = 24
[[variables]]
name = "E"
kind = "beam"
targets = ["strip"]
attribute = "E"
bounds = [0.8, 1.2]
[[variables]]
name = "rho"
kind = "beam"
targets = ["strip"]
attribute = "rho"
bounds = [0.8, 1.2]
[objective]
mac = 1.0
[optimiser]
max_iterations = 12
[prediction]
n_modes = 4
[outputs]
report = false
"""

CLI = "from flexgvt.cli.main import app; app()"


def _write_project(folder: Path) -> Path:
    truth = fg.cases.strip_366(n_elements=20)
    g = truth.model.beams[0]
    truth.model.set_beam_group(0, material=fg.Material("as built", E=g.material.E * 1.05, nu=0.33,
                                                       rho=g.material.rho * 0.97))
    for name in ("outboard", "inboard"):
        gvt = synthetic_gvt(truth.model, truth.configurations[name], truth.sensors, ["S12LE", "S03TE"],
                            f_max_hz=12.0, df_hz=0.05, snr_db=40.0, seed=3, n_modes=12)
        pts = np.array(sorted(gvt.point_xyz))
        write_uff(folder / f"{name}.uff", frfs=gvt.frfs,
                  geometry=TestGeometry(pts, np.array([gvt.point_xyz[p] for p in pts])))
    (folder / "project.toml").write_text(PROJECT)
    return folder / "project.toml"


@pytest.fixture(scope="module")
def project_files(tmp_path_factory):
    return _write_project(tmp_path_factory.mktemp("faults"))


def _copy(project: Path, folder: Path) -> Path:
    folder.mkdir()
    for f in project.parent.iterdir():
        if f.is_file():
            (folder / f.name).write_bytes(f.read_bytes())
    return folder / "project.toml"


def _start(project: Path) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", CLI, "run", str(project)], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, env={**os.environ, "MPLBACKEND": "Agg", "COLUMNS": "400"})


def _evaluations(db: Path) -> int:
    """Evaluations stored so far, read through a read-only connection (never writes the store)."""
    if not db.exists():
        return 0
    try:
        with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=5) as c:
            return c.execute("SELECT COUNT(*) FROM evaluations").fetchone()[0]
    except sqlite3.OperationalError:  # not created yet
        return 0


def _kill_when(proc: subprocess.Popen, ready, what: str, timeout: float = 120.0) -> None:
    deadline = time.time() + timeout
    while not ready() and proc.poll() is None and time.time() < deadline:
        time.sleep(0.005)
    assert proc.poll() is None, f"the run ended before it could be killed {what}"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()


def _numbers(results: Path) -> dict:
    """results.json without what legitimately differs between runs (timings, counters, resumed steps)."""
    d = json.loads(results.read_text())
    d.pop("timings_s")
    d.pop("resumed")
    d.pop("project")
    d.pop("files")
    for k in ("seconds", "solves", "gradients", "starts"):
        d["updating"].pop(k)
    for row in d["updating"]["history"]:
        row.pop("time_s", None)
    for item in d["identified"].values():
        item.pop("source")
    return d


def test_kills_during_identification_optimisation_and_outputs_then_rerun_give_the_uninterrupted_numbers(
        project_files, tmp_path):
    reference = _copy(project_files, tmp_path / "reference")
    ref = _start(reference)
    assert ref.wait(300) == 0, ref.stdout.read().decode()

    project = _copy(project_files, tmp_path / "killed")
    out = project.parent / "results"
    store = out / "store"
    db = store / "updating.sqlite"
    # 1. identification: the first configuration identified and cached, the second not yet
    _kill_when(_start(project), lambda: (store / "identified-outboard.json").exists(), "during identification")
    assert not (store / "identified-inboard.json").exists() and _evaluations(db) == 0
    # 2. optimisation: a few evaluations stored (the run takes about 12)
    _kill_when(_start(project), lambda: _evaluations(db) >= 4, "during optimisation")
    stored = _evaluations(db)
    assert 4 <= stored and not (out / "updated.bdf").exists()
    # 3. output writing: as soon as the first output file is being written (its temporary exists)
    _kill_when(_start(project), lambda: any(out.glob(".updated.*.tmp.bdf")) or (out / "updated.bdf").exists(),
               "while writing the outputs")
    assert not (out / "results.json").exists()
    # The rerun reads the identification and the finished optimisation back and writes the outputs.
    last = _start(project)
    log = last.communicate(timeout=300)[0].decode()
    assert last.returncode == 0, log
    assert "from the store" in log

    # Exactly the uninterrupted run's numbers: the resumed optimiser was answered from the store
    # with the bytes the killed run computed, went on from its exact warm starts, and the finished
    # run is evaluated from the continuation it was evaluated from; so the arithmetic is the same
    # and no tolerance is needed (identified modes, variables and their uncertainties, tables,
    # history, checks, free-free prediction).
    got, want = _numbers(out / "results.json"), _numbers(reference.parent / "results" / "results.json")
    assert got == want
    assert len(got["updating"]["history"]) - 1 <= 12  # one iteration budget over all the runs
    for name in ("updated.bdf", "identified-outboard.uff", "predicted-free-free-updated.uff",
                 "prediction-updated.csv"):
        assert (out / name).read_bytes() == (reference.parent / "results" / name).read_bytes(), name
    assert not list(out.glob(".*.tmp*")) and not list(store.glob(".*.tmp*"))  # no leftovers
    with sqlite3.connect(f"file:{db}?mode=ro", uri=True) as c:
        assert c.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
        runs = c.execute("SELECT COUNT(*) FROM runs WHERE finished IS NOT NULL").fetchone()[0]
        iterations = c.execute("SELECT iteration FROM iterations ORDER BY iteration").fetchall()
    assert runs == 1
    assert [i for (i,) in iterations] == list(range(len(want["updating"]["history"])))  # no interleaving


def test_a_second_run_of_the_same_project_refuses_at_once(project_files, tmp_path):
    project = _copy(project_files, tmp_path / "twice")
    lock = project.parent / "results" / "store" / "run.lock"
    # A real run takes the lock, naming its process, while it runs.
    run = _start(project)
    try:
        deadline = time.time() + 60
        while not (lock.exists() and lock.read_text().strip()) and time.time() < deadline:
            time.sleep(0.01)
        assert f"flexgvt process {run.pid}" in lock.read_text()
    finally:
        run.wait(timeout=120)
    # A second run while the first holds the lock: the first is a process holding it the way a run
    # does (the runner's own acquire_lock) for as long as the check takes, so that the check does
    # not race a small project's few seconds (a second process's start-up and project load can
    # take longer than that on a loaded machine).
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time; from pathlib import Path; "
                               "from flexgvt.updating.store import acquire_lock; "
                               "h = acquire_lock(Path(sys.argv[1]), Path(sys.argv[2])); print('locked', flush=True); "
                               "time.sleep(120)", str(lock), str(project.parent)],
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        t0 = time.time()
        second = subprocess.run([sys.executable, "-c", CLI, "run", str(project)], capture_output=True, text=True,
                                env={**os.environ, "COLUMNS": "400"}, timeout=60)
        assert holder.poll() is None
        assert second.returncode == 2
        msg = " ".join(second.stdout.split())
        assert f"in use by flexgvt process {holder.pid}" in msg and "wait until that run ends" in msg, msg
        assert "Traceback" not in second.stdout + second.stderr
        assert time.time() - t0 < 30  # refused at once, not after the first run
    finally:
        if holder.poll() is None:
            os.kill(holder.pid, signal.SIGKILL)
        holder.wait()
    # The lock of a killed run is gone with its process: the next run takes it.
    from flexgvt.updating.store import acquire_lock
    acquire_lock(lock, project.parent).close()


def test_a_broken_identification_cache_is_identified_again(project_files, tmp_path):
    from flexgvt.workflow.runner import _identification_key, identify_all
    project = load_project(_copy(project_files, tmp_path / "cache"))
    store = tmp_path / "store"
    store.mkdir()
    fresh = identify_all(project, store)
    cache = store / "identified-outboard.json"
    whole = cache.read_bytes()
    saved = json.loads(whole)
    assert saved["key"] == _identification_key(project, "outboard")
    short_shapes = json.loads(whole)
    short_shapes["data"]["shapes_real"] = short_shapes["data"]["shapes_real"][:-1]
    short_diagram = json.loads(whole)
    short_diagram["diagram"]["poles_hz"] = short_diagram["diagram"]["poles_hz"][:-3]
    no_outputs = json.loads(whole)
    del no_outputs["data"]["outputs"]
    broken = [whole[: len(whole) // 2], b"\xff\xfe\x00", b"[1, 2]",
              *(json.dumps(d).encode() for d in (short_shapes, short_diagram, no_outputs))]
    for content in broken:
        cache.write_bytes(content)
        lines = []
        again = identify_all(project, store, lines.append)
        notice = [line for line in lines if "outboard" in line and "unusable" in line]
        assert len(notice) == 1 and "identifying again" in notice[0], (content[:40], lines)
        np.testing.assert_array_equal(again["outboard"].frequencies_hz, fresh["outboard"].frequencies_hz)
        assert cache.read_bytes() == whole  # written whole again: the next run reads it back
    resumed = []
    identify_all(project, store, resumed=resumed)
    assert resumed == ["identification outboard", "identification inboard"]


def test_safe_names_are_file_names_and_unique():
    from flexgvt.workflow.outputs import safe_name
    assert safe_name("outboard_20m-v2.1") == "outboard_20m-v2.1"  # safe names stay as they are
    names = ["a/b", "a_b", "a\\b", "a:b", "../x", ".hidden", "NUL", "con.txt", "", "x" * 5000, "x" * 5001,
             "aile\u0301ron", "a\x00b", "a b"]
    safe = [safe_name(n) for n in names]
    assert len(set(safe)) == len(names)
    for s in safe:
        assert s and len(s) <= 57 and not s.startswith(".")
        assert all(c.isascii() and (c.isalnum() or c in "._-") for c in s)
