"""The results store: a run killed midway and resumed reaches the same answer."""

import os
import signal
import sqlite3
import subprocess
import sys
import textwrap
import time

import numpy as np

from flexgvt import updating as up

SCRIPT = textwrap.dedent("""
    import sys, time
    sys.path.insert(0, {tests!r})
    from test_update import _strip_problem
    from flexgvt import updating as up
    case, initial, cfgs, variables, data, target, truth = _strip_problem(n_elements=30)
    store = up.ResultsStore({path!r})
    # A pause after each stored iterate stands for a long run (the kill must land midway).
    up.update(initial, cfgs, data, variables, mass_target=target, store=store, callback=lambda row: time.sleep(1.0))
""")


def _iterations(path) -> int:
    try:
        with sqlite3.connect(path, timeout=5) as db:
            return db.execute("SELECT COUNT(*) FROM iterations").fetchone()[0]
    except sqlite3.OperationalError:
        return 0


def test_a_run_killed_midway_resumes_to_the_same_answer(tmp_path):
    from test_update import _strip_problem
    path = str(tmp_path / "run.sqlite")
    here = os.path.dirname(__file__)
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT.format(tests=here, path=path)])
    try:
        deadline = time.time() + 120
        while _iterations(path) < 3 and proc.poll() is None and time.time() < deadline:
            time.sleep(0.02)
        assert proc.poll() is None, "the run ended before it could be interrupted"
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    finally:
        if proc.poll() is None:
            proc.kill()
    done_before = _iterations(path)
    assert done_before >= 3
    case, initial, cfgs, variables, data, target, truth = _strip_problem(n_elements=30)
    store = up.ResultsStore(path)
    resumed = up.update(initial, cfgs, data, variables, mass_target=target, store=store)
    assert resumed.starts[0]["resumed"]
    assert len(resumed.history) > done_before  # the stored iterates, then the resumed ones
    fresh = up.update(initial, cfgs, data, variables, mass_target=target)
    np.testing.assert_allclose(resumed.x, fresh.x, rtol=3e-3)  # the identifiability floor of this problem
    np.testing.assert_allclose(resumed.x, truth, rtol=3e-3)
    assert resumed.final.objective < 1e-9
    # A third call finds the run finished and returns its answer without optimising.
    again = up.update(initial, cfgs, data, variables, mass_target=target, store=store)
    assert again.starts[0]["evaluations"] == 0
    np.testing.assert_array_equal(again.x, resumed.x)
