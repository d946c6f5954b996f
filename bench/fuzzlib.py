"""Shared core of the input fuzzers (bench/fuzz_*.py): run a case in a worker process with a
timeout, classify what it raised, group the failures by site, reduce a failing input by lines and
write a summary JSON.

A case function ``func(payload) -> str`` runs inside the worker: it returns a short outcome label
("read", ...) or raises. The worker answers with a dict {"outcome", "class", "site", "message"}:
outcome "clear" for an exception of the ``clear`` classes (flexgvt's own, FlexGVTError), "foreign"
for anything else, "hang" when no answer came within the timeout (the worker is then killed and
restarted) and "crash" when the worker died (segfault, out of memory).

The timeout counts the worker's own CPU time on the case (Linux: /proc), not the wall clock, and
starts once the worker has imported the package: on a loaded machine a case that computes for 2 s
may take 30 s of wall time, and a restarted worker's imports are not the case's. A case that waits
without computing (a deadlock) is caught by the wall clock at ``WALL_FACTOR`` times the timeout.
"""

from __future__ import annotations

import json
import multiprocessing as mp
import os
import time
import traceback
from pathlib import Path

PACKAGE = "flexgvt"
WALL_FACTOR = 20.0
_START_S = 600.0  # the longest a fresh worker may take to import the package


