"""A seeded sample of the UFF fuzzer (bench/fuzz_uff.py): mutated UFF files (real files and flexgvt's
own output) read, identified and used raise only FlexGVTErrors, and none hangs (each case runs in a
worker process with a timeout). On commit 4da6594 this sample found 4 foreign exceptions at 3 sites
(ValueError in read_uff and _modes, LinAlgError in PolyMAX)."""

import importlib.util
import sys
from pathlib import Path

BENCH = Path(__file__).parents[2] / "bench" / "fuzz_uff.py"


def _fuzz_uff():
    spec = importlib.util.spec_from_file_location("fuzz_uff", BENCH)
    module = importlib.util.module_from_spec(spec)
    sys.modules["fuzz_uff"] = module  # the worker process unpickles run_case from it
    spec.loader.exec_module(module)
    return module


def test_mutated_uff_files_give_no_foreign_exception_and_no_hang():
    tally = _fuzz_uff().fuzz(250, seed=4, timeout=10.0, out=None, log=None)
    report = "; ".join(f"{g['count']} x {key}: {g['message'][:100]} (first: case {g['cases'][0]})"
                       for key, g in sorted(tally.groups.items()))
    assert tally.failures == 0, f"{tally.counts}: {report}"
    assert tally.counts.get("identified", 0) > 20 and tally.counts.get("clear", 0) > 60, tally.counts
