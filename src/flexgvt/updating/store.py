"""The results store: an updating run's history in SQLite, so that an interrupted run resumes
where it stopped and reaches the same answer as an uninterrupted one, bit for bit.

    store = fg.updating.ResultsStore("run.sqlite")
    result = fg.updating.update(model, configs, data, variables, store=store)   # rerun: resumes

Every evaluation the optimiser asks for is stored in its own transaction: the design point, what
the optimiser received (residuals, constraints, their Jacobians, exact float64 bytes) and, when
the structure was solved, the continuation it left behind (each configuration's equilibrium, the
next solve's warm start, and the pairing references). A rerun starts the optimiser from the same
point again and answers its requests from the store while they match the record (the optimiser is
deterministic, so they do), then restores the continuation of the last stored evaluation and
computes on: the trajectory, the iteration budget and the answer are those of an uninterrupted run.
A finished run keeps the continuation its answer was evaluated from, so reading it back evaluates
the same numbers (frequencies, Jacobian, uncertainties) as the run that computed them.

A finished run is returned as it is only when asked for with the limits it ran under
(max_iterations, tolerance: ``finished(run, limits)``); under other limits it is continued: the
optimiser starts again, its evaluations are answered from the record without solving, and it
computes on from where the stored run stopped (or stops earlier, under a tighter budget).
``progress`` (a callable taking one line) hears which of these happens, and ``status()`` says
how far the bound problem got (for the message of an interrupted run).

The store is locked (an OS file lock on ``<store>.lock``, released by the system when its process
ends, also on a kill) for as long as it is open: a second process gets StoreLockedError at once.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import socket
import sqlite3
import time
from pathlib import Path

import numpy as np

from ..errors import FileFormatError, FlexGVTError

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: no advisory lock, the store is used unlocked
    fcntl = None


class StoreLockedError(FlexGVTError):
    """Another process holds the results store (a run of the same project is going on)."""

_SCHEMA = """
CREATE TABLE IF NOT EXISTS problems (problem TEXT PRIMARY KEY, structure TEXT NOT NULL, data TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS runs (
    problem TEXT NOT NULL, run INTEGER NOT NULL, method TEXT, started REAL, finished REAL,
    x_final TEXT, objective REAL, message TEXT, PRIMARY KEY (problem, run));
CREATE TABLE IF NOT EXISTS iterations (
    problem TEXT NOT NULL, run INTEGER NOT NULL, iteration INTEGER NOT NULL, x TEXT NOT NULL,
    objective REAL NOT NULL, frequencies TEXT, mac TEXT, residuals TEXT, time REAL,
    PRIMARY KEY (problem, run, iteration));
CREATE TABLE IF NOT EXISTS evaluations (
    problem TEXT NOT NULL, run INTEGER NOT NULL, seq INTEGER NOT NULL, x BLOB NOT NULL, gradient INTEGER NOT NULL,
    data BLOB NOT NULL, continuation BLOB, PRIMARY KEY (problem, run, seq));
CREATE TABLE IF NOT EXISTS limits (problem TEXT NOT NULL, run INTEGER NOT NULL, data TEXT NOT NULL,
    PRIMARY KEY (problem, run));
CREATE TABLE IF NOT EXISTS finals (problem TEXT NOT NULL, run INTEGER NOT NULL, reference BLOB NOT NULL,
    success INTEGER NOT NULL, PRIMARY KEY (problem, run));
"""


def pack(arrays: dict[str, np.ndarray]) -> bytes:
    """Arrays as .npz bytes (exact float64; read back without pickle)."""
    buf = io.BytesIO()
    np.savez(buf, **{k: np.asarray(v) for k, v in arrays.items()})
    return buf.getvalue()


def unpack(blob: bytes) -> dict[str, np.ndarray]:
    with np.load(io.BytesIO(blob), allow_pickle=False) as z:
        return {k: z[k] for k in z.files}



def fingerprint(problem, method: str) -> tuple[str, np.ndarray]:
    """What defines a run: a hash of its structure (method, variables and their targets and bounds,
    configurations, which data and objective terms exist) and the vector of its numbers (initial
    values, measured data, mass targets), compared with a tolerance, since data recomputed in
    another process may differ in the last bits."""
    h = hashlib.sha256()
    h.update(method.encode())
    numbers = []
    for v, b in zip(problem.par.variables, problem.par.bindings):
        h.update(repr((v.name, v.kind, v.attribute, v.targets, v.bounds, v.scale, v.configurations)).encode())
        numbers.append(np.ravel(b.initial))
    for name, m in sorted(problem.measured.items()):
        h.update(repr((name, len(m.frequencies_hz), None if m.shapes is None else m.shapes.shape,
                       sorted(m.static), None if m.observed_by is None else (m.observed_by.names, m.visibility))
                      ).encode())
        numbers += [m.frequencies_hz, np.ravel(np.abs(m.shapes)) if m.shapes is not None else np.zeros(0),
                    np.array(list(m.static.values()), float)]
    h.update(repr(problem.objective).encode())
    t = problem.mass_target
    if t is not None:
        h.update(repr((t.mass is None, t.cg is None, t.inertia is None, t.cg_scale)).encode())
        numbers.append(np.array([v for v in (t.mass, *(t.cg or ()), *(t.inertia or ())) if v is not None], float))
    return h.hexdigest()[:24], np.concatenate([np.ravel(np.asarray(n, float)) for n in numbers])


class ResultsStore:
    """SQLite file holding runs, their iterates (x, objective, per-configuration frequencies and
    MAC of the paired modes) and evaluations. Held by one process at a time (StoreLockedError
    otherwise); lock=False opens it without the lock, to read a store a run is writing (use
    history() only: a second writer would interleave with the run)."""

    def __init__(self, path: str | Path, lock: bool = True, progress=None):
        self.path = Path(path)
        self.progress = progress or (lambda line: None)
        self._lock = acquire_lock(Path(f"{self.path}.lock"), self.path) if lock else None
        try:
            self._db = sqlite3.connect(str(self.path), isolation_level=None, timeout=30.0)
            self._db.executescript(_SCHEMA)
        except sqlite3.DatabaseError as exc:
            self._release()
            raise FileFormatError(f"{self.path}: not a flexgvt results store ({exc}); give a new file name") from None
        self.problem = ""
        self.exact = True  # the bound problem's numbers are the stored ones bit for bit (replay allowed)

    def bind(self, key: tuple[str, np.ndarray]) -> str:
        """Select the stored problem with this structure and these numbers (to rtol 1e-6), or
        register a new one; returns its key. 1e-6: data recomputed in another process differ by
        ~1e-8 (the eigensolver's random start), and no measurement is given to seven digits."""
        structure, numbers = key
        rows = self._db.execute("SELECT problem, data FROM problems WHERE structure = ?", (structure,)).fetchall()
        for problem, data in rows:
            stored = np.array(json.loads(data), float)
            if stored.shape == numbers.shape and np.allclose(stored, numbers, rtol=1e-6, atol=0.0):
                self.problem = problem
                self.exact = bool(np.array_equal(stored, numbers))
                return problem
        self.problem = f"{structure}-{len(rows)}"
        self.exact = True
        with self._db:
            self._db.execute("INSERT INTO problems VALUES (?, ?, ?)",
                             (self.problem, structure, json.dumps(numbers.tolist())))
        return self.problem

    def record(self, run: int, row: dict) -> None:
        """One iterate (row["iteration"] is its number: a replayed iterate rewrites its own row), in
        its own transaction (an interruption never leaves half a row)."""
        with self._db:
            self._db.execute("INSERT OR IGNORE INTO runs (problem, run, started) VALUES (?, ?, ?)",
                             (self.problem, run, time.time()))
            self._db.execute(
                "INSERT OR REPLACE INTO iterations VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (self.problem, run, int(row["iteration"]), json.dumps(row["x"]), row["objective"],
                 json.dumps(row["frequencies_hz"]), json.dumps(row["mac"]), json.dumps(row["residuals"]),
                 row["time_s"]))

    def record_evaluation(self, run: int, seq: int, x: np.ndarray, gradient: bool, data: dict,
                          continuation: bytes | None) -> None:
        """Evaluation number ``seq`` of ``run``: what the optimiser received (``data``: arrays) and the
        continuation after it (None when nothing was solved), in one transaction."""
        with self._db:
            self._db.execute("INSERT OR IGNORE INTO runs (problem, run, started) VALUES (?, ?, ?)",
                             (self.problem, run, time.time()))
            self._db.execute("INSERT OR REPLACE INTO evaluations VALUES (?, ?, ?, ?, ?, ?, ?)",
                             (self.problem, run, seq, np.asarray(x, float).tobytes(), int(gradient), pack(data),
                              continuation))

    def evaluations(self, run: int) -> list[dict]:
        """The stored evaluations of ``run`` in order (up to the first gap): seq, x (bytes), gradient,
        data (arrays), continuation (bytes or None). A row that cannot be read ends the list. None
        are returned (and those stored are dropped) when the bound problem's numbers match the
        stored ones only to the tolerance of bind: answers computed from other data are not replayed."""
        if not self.exact:
            self.discard(run, 0, 0)
            return []
        rows = self._db.execute("SELECT seq, x, gradient, data, continuation FROM evaluations WHERE problem = ? "
                                "AND run = ? ORDER BY seq", (self.problem, run)).fetchall()
        out = []
        for seq, x, gradient, data, cont in rows:
            if seq != len(out):
                break
            try:
                arrays = unpack(data)
            except (OSError, ValueError, KeyError):
                break
            out.append({"seq": seq, "x": bytes(x), "gradient": bool(gradient), "data": arrays,
                        "continuation": None if cont is None else bytes(cont)})
        return out

    def discard(self, run: int, seq: int, iteration: int) -> None:
        """Forget evaluations from ``seq`` and iterates from ``iteration`` on (a replay that no longer
        matches the record, e.g. after a change of flexgvt's numerics, computes on from there)."""
        with self._db:
            self._db.execute("DELETE FROM evaluations WHERE problem = ? AND run = ? AND seq >= ?",
                             (self.problem, run, seq))
            self._db.execute("DELETE FROM iterations WHERE problem = ? AND run = ? AND iteration >= ?",
                             (self.problem, run, iteration))

    def finish(self, run: int, x: np.ndarray, objective: float, method: str, message: str,
               reference: bytes | None = None, iterations: int | None = None, success: bool = True,
               limits: dict | None = None) -> None:
        """The run's answer, and the continuation it is evaluated from (``reference``, packed), so
        that reading it back computes the same numbers; iterates beyond ``iterations`` are dropped.
        limits: what the run stopped under ({'max_iterations': .., 'tolerance': ..}); finished()
        returns the answer only for these."""
        with self._db:
            self._db.execute("DELETE FROM limits WHERE problem = ? AND run = ?", (self.problem, run))
            if limits is not None:
                self._db.execute("INSERT INTO limits VALUES (?, ?, ?)",
                                 (self.problem, run, json.dumps(limits, sort_keys=True)))
            if reference is not None:
                self._db.execute("INSERT OR REPLACE INTO finals VALUES (?, ?, ?, ?)",
                                 (self.problem, run, reference, int(success)))
            if iterations is not None:
                self._db.execute("DELETE FROM iterations WHERE problem = ? AND run = ? AND iteration >= ?",
                                 (self.problem, run, iterations))
            self._db.execute("INSERT OR IGNORE INTO runs (problem, run, started) VALUES (?, ?, ?)",
                             (self.problem, run, time.time()))
            self._db.execute("UPDATE runs SET finished = ?, x_final = ?, objective = ?, method = ?, message = ? "
                             "WHERE problem = ? AND run = ?",
                             (time.time(), json.dumps(np.asarray(x).tolist()), objective, method, message,
                              self.problem, run))

    def finished(self, run: int, limits: dict | None = None) -> dict | None:
        """The stored answer of ``run`` (x, objective, method, message, reference, success), or None:
        when it never finished, or when ``limits`` are given and differ from those it finished under
        (then the caller runs it again and the record answers up to where it stopped). Says on
        ``progress`` which it is when there is a record."""
        row = self._db.execute("SELECT x_final, objective, method, message FROM runs WHERE problem = ? AND run = ? "
                               "AND finished IS NOT NULL", (self.problem, run)).fetchone()
        done = self.status(run)
        if row is not None and limits is not None:
            stored = self._db.execute("SELECT data FROM limits WHERE problem = ? AND run = ?",
                                      (self.problem, run)).fetchone()
            before = None if stored is None else json.loads(stored[0])
            if before != json.loads(json.dumps(limits, sort_keys=True)):
                was = "unknown limits" if before is None else _limits_text(before)
                self.progress(f"updating{_run_text(run)}: the stored run stopped under {was} at objective "
                              f"{row[1]:.6g}; continuing it under {_limits_text(limits)} ({done['evaluations']} "
                              "stored evaluations answered without solving)")
                return None
        if row is None:
            if done["evaluations"]:
                best = "" if done["best_objective"] is None else f", best objective {done['best_objective']:.6g}"
                self.progress(f"updating{_run_text(run)}: resuming the interrupted run from the store "
                              f"({done['evaluations']} evaluations{best}; answered without solving)")
            return None
        self.progress(f"updating{_run_text(run)}: the finished run read back from the store (same problem, data "
                      "and limits; `flexgvt run --fresh` computes it again)")
        ref = self._db.execute("SELECT reference, success FROM finals WHERE problem = ? AND run = ?",
                               (self.problem, run)).fetchone()
        return {"x": np.array(json.loads(row[0]), float), "objective": row[1], "method": row[2], "message": row[3],
                "reference": None if ref is None else bytes(ref[0]), "success": True if ref is None else bool(ref[1])}

    def status(self, run: int | None = None) -> dict:
        """How far the bound problem got (one run, or all): evaluations stored, accepted iterates and
        the best objective among them (None before the first)."""
        where, args = ("problem = ?", (self.problem,)) if run is None else \
            ("problem = ? AND run = ?", (self.problem, run))
        n = self._db.execute(f"SELECT COUNT(*) FROM evaluations WHERE {where}", args).fetchone()[0]
        k, best = self._db.execute(f"SELECT COUNT(*), MIN(objective) FROM iterations WHERE {where}", args).fetchone()
        return {"evaluations": int(n), "iterations": int(k), "best_objective": None if best is None else float(best)}

    def clear(self) -> None:
        """Forget every stored problem and run (a fresh start)."""
        with self._db:
            for table in ("problems", "runs", "iterations", "evaluations", "finals", "limits"):
                self._db.execute(f"DELETE FROM {table}")

    def history(self, run: int = 0) -> list[dict]:
        rows = self._db.execute("SELECT iteration, x, objective, frequencies, mac FROM iterations WHERE problem = ? "
                                "AND run = ? ORDER BY iteration", (self.problem, run)).fetchall()
        return [{"iteration": i, "x": json.loads(x), "objective": o, "frequencies_hz": json.loads(f),
                 "mac": json.loads(m)} for i, x, o, f, m in rows]

    def close(self) -> None:
        self._db.close()
        self._release()

    def _release(self) -> None:
        if self._lock is not None:
            self._lock.close()  # closing the descriptor releases the lock
            self._lock = None

    def __enter__(self) -> "ResultsStore":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _run_text(run: int) -> str:
    return "" if run == 0 else f" (start {run + 1})"


def _limits_text(limits: dict) -> str:
    return ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in sorted(limits.items()))


def acquire_lock(lock: Path, what: Path):
    """An exclusive OS lock on ``lock`` (created beside ``what``), held by the returned open file;
    StoreLockedError at once, naming the holder, when another process has it."""
    if fcntl is None:  # pragma: no cover
        return None
    try:
        f = open(lock, "a+")
    except OSError as exc:
        raise FileFormatError(f"{lock}: cannot create the lock file of the results store ({exc.strerror}); "
                              "check the folder's permissions") from None
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        f.seek(0)
        holder = f.read(200).strip() or "another process"
        f.close()
        raise StoreLockedError(f"{what} is in use by {holder}: wait until that run ends (or stop it; a run that "
                               "was killed releases the lock by itself), or give another output directory") from None
    f.seek(0)
    f.truncate()
    f.write(f"flexgvt process {os.getpid()} on {socket.gethostname()} since "
            f"{time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime())}\n")
    f.flush()
    return f
