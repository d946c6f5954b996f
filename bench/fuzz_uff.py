"""Fuzz the UFF reader and what follows it: mutated UFF files through read_uff, then .frfs and PolyMAX
on the FRFs, the modes (as a project reads them, flexgvt.workflow.read_modes) and the geometry.

    python bench/fuzz_uff.py --n 4000 --seed 1 --timeout 20 --out fuzz-uff

Sources: the real files of tests/data/uff (LMS Test.Lab, OROS, ArtemiS, NX, a binary 58b record) and
flexgvt's own output written at start (geometry + FRFs in ASCII and binary 58b, modes UFF 55 with
the standard-deviation lines `flexgvt ema identify` writes, a force and two responses as time
histories). Each case is described (describe_uff), read with drop_incomplete=True, and its time
histories turned into FRFs. Each case applies one or two mutations:
a field replaced (0, -1, 1e20, 1e300, nan, text, blank...), a line deleted, duplicated or cut, a
node count or id changed, two datasets swapped, a dataset duplicated or its delimiter lost, the file
truncated, random bytes. Outcomes (bench/fuzzlib.py): read, clear (a FlexGVTError), foreign (any
other exception), hang (no answer within the timeout), crash. Foreign exceptions and hangs are
grouped by class and innermost flexgvt frame; the first file of each group is saved in
OUT/reproducers/<group>/ (original.uff and a line-reduced minimal.uff). OUT/summary.json: the counts.
"""

from __future__ import annotations

import contextlib
import io
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import fuzzlib  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "uff"
REAL = ["TestLab 161 164 18 15 82.uff", "mesh_Oros-modal_uff15_uff2412.uff",
        "Artemis export - Geometry RPBC_setup_05_14102016_105117.uff", "NX simulation output.uff",
        "Sample_UFF58b_bin.uff"]
OWN = ["own_frfs.uff", "own_frfs_58b.uff", "own_modes.uff", "own_time.uff"]
VALUES = [b"0", b"-1", b"1", b"2", b"7", b"58", b"55", b"15", b"1e20", b"1.0E+300", b"-1e300", b"nan", b"inf",
          b"", b"abc", b"99999999999", b"2147483648", b"-0", b"1.5", b"0.0", b"1E-300", b"D", b"-99999"]
DELIM = b"    -1"


def write_own(folder: Path) -> dict[str, bytes]:
    """flexgvt's own UFF output: FRFs with geometry (ASCII and binary 58b), modes with standard deviations."""
    from flexgvt.ema import ModalModel, synthesize_frfs
    from flexgvt.io.uff import ModalResults, TestGeometry, write_uff

    rng = np.random.default_rng(4)
    model = ModalModel(np.array([1.2, 3.4, 7.9]), np.array([0.02, 0.015, 0.01]), rng.standard_normal((3, 6)))
    frfs = synthesize_frfs(model, np.linspace(0.2, 12, 240), list(range(6)), [0, 3], snr_db=40, seed=2)
    pts = np.unique(frfs.outputs[:, 0])
    geo = TestGeometry(pts, rng.standard_normal((len(pts), 3)))
    out = {}
    for name, binary in (("own_frfs.uff", False), ("own_frfs_58b.uff", True)):
        out[name] = write_uff(folder / name, geometry=geo, frfs=frfs, binary=binary).read_bytes()
    modes = ModalResults(np.array([1.2, 3.4, 7.9]), np.array([0.02, 0.015, 0.01]),
                         rng.standard_normal((3, len(pts), 3)),
                         pts, np.array([0.001, 0.002, 0.004]), np.array([0.001, 0.001, 0.002]))
    out["own_modes.uff"] = write_uff(folder / "own_modes.uff", geometry=geo, modes=modes).read_bytes()
    from flexgvt.ema import synthesize_time_data
    from flexgvt.io.uff import TimeHistories

    _, force, resp = synthesize_time_data(model, 32.0, 8.0, [0, 1], [0], snr_db=30, seed=1)
    th = TimeHistories(np.vstack([force, resp]), np.array([[9, 3], [1, 3], [2, 3]]), 32.0, units=("N", "m", "m"),
                       spec_types=(13, 8, 8))
    out["own_time.uff"] = write_uff(folder / "own_time.uff", geometry=geo, time_histories=th).read_bytes()
    return out


