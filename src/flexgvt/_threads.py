"""Thread policy helpers shared by the numerical layers (fem, ema, updating): the bottom of the
import graph, next to errors.py, so that no method layer reaches into another for them.

BLAS' thread count is a process-wide setting. The solvers hold it at one thread while any of them
runs, through one reference-counted, locked hold: the first solve to enter sets the limit, the
last to leave restores the count found on entry, so two threads solving side by side cannot leave
the process at one thread (the race of a save-and-restore per call: A saves N and sets 1, B saves
1, A restores N while B runs, B restores 1). numba's thread count (numba.set_num_threads) is
thread-local and needs no such care.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from threadpoolctl import ThreadpoolController


@functools.cache
def _blas_controller() -> ThreadpoolController:
    return ThreadpoolController()  # finds the loaded BLAS libraries once (about 2 ms)


class _BlasHold:
    """The process' one BLAS limit, held while any holder is inside (see the module docstring)."""

    def __init__(self):
        self._lock = threading.Lock()
        self._holders = 0
        self._limiter = None
        self._threads = 1

    def enter(self, threads: int) -> None:
        with self._lock:
            if self._holders == 0:
                self._limiter = _blas_controller().limit(limits=threads, user_api="blas")
                self._threads = threads
            self._holders += 1

    def leave(self) -> None:
        with self._lock:
            self._holders -= 1
            if self._holders == 0:
                self._limiter.restore_original_limits()
                self._limiter = None

    @property
    def threads(self) -> int | None:
        """The held limit, or None when nothing holds one."""
        with self._lock:
            return self._threads if self._holders else None


_HOLD = _BlasHold()


@contextmanager
def blas_threads(threads: int = 1) -> Iterator[None]:
    """Hold BLAS at ``threads`` threads for the block (process-wide; restored when the last holder in
    any thread leaves). Entry points (the command line, a project run, a dask worker) take it once
    around their work; the solvers take it too (serial_blas), so nested holds cost a counter.
    A block entered while another thread holds a different limit keeps that one (one process, one
    BLAS setting)."""
    _HOLD.enter(int(threads))
    try:
        yield
    finally:
        _HOLD.leave()


def serial_blas(function):
    """Run ``function`` with BLAS on one thread (blas_threads(1) around the call).

    The beam kernel's OpenMP threads and OpenBLAS' threads both spin-wait for work; interleaved on
    a few cores they starve each other: a 60,000-entry vector norm right after a kernel call was
    measured at 2.5 ms instead of 0.02 ms. The solvers' own BLAS work (vector operations, ARPACK's
    small dense products) gains nothing from threads.
    """
    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        with blas_threads(1):
            return function(*args, **kwargs)
    return wrapper
