"""Mutated real decks (fields changed, lines dropped, files truncated, references broken, random
bytes): read_bdf either reads them or raises a flexgvt error (FlexGVTError) naming the file, never a
foreign exception (seeded; a few seconds)."""

import warnings
from pathlib import Path

import numpy as np

import flexgvt as fg
from flexgvt.errors import FlexGVTError

DATA = Path(__file__).parents[1] / "data" / "bdf"
SOURCES = [DATA / "pynastran" / "pt145.bdf", DATA / "all_cards.bdf", DATA / "rods.bdf",
           DATA / "pynastran" / "sdof_crod.bdf", DATA / "pynastran" / "euler_column_linear_buckling.bdf",
           DATA / "pynastran" / "ha144" / "ha144ds.bdf", DATA / "pynastran" / "strut_wing" / "buckled.bdf"]
BAH = DATA / "pynastran" / "bah_plane" / "structure_bah.inc"
VALUES = ["0.", "-1.", "1.e30", "nan", "abc", "", "99999", "1", "-7", "1.5", "YES", "+", "*"]


def bulk_lines(text: str) -> list[int]:
    lines = text.split("\n")
    start = next((i for i, ln in enumerate(lines) if ln.upper().startswith("BEGIN BULK")), -1) + 1
    return [i for i in range(start, len(lines)) if lines[i] and lines[i][0] not in "$"]


def mutate(text: str, rng, kind: int) -> str:
    lines = text.split("\n")
    bulk = bulk_lines(text)
    k = int(rng.choice(bulk))
    if kind == 0:  # one field replaced (free or fixed format)
        ln = lines[k]
        if "," in ln:
            fields = ln.split(",")
            j = int(rng.integers(1, len(fields))) if len(fields) > 1 else 0
            fields[j] = str(rng.choice(VALUES))
            lines[k] = ",".join(fields)
        else:
            j = int(rng.integers(1, 9))
            lines[k] = (ln.ljust(72)[:8 * j] + f"{rng.choice(VALUES):<8}"[:8] + ln.ljust(72)[8 * j + 8:]).rstrip()
    elif kind == 1:  # a card line dropped (missing references, broken continuations)
        del lines[k]
    elif kind == 2:  # truncated
        return text[: int(rng.integers(1, len(text)))]
    elif kind == 3:  # random printable bytes
        b = list(text)
        for _ in range(6):
            b[int(rng.integers(0, len(b)))] = chr(int(rng.integers(32, 127)))
        return "".join(b)
    else:  # an id changed: a reference to nothing, or a duplicate
        ln = lines[k]
        sep = "," if "," in ln else None
        fields = ln.split(sep) if sep else [ln[i:i + 8] for i in range(0, len(ln), 8)]
        if len(fields) > 2:
            fields[2] = str(int(rng.integers(1, 40))).ljust(0 if sep else 8)
        lines[k] = (sep or "").join(fields)
    return "\n".join(lines)


def fuzz(sources: list[Path], cases: int, tmp_path: Path, seed: int) -> dict:
    """Read ``cases`` mutations of the ``sources`` decks (in turn, unsupported cards as warnings and
    errors alternately); every failure must be a FlexGVTError naming the file. Returns the counts
    of decks read and refused."""
    rng = np.random.default_rng(seed)
    outcomes = {"read": 0, "error": 0}
    for n in range(cases):
        src = sources[n % len(sources)]
        path = tmp_path / f"fuzz{n}{src.suffix}"
        path.write_text(mutate(src.read_text(), rng, n % 5))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fg.io.read_bdf(path, unsupported=("warn", "error")[(n // len(sources)) % 2])
            outcomes["read"] += 1
        except FlexGVTError as exc:
            assert path.name in str(exc), f"{type(exc).__name__} without the file name: {exc}"
            outcomes["error"] += 1
        except Exception as exc:  # pragma: no cover - the failure report
            raise AssertionError(f"fuzz case {n} ({src.name}, kind {n % 5}) raised {type(exc).__name__}: {exc}\n"
                                 f"deck kept at {path}") from exc
    return outcomes


def test_mutated_real_decks_raise_only_flexgvt_errors(tmp_path):
    (tmp_path / "aero_bah.inc").write_text("")
    outcomes = fuzz(SOURCES, 210, tmp_path, seed=18)
    assert outcomes["error"] > 20 and outcomes["read"] > 10