def sources() -> dict[str, bytes]:
    folder = Path(tempfile.mkdtemp(prefix="fuzz_uff_src_"))
    own = write_own(folder)
    return {**{name: (DATA / name).read_bytes() for name in REAL}, **own}


def _datasets(lines: list[bytes]) -> list[tuple[int, int]]:
    """(first, last) line indices of each dataset, delimiters included."""
    marks = [i for i, ln in enumerate(lines) if ln.rstrip() == DELIM]
    return [(marks[k], marks[k + 1]) for k in range(0, len(marks) - 1, 2)]


def _text_lines(lines: list[bytes]) -> list[int]:
    """Indices of the lines that look like ASCII text (the binary payload of 58b is left alone)."""
    return [i for i, ln in enumerate(lines) if len(ln) < 100 and all(32 <= c < 127 or c in (9, 13) for c in ln)] or [0]


def _replace_field(line: bytes, rng, value: bytes | None = None) -> bytes:
    fields = list(re.finditer(rb"\S+", line))
    if not fields:
        return line + b" " + (value if value is not None else rng.choice(VALUES))
    m = fields[int(rng.integers(len(fields)))]
    new = value if value is not None else VALUES[int(rng.integers(len(VALUES)))]
    width = m.end() - m.start()
    new = new.rjust(width) if len(new) <= width else new  # keep columns where it fits
    return line[:m.start()] + new + line[m.end():]


def mutate(data: bytes, rng: np.random.Generator) -> tuple[bytes, str]:
    """(mutated file, description)."""
    lines = data.split(b"\n")
    text = _text_lines(lines)
    k = int(rng.choice(text))
    kind = int(rng.choice(10, p=[0.28, 0.1, 0.08, 0.1, 0.1, 0.08, 0.06, 0.05, 0.05, 0.1]))
    if kind == 0:
        lines[k] = _replace_field(lines[k], rng)
        return b"\n".join(lines), f"field replaced, line {k + 1}"
    if kind == 1:
        del lines[k]
        return b"\n".join(lines), f"line {k + 1} deleted"
    if kind == 2:
        lines.insert(k, lines[k])
        return b"\n".join(lines), f"line {k + 1} duplicated"
    if kind == 3:  # a line cut short
        cut = int(rng.integers(0, max(1, len(lines[k]))))
        lines[k] = lines[k][:cut]
        return b"\n".join(lines), f"line {k + 1} cut at column {cut}"
    if kind == 4:  # a count or id changed (first field of a line: node ids, counts, set types)
        value = str(int(rng.choice([0, -1, 1, 2, 3, 5, 6, 10, 40, 100, 999999, 2**31]))).encode()
        fields = list(re.finditer(rb"\S+", lines[k]))
        if fields:
            j = int(rng.integers(min(3, len(fields))))
            m = fields[j]
            lines[k] = lines[k][:m.start()] + value.rjust(m.end() - m.start()) + lines[k][m.end():]
        return b"\n".join(lines), f"count or id changed, line {k + 1}"
    sets = _datasets(lines)
    if kind == 5 and len(sets) >= 2:  # two datasets swapped
        a, b = sorted(rng.choice(len(sets), 2, replace=False))
        (a0, a1), (b0, b1) = sets[a], sets[b]
        lines = lines[:a0] + lines[b0:b1 + 1] + lines[a1 + 1:b0] + lines[a0:a1 + 1] + lines[b1 + 1:]
        return b"\n".join(lines), f"datasets {a + 1} and {b + 1} swapped"
    if kind == 6 and sets:  # a dataset duplicated
        a0, a1 = sets[int(rng.integers(len(sets)))]
        lines = lines[:a1 + 1] + lines[a0:a1 + 1] + lines[a1 + 1:]
        return b"\n".join(lines), f"dataset at line {a0 + 1} duplicated"
    if kind == 7 and sets:  # a delimiter lost
        a0, a1 = sets[int(rng.integers(len(sets)))]
        j = a0 if rng.random() < 0.5 else a1
        del lines[j]
        return b"\n".join(lines), f"delimiter at line {j + 1} deleted"
    if kind == 8:
        cut = int(rng.integers(1, len(data)))
        return data[:cut], f"truncated at byte {cut}"
    b = bytearray(data)
    for _ in range(int(rng.integers(1, 8))):
        b[int(rng.integers(len(b)))] = int(rng.integers(0, 256)) if rng.random() < 0.3 else int(rng.integers(32, 127))
    return bytes(b), "random bytes"


