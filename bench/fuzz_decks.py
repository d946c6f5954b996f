"""Fuzz the Nastran reader and solver: mutated decks through read_bdf + solve_deck.

    python bench/fuzz_decks.py --n 10000 --seed 1 --timeout 20 --out fuzz-decks

Each case is one real or synthetic deck of tests/data/bdf with one mutation (a field replaced by
0, -1, 1e20, 1e300, nan, blank, text...; a huge THRU range, set or card replication; a line
deleted, duplicated or truncated; two fields swapped; random bytes; or a few of these at once),
run in a worker process with a per-case timeout. Outcomes: read (read and solved), clear (a
FlexGVTError), foreign (any other exception), hang (no answer within the timeout), crash (the
worker died). Foreign exceptions and
hangs are grouped by class and innermost flexgvt frame; the first case of each group is saved in
OUT/reproducers/<group>/ with a line-reduced minimal deck. OUT/summary.json holds the counts.
"""

from __future__ import annotations

import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import fuzzlib  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "bdf"
SOURCES = ["all_cards.bdf", "rods.bdf", "pynastran/sdof_crod.bdf", "pynastran/pt145.bdf", "pynastran/ha144/ha144ds.bdf",
           "pynastran/ha144/ha144da.bdf", "pynastran/strut_wing/buckled.bdf", "pynastran/fmondsp.dat",
           "pynastran/euler_column_linear_buckling.bdf", "beam_modes/beam_modes.dat", "beam_modes/cbar_cbeam.blk",
           "pynastran/cantilever_2014.1.bdf", "plates.bdf", "pynastran/goland/goland_final_test.bdf"]
SMALL_SOURCES = SOURCES[:7] + ["beam_modes/beam_modes.dat", "beam_modes/cbar_cbeam.blk"]
INCLUDES = {"beam_modes/beam_modes.dat": ["beam_modes/cbar_cbeam.blk"]}  # written beside the mutated deck
VALUES = ["0", "0.", "-1", "-1.", "1e20", "1.e20", "1e300", "-1e300", "1.+300", "1e308", "1e-300", "nan", "inf",
          "-inf", "", "abc", "YES", "1.5", "99999999", "100000000", "2147483648", "99999999999999999999", "+", "*",
          "=", "THRU", "-99999999", "1.e+30"]
HUGE = [2147483648, 100_000_000, 99_999_999, 10**12, 20_000_001]


def _split(line: str):
    """(free, head, fields, width) of a bulk data line."""
    if "," in line:
        parts = line.split(",")
        return True, parts[0], parts[1:], 0
    s = line.expandtabs(8) if "\t" in line else line
    head = s[:8]
    width = 16 if head.strip().endswith("*") else 8
    body = s[8:72]
    return False, head, [body[i:i + width] for i in range(0, len(body), width)], width


def _join(free: bool, head: str, fields: list[str], width: int) -> str:
    if free or any(len(f.strip()) > width for f in fields):  # a long value: write the line free field
        return ",".join([head.strip()] + [f.strip() for f in fields])
    return head.ljust(8)[:8] + "".join(f.rjust(width) if f.strip() else " " * width for f in fields)


def _bulk(lines: list[str]) -> list[int]:
    start = next((i + 1 for i, ln in enumerate(lines) if ln.upper().replace(" ", "").startswith("BEGINBULK")), 0)
    return [i for i in range(start, len(lines)) if lines[i].strip() and not lines[i].startswith("$")
            and not lines[i].upper().startswith("ENDDATA")] or [0]


def mutate(text: str, rng: np.random.Generator) -> tuple[str, str]:
    """(mutated deck, description of the mutation)."""
    lines = text.split("\n")
    bulk = _bulk(lines)
    k = int(rng.choice(bulk))
    kind = int(rng.choice(10, p=[0.3, 0.07, 0.07, 0.05, 0.09, 0.1, 0.08, 0.06, 0.1, 0.08]))
    if kind == 9:  # a few mutations at once (combinations of bad values, ids and lines)
        whats = []
        for _ in range(int(rng.integers(2, 5))):
            text, what = mutate(text, rng)
            whats.append(what)
        return text, "; ".join(whats)
    if kind in (0, 8):  # one (or two) fields replaced
        for _ in range(1 + (kind == 8)):
            k = int(rng.choice(bulk))
            free, head, fields, width = _split(lines[k])
            if not fields:
                continue
            j = int(rng.integers(len(fields)))
            value = str(rng.choice(VALUES))
            fields[j] = value
            lines[k] = _join(free, head, fields, width)
        return "\n".join(lines), f"field(s) replaced, line {k + 1}"
    if kind == 1:
        del lines[k]
        return "\n".join(lines), f"line {k + 1} deleted"
    if kind == 2:
        lines.insert(k, lines[k])
        return "\n".join(lines), f"line {k + 1} duplicated"
    if kind == 3:
        cut = int(rng.integers(1, len(text)))
        return text[:cut], f"truncated at character {cut}"
    if kind == 4:  # two fields swapped
        free, head, fields, width = _split(lines[k])
        if len(fields) >= 2:
            a, b = rng.choice(len(fields), 2, replace=False)
            fields[a], fields[b] = fields[b], fields[a]
            lines[k] = _join(free, head, fields, width)
        return "\n".join(lines), f"fields swapped, line {k + 1}"
    if kind == 5:  # an id or reference changed
        free, head, fields, width = _split(lines[k])
        if fields:
            j = int(rng.integers(min(4, len(fields))))
            fields[j] = str(int(rng.choice([0, -1, 1, 2, 3, 7, 10, 100, 99999999, 100000000])))
            lines[k] = _join(free, head, fields, width)
        return "\n".join(lines), f"id changed, line {k + 1}"
    if kind == 6:  # a huge expansion
        big = int(rng.choice(HUGE))
        card = [f"SET1,99001,1,THRU,{big}", f"SPC1,99001,123456,1,THRU,{big}", f"SPOINT,1,THRU,{big}",
                f"SET1,99001,{big},THRU,{big + big}", "=(" + str(big) + ")", f"EPOINT,5,THRU,{big}"]
        pick = int(rng.integers(len(card) + 1))
        if pick == len(card):  # case control set
            cc = next((i for i, ln in enumerate(lines) if ln.upper().startswith("BEGIN")), None)
            if cc is not None:
                lines.insert(cc, f"SET 99001 = 1 THRU {big}")
                return "\n".join(lines), f"case control SET 1 THRU {big}"
            pick = 0
        lines.insert(k + 1, card[pick])
        return "\n".join(lines), f"{card[pick]} after line {k + 1}"
    # random printable bytes
    chars = list(text)
    for _ in range(int(rng.integers(1, 8))):
        chars[int(rng.integers(len(chars)))] = chr(int(rng.integers(32, 127)))
    return "".join(chars), "random characters"


