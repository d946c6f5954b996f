"""A seeded sample of the deck fuzzer (bench/fuzz_decks.py): mutated Nastran decks read and solved
raise only FlexGVTErrors, and none hangs (each case runs in a worker process with a timeout)."""

import importlib.util
from pathlib import Path

BENCH = Path(__file__).parents[2] / "bench" / "fuzz_decks.py"


def _fuzz_decks():
    spec = importlib.util.spec_from_file_location("fuzz_decks", BENCH)
    module = importlib.util.module_from_spec(spec)
    import sys
    sys.modules["fuzz_decks"] = module  # the worker process unpickles run_case from it
    spec.loader.exec_module(module)
    return module


def test_mutated_decks_give_no_foreign_exception_and_no_hang():
    fd = _fuzz_decks()
    tally = fd.fuzz(150, seed=2026, timeout=10.0, out=None, sources=fd.SMALL_SOURCES, log=None)
    report = "; ".join(f"{g['count']} x {key}: {g['message'][:100]} (first: case {g['cases'][0]})"
                       for key, g in sorted(tally.groups.items()))
    assert tally.failures == 0, f"{tally.counts}: {report}"
    assert tally.counts.get("read", 0) > 10 and tally.counts.get("clear", 0) > 40, tally.counts
