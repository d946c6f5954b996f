"""Thread policy helpers shared by the numerical layers (fem, ema, updating): the bottom of the
import graph, next to errors.py, so that no method layer reaches into another for them."""

from __future__ import annotations

import functools

from threadpoolctl import ThreadpoolController


@functools.cache
def _blas_controller() -> ThreadpoolController:
    return ThreadpoolController()  # finds the loaded BLAS libraries once (about 2 ms)


def serial_blas(function):
    """Run ``function`` with BLAS on one thread (restored afterwards).

    The beam kernel's OpenMP threads and OpenBLAS' threads both spin-wait for work; interleaved on
    a few cores they starve each other: a 60,000-entry vector norm right after a kernel call was
    measured at 2.5 ms instead of 0.02 ms. The solvers' own BLAS work (vector operations, ARPACK's
    small dense products) gains nothing from threads.
    """
    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        with _blas_controller().limit(limits=1, user_api="blas"):
            return function(*args, **kwargs)
    return wrapper
