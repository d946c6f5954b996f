"""A seeded sample of the project fuzzer (bench/fuzz_project.py): mutated `flexgvt init --data`
projects through load_project and the first steps raise only FlexGVTErrors, and none hangs (each
case runs in a worker process with a timeout). On commit 4da6594 this sample found 6 foreign
exceptions at 4 sites (UnicodeDecodeError and JSONDecodeError scoring the reference after the
prediction, ValueError in read_uff and in identify_block)."""

import importlib.util
import sys
from pathlib import Path


BENCH = Path(__file__).parents[2] / "bench"


def _fuzz_project():
    sys.path.insert(0, str(BENCH))  # fuzz_project imports fuzzlib and fuzz_uff beside it
    spec = importlib.util.spec_from_file_location("fuzz_project", BENCH / "fuzz_project.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["fuzz_project"] = module  # the worker process unpickles run_case from it
    spec.loader.exec_module(module)
    return module


def test_mutated_projects_give_no_foreign_exception_and_no_hang(base):
    tally = _fuzz_project().fuzz(60, seed=1, timeout=20.0, out=None, base=base, log=None)
    report = "; ".join(f"{g['count']} x {key}: {g['message'][:100]} (first: case {g['cases'][0]})"
                       for key, g in sorted(tally.groups.items()))
    assert tally.failures == 0, f"{tally.counts}: {report}"
    assert tally.counts.get("loaded", 0) >= 4 and tally.counts.get("clear", 0) > 30, tally.counts
