"""The results store: a run killed midway and resumed reaches the uninterrupted run's answer exactly,
within one iteration budget; a finished run read back gives the same numbers."""

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
    up.update(initial, cfgs, data, variables, mass_target=target, store=store, progress=lambda row: time.sleep(1.0))
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
    fresh = up.update(initial, cfgs, data, variables, mass_target=target)
    # The resumed optimiser is answered from the store with the killed run's own bytes up to where it
    # stopped, then computes on from its exact warm starts: the trajectory is the uninterrupted one,
    # so the answer is equal, not merely close, and the evaluations count against one budget.
    np.testing.assert_array_equal(resumed.x, fresh.x)
    assert resumed.starts[0]["evaluations"] == fresh.starts[0]["evaluations"]
    assert [h["x"] for h in resumed.history] == [h["x"] for h in fresh.history]
    assert len(resumed.history) > done_before
    np.testing.assert_allclose(resumed.x, truth, rtol=3e-3)  # the identifiability floor of this problem
    assert resumed.final.objective < 1e-9
    # A third call finds the run finished and returns its answer without optimising, evaluated from
    # where the run evaluated it: the same residuals, Jacobian and uncertainties.
    again = up.update(initial, cfgs, data, variables, mass_target=target, store=store)
    assert again.starts[0]["evaluations"] == 0
    np.testing.assert_array_equal(again.x, resumed.x)
    np.testing.assert_array_equal(again.final.jacobian, resumed.final.jacobian)
    np.testing.assert_array_equal(again.identifiability["std_normalised"], resumed.identifiability["std_normalised"])
    store.close()
    with sqlite3.connect(path) as db:
        assert db.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


def test_the_store_is_held_by_one_process_at_a_time(tmp_path):
    from flexgvt.updating.store import StoreLockedError
    path = tmp_path / "run.sqlite"
    script = f"import sys, time; from flexgvt import updating as up; s = up.ResultsStore({str(path)!r}); " \
             "print('open', flush=True); time.sleep(60)"
    holder = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "open"
        try:
            up.ResultsStore(path)
        except StoreLockedError as exc:
            assert f"flexgvt process {holder.pid}" in str(exc) and str(path) in str(exc)
        else:
            raise AssertionError("a second process opened a store in use")
    finally:
        holder.kill()
        holder.wait()
    with up.ResultsStore(path):  # the killed holder's lock went with it
        pass


def test_a_record_made_with_other_data_is_not_replayed(tmp_path):
    """Data within the store's matching tolerance (1e-6) but not bit-identical: the run is found,
    but its recorded evaluations (computed from the other data) are dropped, not replayed."""
    from test_update import _strip_problem

    class Stop(Exception):
        pass

    def stop(row):
        if row["iteration"] >= 2:
            raise Stop

    case, initial, cfgs, variables, data, target, truth = _strip_problem(
        n_elements=12, names=("unloaded", "self_weight"), attributes=("E", "rho"))
    store = up.ResultsStore(tmp_path / "run.sqlite")
    try:
        up.update(initial, cfgs, data, variables, mass_target=target, store=store, progress=stop)
    except Stop:  # an interruption
        pass
    nudged = [up.Measured(m.configuration, m.frequencies_hz * (1 + 1e-9)) for m in data]
    resumed = up.update(initial, cfgs, nudged, variables, mass_target=target, store=store)
    fresh = up.update(initial, cfgs, nudged, variables, mass_target=target)
    assert not resumed.starts[0]["resumed"]
    np.testing.assert_array_equal(resumed.x, fresh.x)
    store.close()
