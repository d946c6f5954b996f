"""MKL PARDISO (from the `mkl` wheel, located through pypardiso) as a symmetric LDL^T with Bunch-Kaufman
pivoting inside supernodes: one symbolic analysis (METIS ordering) per sparsity pattern, numeric
refactorisation on new values, solves with one or many right-hand sides.

Called through ctypes with zero-based indices on the upper triangle in CSR, which is the lower
triangle of a CSC matrix read as rows: the CSC data of the analysed pattern is gathered through one
index array, no conversion per call. A factorisation that had to perturb a pivot (a singular or badly
indefinite matrix) is reported as failed, as the CHOLMOD path's tiny-pivot rule does, so the caller
takes SuperLU's pivoted LU.
"""

from __future__ import annotations

import ctypes
import weakref

import numpy as np

from ..errors import SolverError

try:  # a default dependency on x86-64 (MKL wheels); elsewhere the solver falls back to SuperLU
    import pypardiso as _pypardiso
except ImportError:  # pragma: no cover - depends on the machine
    _pypardiso = None

_MTYPE = -2  # real symmetric indefinite
_PERTURBATION = 12  # pivots below 1e-12 of the matrix norm are perturbed (iparm[9]); counted -> refused


def _library():
    """MKL's pardiso entry point with its argument types, or None (pypardiso or mkl_rt missing)."""
    if _pypardiso is None:
        return None
    try:
        return _pypardiso.PyPardisoSolver()._mkl_pardiso
    except (ImportError, OSError):  # pragma: no cover - a broken MKL install
        return None


_PARDISO = _library()
HAVE_PARDISO = _PARDISO is not None

_I32 = ctypes.POINTER(ctypes.c_int32)
_F64 = ctypes.POINTER(ctypes.c_double)
_I64 = ctypes.POINTER(ctypes.c_int64)


def _call(handle, iparm, phase, n, data, indptr, indices, b=None, x=None, nrhs=1) -> int:
    error = ctypes.c_int32(0)
    one = ctypes.c_int32(1)
    dummy = np.zeros(1)
    _PARDISO(handle.ctypes.data_as(_I64), ctypes.byref(one), ctypes.byref(one), ctypes.byref(ctypes.c_int32(_MTYPE)),
             ctypes.byref(ctypes.c_int32(phase)), ctypes.byref(ctypes.c_int32(n)), data.ctypes.data_as(_F64),
             indptr.ctypes.data_as(_I32), indices.ctypes.data_as(_I32), np.zeros(1, np.int32).ctypes.data_as(_I32),
             ctypes.byref(ctypes.c_int32(nrhs)), iparm.ctypes.data_as(_I32), ctypes.byref(ctypes.c_int32(0)),
             (dummy if b is None else b).ctypes.data_as(_F64), (dummy if x is None else x).ctypes.data_as(_F64),
             ctypes.byref(error))
    return error.value


def _release(handle, iparm, n, data, indptr, indices):
    _call(handle, iparm, -1, n, data, indptr, indices)


class PardisoLDL:
    """The analysed pattern of one symmetric CSC matrix with both triangles stored (sorted indices,
    every diagonal entry present); ``refactor(data)`` with that matrix's data, then ``solve_A``."""

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n: int):
        if not HAVE_PARDISO:
            raise SolverError("MKL PARDISO is not available: pip install pypardiso (x86-64), or use the default "
                              "backend (fem.linsolve.BACKENDS)")
        cols = np.repeat(np.arange(n), np.diff(indptr))
        lower = indices >= cols  # CSC lower triangle = CSR upper triangle, row by row
        self._take = np.flatnonzero(lower)
        self.n = n
        self._indptr = np.zeros(n + 1, np.int32)
        np.cumsum(np.bincount(cols[lower], minlength=n), out=self._indptr[1:])
        self._indices = np.ascontiguousarray(indices[lower], dtype=np.int32)
        self._data = np.zeros(len(self._take))
        self._handle = np.zeros(64, np.int64)
        iparm = np.zeros(64, np.int32)
        iparm[0] = 1  # these settings, not the defaults
        iparm[1] = 2  # nested dissection (METIS)
        iparm[7] = 0  # no iterative refinement (it would hide perturbed pivots)
        iparm[9] = _PERTURBATION
        iparm[10] = 0  # no scaling, no matching: the analysis depends on the pattern only
        iparm[12] = 0
        iparm[17] = -1  # report the factor's non-zeros
        iparm[20] = 1  # Bunch-Kaufman 1x1 and 2x2 pivots
        iparm[34] = 1  # zero-based indices
        self._iparm = iparm
        error = _call(self._handle, iparm, 11, n, self._data, self._indptr, self._indices)
        self._finalizer = weakref.finalize(self, _release, self._handle, iparm, n, self._data, self._indptr,
                                           self._indices)
        if error:
            raise SolverError(f"PARDISO's analysis of a {n} x {n} matrix failed (MKL error {error}); "
                              "StaticSettings(cholmod=False) or solve_modes(..., cholmod=False) use SuperLU instead")
        self.ok = False

    @property
    def factor_nnz(self) -> int:
        return int(self._iparm[17])

    @property
    def inertia(self) -> tuple[int, int]:
        """(positive, negative) pivots of the last factorisation (the matrix's inertia when none was perturbed)."""
        return int(self._iparm[21]), int(self._iparm[22])

    def refactor(self, data: np.ndarray) -> bool:
        """Numeric factorisation of the matrix with CSC data ``data`` on the analysed pattern; False
        if it failed or had to perturb a pivot (singular or nearly so)."""
        np.take(data, self._take, out=self._data)
        error = _call(self._handle, self._iparm, 22, self.n, self._data, self._indptr, self._indices)
        self.ok = error == 0 and self._iparm[13] == 0 and np.all(np.isfinite(self._data))
        return bool(self.ok)

    def solve_A(self, b: np.ndarray) -> np.ndarray:
        """A^-1 b for b of shape (n,) or (n, k)."""
        b = np.asarray(b, dtype=float)
        rhs = np.asfortranarray(b)
        x = np.empty_like(rhs, order="F")
        nrhs = 1 if b.ndim == 1 else b.shape[1]
        error = _call(self._handle, self._iparm, 33, self.n, self._data, self._indptr, self._indices, rhs, x, nrhs)
        if error:
            raise SolverError(f"PARDISO's solve with a {self.n} x {self.n} factor failed (MKL error {error}); "
                              "StaticSettings(cholmod=False) or solve_modes(..., cholmod=False) use SuperLU instead")
        return np.ascontiguousarray(x)