_TMP: list[Path] = []


def run_case(payload: bytes) -> str:
    """Worker side: read the file, then use what it holds as flexgvt does."""
    from flexgvt.ema import polymax
    from flexgvt.ema import estimate_frf_from_time
    from flexgvt.io.uff import describe_uff, read_uff, shapes_at_points
    from flexgvt.workflow import read_modes

    if not _TMP:
        _TMP.append(Path(tempfile.mkdtemp(prefix="fuzz_uff_")))
    path = _TMP[0] / "case.uff"
    path.write_bytes(payload)
    with contextlib.redirect_stdout(io.StringIO()):  # pyuff prints notes about skipped datasets
        str(describe_uff(path))
        data = read_uff(path, drop_incomplete=True)
    outcome = "read"
    if any(f.kind == "time response" for f in data.functions):
        th = data.time_histories
        if th.n_samples >= 64:
            estimate_frf_from_time(th, nperseg=64)
    if data.geometry is not None and len(data.geometry.point_ids):
        data.geometry.index(int(data.geometry.point_ids[-1]))
    if data.modes is not None:
        read_modes(path, "fuzz")
    if any(f.kind == "FRF" for f in data.functions):
        frfs = data.frfs
        if frfs.H.size <= 50_000:
            modes = polymax(frfs, max_order=12).select()
            if len(modes.frequencies_hz) and np.all(np.abs(frfs.outputs[:, 1]) <= 3):
                shapes_at_points(np.real(modes.shapes), frfs.outputs)
            outcome = "identified"
    return outcome


def _clear():
    from flexgvt.errors import FlexGVTError
    return (FlexGVTError,)


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_")[:90]


def fuzz(n: int, seed: int, timeout: float, out: Path | None = None, names=None, reduce: bool = True,
         log=print) -> fuzzlib.Tally:
    """Run ``n`` mutated UFF files; returns the Tally (and writes OUT/summary.json, OUT/reproducers)."""
    rng = np.random.default_rng(seed)
    files = sources()
    names = list(names or files)
    tally = fuzzlib.Tally()
    clear = _clear()
    t0 = time.perf_counter()
    with fuzzlib.Worker(timeout=timeout) as worker:
        for case in range(n):
            name = names[int(rng.integers(len(names)))]
            payload, what = mutate(files[name], rng)
            if rng.random() < 0.2:  # a second mutation
                payload, more = mutate(payload, rng)
                what += "; " + more
            result = worker.run(run_case, payload, clear)
            new = tally.add(f"{case}: {name}, {what}", result)
            if new and out is not None:
                _save(out / "reproducers" / _safe(new), payload, result, worker, clear, reduce, log)
            if log and (case + 1) % 500 == 0:
                log(f"{case + 1} cases, {time.perf_counter() - t0:.0f} s: {tally.counts}")
    if out is not None:
        tally.write(out / "summary.json", n=n, seed=seed, timeout_s=timeout, sources=names,
                    elapsed_s=round(time.perf_counter() - t0, 1))
    return tally


def _save(folder: Path, payload: bytes, result, worker, clear, reduce: bool, log) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "original.uff").write_bytes(payload)
    (folder / "error.txt").write_text(f"{result['class']} at {result['site']}: {result['message']}\n")
    if not reduce or result["outcome"] == "hang":
        return
    key = fuzzlib.site_key(result)

    def still_fails(lines):
        got = worker.run(run_case, b"\n".join(lines), clear)
        return got["outcome"] in fuzzlib.Tally.BAD and fuzzlib.site_key(got) == key

    minimal = fuzzlib.reduce_lines(payload.split(b"\n"), still_fails, max_tries=150)
    (folder / "minimal.uff").write_bytes(b"\n".join(minimal) + b"\n")
    if log:
        log(f"new failure {key}: {len(minimal)} line(s) kept in {folder}")


def main(argv=None) -> int:
    return fuzzlib.main(argv, __doc__, fuzz, n=4000, out="fuzz-uff", what="UFF files",
                        columns=(("read", "read"), ("read and identified", "identified")))

if __name__ == "__main__":
    sys.exit(main())
