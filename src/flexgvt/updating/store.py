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
CREATE TABLE IF NOT EXISTS runs (
    problem TEXT NOT NULL, run INTEGER NOT NULL, method TEXT, started REAL, finished REAL,
    x_final TEXT, objective REAL, message TEXT, PRIMARY KEY (problem, run));
CREATE TABLE IF NOT EXISTS iterations (
    problem TEXT NOT NULL, run INTEGER NOT NULL, iteration INTEGER NOT NULL, x TEXT NOT NULL,
    objective REAL NOT NULL, frequencies TEXT, mac TEXT, residuals TEXT, time REAL,
    PRIMARY KEY (problem, run, iteration));
"""


def fingerprint(problem, method: str) -> str:
    """A hash of what defines a run: variables, bounds, configurations, measured data, objective, method."""
    h = hashlib.sha256()
    h.update(method.encode())
    for v in problem.par.variables:
        h.update(repr((v.name, v.kind, v.attribute, v.targets, v.bounds, v.scale, v.configurations)).encode())
    for b in problem.par.bindings:
        h.update(np.ascontiguousarray(b.initial, float).tobytes())
    for name, m in sorted(problem.measured.items()):
        h.update(name.encode())
        h.update(np.ascontiguousarray(m.frequencies_hz).tobytes())
        if m.shapes is not None:
            h.update(np.ascontiguousarray(m.shapes).tobytes())
    h.update(repr(problem.objective).encode())
    h.update(repr(problem.mass_target).encode())
    return h.hexdigest()[:32]


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

    def bind(self, problem_key: str) -> None:
        self.problem = problem_key

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
