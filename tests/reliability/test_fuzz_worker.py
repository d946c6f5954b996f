"""The fuzzers' worker (bench/fuzzlib.py): a case that computes past its budget is a hang by its own
CPU time (a loaded machine's slow wall clock is not), one that waits without computing is a hang by
the wall clock, a dead worker is a crash, and a fresh worker's imports are not the case's."""

import importlib.util
import os
import sys
import time
from pathlib import Path

import pytest

BENCH = Path(__file__).parents[2] / "bench" / "fuzzlib.py"


@pytest.fixture(scope="module")
def fuzzlib():
    sys.path.insert(0, str(BENCH.parent))  # the spawned worker imports fuzzlib by name
    spec = importlib.util.spec_from_file_location("fuzzlib", BENCH)
    module = importlib.util.module_from_spec(spec)
    sys.modules["fuzzlib"] = module
    spec.loader.exec_module(module)
    return module


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="CPU time needs /proc (Linux)")
def test_cpu_time_decides_a_computing_hang_and_the_wall_clock_a_waiting_one(fuzzlib):
    with fuzzlib.Worker(timeout=0.5, memory_bytes=None, wall_factor=400.0) as worker:
        assert worker.run(len, "abcd")["outcome"] == "4"
        spin = worker.run(sum, range(10**12))  # half a CPU second, however long a loaded machine takes
        assert spin["outcome"] == "hang" and "0.5 s of CPU time" in spin["message"]
        assert worker.run(len, "ab")["outcome"] == "2"  # restarted after the kill
    with fuzzlib.Worker(timeout=0.2, memory_bytes=None, wall_factor=10.0) as worker:
        wait = worker.run(time.sleep, 60.0)
        assert wait["outcome"] == "hang" and "2 s (waiting, not computing)" in wait["message"]
        crash = worker.run(os._exit, 3)
        assert crash["outcome"] == "crash" and "exit code 3" in crash["message"]


def test_cpu_seconds_reads_this_process(fuzzlib):
    if not Path("/proc/self/stat").exists():
        assert fuzzlib.cpu_seconds(os.getpid()) is None
        return
    before = fuzzlib.cpu_seconds(os.getpid())
    sum(range(3 * 10**6))
    assert fuzzlib.cpu_seconds(os.getpid()) >= before > 0
