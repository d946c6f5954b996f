"""Two solves side by side in one process: the same results as one after the other, and the
process-wide BLAS thread limit left as it was (flexgvt._threads' reference-counted hold)."""

import threading

import numpy as np
from threadpoolctl import ThreadpoolController, threadpool_limits

import flexgvt as fg
from fem_builders import straight_beam
from flexgvt._threads import _BlasHold


def _blas_threads() -> set:
    return {lib.num_threads for lib in ThreadpoolController().select(user_api="blas").lib_controllers}


def _cantilever(n: int):
    model, ids = straight_beam(n)
    return model, fg.Configuration("self weight", fixed={int(ids[0]): "123456"}, gravity=1.0)


def _solve(model, config):
    state = fg.solve_static(model, config)
    return state.positions, fg.solve_modes(state, 6).frequencies_hz


def test_interleaved_holds_restore_the_limit_found_on_entry():
    """A enters, B enters, A leaves while B runs, B leaves: the original count comes back only then
    (a save-and-restore per call left the process at one thread in this order)."""
    with threadpool_limits(limits=2, user_api="blas"):
        hold = _BlasHold()
        hold.enter(1)
        hold.enter(1)
        assert _blas_threads() == {1}
        hold.leave()
        assert _blas_threads() == {1} and hold.threads == 1  # B still runs on one thread
        hold.leave()
        assert _blas_threads() == {2} and hold.threads is None


def test_two_threads_solving_side_by_side_match_serial_and_keep_the_blas_limit():
    jobs = [_cantilever(60), _cantilever(90)]
    serial = [_solve(*job) for job in jobs]
    with threadpool_limits(limits=2, user_api="blas"):
        for _ in range(3):  # a few rounds: the interleaving differs each time
            results, errors = [None, None], []

            def run(k):
                try:
                    results[k] = _solve(*jobs[k])
                except Exception as exc:  # noqa: BLE001 - reported below
                    errors.append(exc)

            threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            assert not errors, errors
            for (x, f), (xs, fs) in zip(results, serial):
                np.testing.assert_array_equal(x, xs)
                np.testing.assert_array_equal(f, fs)
            assert _blas_threads() == {2}


def test_blas_threads_holds_for_the_block_and_nests():
    with threadpool_limits(limits=2, user_api="blas"):
        with fg.blas_threads(1):
            assert _blas_threads() == {1}
            _solve(*_cantilever(20))  # the solvers' own hold nests inside
            assert _blas_threads() == {1}
        assert _blas_threads() == {2}