def cpu_seconds(pid: int) -> float | None:
    """CPU time (user + system, all threads) the process ``pid`` has used [s]; None where /proc is
    not available."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return None


def classify(exc: BaseException, clear: tuple = ()) -> dict:
    """{"outcome": "clear"|"foreign", "class", "site", "message"}; site is the innermost frame in
    the package (``flexgvt/io/nastran/_read.py:240 check_references``), else the innermost frame."""
    frames = traceback.extract_tb(exc.__traceback__)
    ours = [f for f in frames if f"/{PACKAGE}/" in f.filename.replace("\\", "/")]
    frame = (ours or frames or [None])[-1]
    site = ""
    if frame is not None:
        name = frame.filename.replace("\\", "/")
        name = PACKAGE + "/" + name.rsplit(f"/{PACKAGE}/", 1)[1] if f"/{PACKAGE}/" in name else Path(name).name
        site = f"{name}:{frame.lineno} {frame.name}"
    try:
        message = (str(exc).splitlines() or [""])[0][:300]
    except Exception as inner:  # noqa: BLE001 - an exception whose message itself fails
        message = f"(str() raised {type(inner).__name__})"
    return {"outcome": "clear" if isinstance(exc, clear) else "foreign", "class": type(exc).__name__, "site": site,
            "message": message}


def _serve(conn, memory_bytes: int | None) -> None:
    """Worker loop: (func, payload, clear) in, outcome dict out."""
    import warnings

    if memory_bytes:
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, memory_bytes))
    try:
        __import__(PACKAGE)
    except BaseException:  # noqa: BLE001 - the case will raise it again and be classified
        pass
    conn.send("ready")
    while True:
        try:
            job = conn.recv()
        except EOFError:
            return
        if job is None:
            return
        func, payload, clear = job
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = {"outcome": str(func(payload)), "class": "", "site": "", "message": ""}
        except BaseException as exc:  # noqa: BLE001 - classifying every exception is the point
            result = classify(exc, clear)
        conn.send(result)


class Worker:
    """One worker process (spawned: a clean interpreter) running cases one at a time with a timeout."""

    def __init__(self, timeout: float = 20.0, memory_bytes: int | None = 4 << 30, wall_factor: float = WALL_FACTOR):
        self.timeout, self.memory_bytes, self.wall_factor = timeout, memory_bytes, wall_factor
        self._ctx = mp.get_context("spawn")
        self._proc = None

    def _start(self) -> None:
        self._conn, child = self._ctx.Pipe()
        self._proc = self._ctx.Process(target=_serve, args=(child, self.memory_bytes), daemon=True)
        self._proc.start()
        child.close()
        if self._conn.poll(_START_S):
            try:
                self._conn.recv()
            except EOFError:
                pass

    def _answered(self, timeout: float) -> bool | str:
        """Wait for the answer: True when it came (or the worker died), else the budget that ran out."""
        pid = self._proc.pid
        cpu0, wall0 = cpu_seconds(pid), time.monotonic()
        while not self._conn.poll(0.05):
            wall = time.monotonic() - wall0
            cpu = cpu_seconds(pid)
            if cpu0 is None or cpu is None:
                if wall > timeout:
                    return f"{timeout:g} s"
            elif cpu - cpu0 > timeout:
                return f"{timeout:g} s of CPU time"
            elif wall > self.wall_factor * timeout:
                return f"{self.wall_factor * timeout:g} s (waiting, not computing)"
            if not self._proc.is_alive():
                return True
        return True

    def run(self, func, payload, clear: tuple = (), timeout: float | None = None) -> dict:
        if self._proc is None or not self._proc.is_alive():
            self._start()
        limit = self.timeout if timeout is None else timeout
        self._conn.send((func, payload, clear))
        answered = self._answered(limit)
        if answered is True:
            if self._conn.poll():
                try:
                    return self._conn.recv()
                except EOFError:
                    pass
        else:
            self.close(kill=True)
            return {"outcome": "hang", "class": "Hang", "site": "", "message": f"no answer in {answered}"}
        if self._proc is not None:
            self._proc.join(5)
        code = self._proc.exitcode if self._proc is not None else None
        self.close(kill=True)
        return {"outcome": "crash", "class": "Crash", "site": "", "message": f"worker died (exit code {code})"}

    def close(self, kill: bool = False) -> None:
        if self._proc is None:
            return
        if kill:
            self._proc.kill()
        else:
            try:
                self._conn.send(None)
            except (BrokenPipeError, OSError):
                pass
        self._proc.join(5)
        if self._proc.is_alive():
            self._proc.kill()
            self._proc.join()
        self._proc = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def site_key(result: dict) -> str:
    """Group name of a failure: class and innermost package frame (file and function, no line)."""
    site = result["site"].split(" ", 1)
    where = site[0].rsplit(":", 1)[0] + (f" {site[1]}" if len(site) > 1 else "") if result["site"] else ""
    return f"{result['class']} @ {where}" if where else result["class"]


class Tally:
    """Counts per outcome and the failures (foreign, hang, crash) grouped by site_key."""

    BAD = ("foreign", "hang", "crash")

    def __init__(self):
        self.counts: dict[str, int] = {}
        self.groups: dict[str, dict] = {}

    def add(self, case: str, result: dict) -> str | None:
        """Count ``result``; returns the group key when it is a new failure group (else None)."""
        self.counts[result["outcome"]] = self.counts.get(result["outcome"], 0) + 1
        if result["outcome"] not in self.BAD:
            return None
        key = site_key(result)
        group = self.groups.setdefault(key, {"count": 0, "cases": [], "message": result["message"],
                                             "site": result["site"]})
        group["count"] += 1
        group["cases"].append(case)
        return key if group["count"] == 1 else None

    @property
    def failures(self) -> int:
        return sum(self.counts.get(k, 0) for k in self.BAD)

    def write(self, path: Path, **extra) -> None:
        data = {**extra, "counts": self.counts, "failures": self.failures,
                "groups": {k: {**v, "cases": v["cases"][:20]} for k, v in sorted(self.groups.items())}}
        Path(path).write_text(json.dumps(data, indent=1))


def reduce_lines(lines: list[str], still_fails, max_tries: int = 300) -> list[str]:
    """Fewest lines (greedy chunk removal, halving the chunk) for which ``still_fails(lines)`` holds."""
    tries, chunk = 0, max(1, len(lines) // 2)
    while chunk >= 1 and tries < max_tries:
        k, removed = 0, False
        while k < len(lines) and tries < max_tries:
            trial = lines[:k] + lines[k + chunk:]
            tries += 1
            if trial and still_fails(trial):
                lines, removed = trial, True
            else:
                k += chunk
        if not removed:
            chunk //= 2
    return lines


def main(argv, doc: str, fuzz, *, n: int, out: str, what: str, columns: tuple[tuple[str, str], ...]) -> int:
    """The command line every fuzzer shares (--n --seed --timeout --out --no-reduce): run
    ``fuzz(n, seed, timeout, out, reduce=...) -> Tally`` and print its table; status 1 on failures.
    columns: (heading, count key) of the fuzzer's own outcomes before the common ones."""
    import argparse
    import time

    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=n)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per case before it counts as a hang")
    ap.add_argument("--out", type=Path, default=Path(out))
    ap.add_argument("--no-reduce", action="store_true", help="save failing inputs without reducing them")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    tally = fuzz(args.n, args.seed, args.timeout, args.out, reduce=not args.no_reduce)
    c = tally.counts
    cols = columns + (("clear flexgvt errors", "clear"), ("foreign exceptions", "foreign"), ("hangs", "hang"),
                      ("worker crashes", "crash"))
    print(f"\n{args.n} mutated {what} (seed {args.seed}, timeout {args.timeout:g} s) in "
          f"{time.perf_counter() - t0:.0f} s")
    print("| " + " | ".join(h for h, _ in cols) + " |")
    print("|" + "---:|" * len(cols))
    print("| " + " | ".join(str(c.get(k, 0)) for _, k in cols) + " |")
    for key, g in sorted(tally.groups.items()):
        print(f"  {g['count']:5d}  {key}: {g['message'][:120]}")
    return 1 if tally.failures else 0
