"""The results store: an updating run's history in SQLite, one transaction per accepted iterate,
so that an interrupted run resumes where it stopped and reaches the same answer.

    store = fg.updating.ResultsStore("run.sqlite")
    result = fg.updating.update(model, configs, data, variables, store=store)   # rerun: resumes
"""

from __future__ import annotations

import hashlib
import json
import sqlite3
import time
from pathlib import Path

import numpy as np

from ..errors import FileFormatError

_SCHEMA = """
CREATE TABLE IF NOT EXISTS problems (problem TEXT PRIMARY KEY, structure TEXT NOT NULL, data TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS runs (
    problem TEXT NOT NULL, run INTEGER NOT NULL, method TEXT, started REAL, finished REAL,
    x_final TEXT, objective REAL, message TEXT, PRIMARY KEY (problem, run));
CREATE TABLE IF NOT EXISTS iterations (
    problem TEXT NOT NULL, run INTEGER NOT NULL, iteration INTEGER NOT NULL, x TEXT NOT NULL,
    objective REAL NOT NULL, frequencies TEXT, mac TEXT, residuals TEXT, time REAL,
    PRIMARY KEY (problem, run, iteration));
"""


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
    """SQLite file holding runs and their iterates (x, objective, per-configuration frequencies and
    MAC of the paired modes)."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        try:
            self._db = sqlite3.connect(str(self.path), isolation_level=None, timeout=30.0)
            self._db.executescript(_SCHEMA)
        except sqlite3.DatabaseError as exc:
            raise FileFormatError(f"{self.path}: not a flexgvt results store ({exc}); give a new file name") from None
        self.problem = ""

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
                return problem
        self.problem = f"{structure}-{len(rows)}"
        with self._db:
            self._db.execute("INSERT INTO problems VALUES (?, ?, ?)",
                             (self.problem, structure, json.dumps(numbers.tolist())))
        return self.problem

    def record(self, run: int, row: dict) -> None:
        """One iterate, in its own transaction (an interruption never leaves half a row)."""
        with self._db:
            self._db.execute("INSERT OR IGNORE INTO runs (problem, run, started) VALUES (?, ?, ?)",
                             (self.problem, run, time.time()))
            self._db.execute(
                "INSERT OR REPLACE INTO iterations VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (self.problem, run, self._next(run), json.dumps(row["x"]), row["objective"],
                 json.dumps(row["frequencies_hz"]), json.dumps(row["mac"]), json.dumps(row["residuals"]),
                 row["time_s"]))

    def _next(self, run: int) -> int:
        got = self._db.execute("SELECT MAX(iteration) FROM iterations WHERE problem = ? AND run = ?",
                               (self.problem, run)).fetchone()[0]
        return 0 if got is None else got + 1

    def finish(self, run: int, x: np.ndarray, objective: float, method: str, message: str) -> None:
        with self._db:
            self._db.execute("INSERT OR IGNORE INTO runs (problem, run, started) VALUES (?, ?, ?)",
                             (self.problem, run, time.time()))
            self._db.execute("UPDATE runs SET finished = ?, x_final = ?, objective = ?, method = ?, message = ? "
                             "WHERE problem = ? AND run = ?",
                             (time.time(), json.dumps(np.asarray(x).tolist()), objective, method, message,
                              self.problem, run))

    def finished(self, run: int) -> dict | None:
        row = self._db.execute("SELECT x_final, objective, method, message FROM runs WHERE problem = ? AND run = ? "
                               "AND finished IS NOT NULL", (self.problem, run)).fetchone()
        if row is None:
            return None
        return {"x": np.array(json.loads(row[0])), "objective": row[1], "method": row[2], "message": row[3]}

    def best(self, run: int) -> np.ndarray | None:
        """The lowest-objective iterate recorded for ``run`` (where an interrupted run resumes)."""
        row = self._db.execute("SELECT x FROM iterations WHERE problem = ? AND run = ? ORDER BY objective, "
                               "iteration DESC LIMIT 1", (self.problem, run)).fetchone()
        return None if row is None else np.array(json.loads(row[0]))

    def history(self, run: int = 0) -> list[dict]:
        rows = self._db.execute("SELECT iteration, x, objective, frequencies, mac FROM iterations WHERE problem = ? "
                                "AND run = ? ORDER BY iteration", (self.problem, run)).fetchall()
        return [{"iteration": i, "x": json.loads(x), "objective": o, "frequencies_hz": json.loads(f),
                 "mac": json.loads(m)} for i, x, o, f, m in rows]

    def close(self) -> None:
        self._db.close()