_TMP: list[Path] = []


def run_case(payload: tuple) -> str:
    """Worker side: write the deck (and its includes) in the worker's own folder, which is also its
    working directory, read it and solve every subcase; a file left behind is an error too."""
    import os

    import flexgvt as fg
    from flexgvt.workflow.deck import solve_deck

    text, suffix, unsupported = payload[:3]
    includes = payload[3] if len(payload) > 3 else {}
    if not _TMP:
        _TMP.append(Path(tempfile.mkdtemp(prefix="fuzz_decks_")))
        os.chdir(_TMP[0])
    folder = _TMP[0]
    for old in folder.iterdir():
        old.unlink()
    for name, content in includes.items():
        (folder / name).write_text(content)
    path = folder / f"case{suffix}"
    path.write_text(text)
    try:
        deck = fg.io.read_bdf(path, unsupported=unsupported)
        for name, result in solve_deck(deck).items():
            values = [result.modes.frequencies_hz, result.state.displacements]
            if not all(np.all(np.isfinite(np.asarray(v, float))) for v in values):
                raise SilentNonFinite(f"configuration {name}: NaN or infinite frequencies or displacements, no error")
    finally:
        stray = sorted(p.name for p in folder.iterdir() if p.name not in {path.name, *includes})
    if stray:
        raise StrayFile(f"files written in the working directory: {stray}")
    return "read"


class SilentNonFinite(Exception):
    """A deck read and solved without an error but with NaN or infinite results."""


class StrayFile(Exception):
    """Reading or solving a deck left a file in the working directory (pyNastran_crash.bdf)."""


def _clear():
    from flexgvt.errors import FlexGVTError
    return (FlexGVTError,)


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_")[:90]


def fuzz(n: int, seed: int, timeout: float, out: Path | None = None, sources=SOURCES, reduce: bool = True,
         log=print) -> fuzzlib.Tally:
    """Run ``n`` mutated decks; returns the Tally (and writes OUT/summary.json, OUT/reproducers)."""
    rng = np.random.default_rng(seed)
    texts = [(DATA / s).read_text(errors="replace") for s in sources]
    includes = [{Path(i).name: (DATA / i).read_text() for i in INCLUDES.get(s, [])} for s in sources]
    tally = fuzzlib.Tally()
    clear = _clear()
    t0 = time.perf_counter()
    with fuzzlib.Worker(timeout=timeout) as worker:
        for case in range(n):
            src = int(rng.integers(len(sources)))
            text, what = mutate(texts[src], rng)
            suffix = Path(sources[src]).suffix
            payload = (text, suffix, ("warn", "error")[case % 2], includes[src])
            result = worker.run(run_case, payload, clear)
            new = tally.add(f"{case}: {sources[src]}, {what}", result)
            if new and out is not None:
                _save(out / "reproducers" / _safe(new), payload, result, worker, clear, reduce, log)
            if log and (case + 1) % 500 == 0:
                log(f"{case + 1} cases, {time.perf_counter() - t0:.0f} s: {tally.counts}")
    if out is not None:
        tally.write(out / "summary.json", n=n, seed=seed, timeout_s=timeout, sources=list(sources),
                    elapsed_s=round(time.perf_counter() - t0, 1))
    return tally


def _save(folder: Path, payload, result, worker, clear, reduce: bool, log) -> None:
    text, suffix, unsupported, includes = payload
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"original{suffix}").write_text(text)
    for name, content in includes.items():
        (folder / name).write_text(content)
    (folder / "error.txt").write_text(f"{result['class']} at {result['site']}: {result['message']}\n"
                                      f"read_bdf(..., unsupported='{unsupported}') then solve_deck\n")
    if not reduce or result["outcome"] == "hang":
        return
    key = fuzzlib.site_key(result)

    def still_fails(lines):
        got = worker.run(run_case, ("\n".join(lines), suffix, unsupported, includes), clear)
        return fuzzlib.site_key(got) == key if got["outcome"] in fuzzlib.Tally.BAD else False

    minimal = fuzzlib.reduce_lines(text.split("\n"), still_fails)
    (folder / f"minimal{suffix}").write_text("\n".join(minimal) + "\n")
    if log:
        log(f"new failure {key}: {len(minimal)} line(s) kept in {folder}")


def main(argv=None) -> int:
    return fuzzlib.main(argv, __doc__, fuzz, n=10000, out="fuzz-decks", what="decks",
                        columns=(("read and solved", "read"),))

if __name__ == "__main__":
    sys.exit(main())
