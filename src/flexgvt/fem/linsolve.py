"""Sparse factorisations for the Newton solve and the shift-invert eigensolver: a symmetric LDL^T
with the symbolic analysis done once per sparsity pattern and a numeric refactorisation each
iteration, SuperLU where no such backend is installed.

Backends (``BACKENDS``, the first is the default): MKL PARDISO (pypardiso and the mkl wheel, a default
dependency on x86-64: Bunch-Kaufman pivoting inside supernodes, METIS ordering) and CHOLMOD
(scikit-sparse, optional: needs SuiteSparse headers; simplicial LDL^T without pivoting). Either
factorises the symmetric part of K + alpha M, which equals the tangent at equilibrium (the skew
part of the consistent tangent is proportional to the residual, and to applied nodal moments),
indefinite matrices included; when a pivot is tiny (a singular or badly indefinite matrix: CHOLMOD's
|d_i| below 1e-12 |a_ii|, PARDISO's perturbed pivots) the LU of the full non-symmetric matrix is used
for that iteration. docs/benchmarks.md (scale) has the measurements behind the order.
"""

from __future__ import annotations

import warnings

import numba
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolverError

try:  # optional: pip install scikit-sparse (needs SuiteSparse headers, Debian libsuitesparse-dev)
    from sksparse import cholmod as _cholmod
except ImportError:  # pragma: no cover - depends on the machine
    _cholmod = None

from .._threads import serial_blas  # noqa: F401  (re-exported: fem.linsolve.serial_blas)
from ._pardiso import HAVE_PARDISO, PardisoLDL
from .assembly import scatter_add_symmetric

HAVE_CHOLMOD = _cholmod is not None  # scikit-sparse's CHOLMOD
BACKENDS = tuple(name for name, ok in (("pardiso", HAVE_PARDISO), ("cholmod", HAVE_CHOLMOD)) if ok)
HAVE_FAST = bool(BACKENDS)  # a symmetric factorisation with a reusable analysis (else SuperLU only)
_PIVOT_TOLERANCE = 1e-12  # smallest accepted |pivot| of LDL^T relative to its diagonal entry


@numba.njit(cache=True, nogil=True)
def _gather(data, kept, dropped, out):  # pragma: no cover - compiled
    """out = data[kept]; True if data[dropped] holds a non-zero (the pruned pattern must grow)."""
    for i in range(dropped.size):
        if data[dropped[i]] != 0.0:
            return True
    for i in range(kept.size):
        out[i] = data[kept[i]]
    return False


@numba.njit(cache=True)
def _prune(data, indptr, indices, keep):  # pragma: no cover - compiled
    """Pattern of the kept entries (and every diagonal one): pruned (indptr, indices, data), the
    kept and dropped positions in the full data, each diagonal entry's position in the pruned
    data (-1: not stored) and the updated keep mask."""
    n = indptr.size - 1
    nnz = indices.size
    keep = keep.copy()
    count = 0
    for c in range(n):
        for k in range(indptr[c], indptr[c + 1]):
            if indices[k] == c:
                keep[k] = True
            if keep[k]:
                count += 1
    p_indptr = np.zeros(n + 1, indptr.dtype)
    p_indices = np.empty(count, indices.dtype)
    p_data = np.empty(count)
    kept = np.empty(count, np.int64)
    dropped = np.empty(nnz - count, np.int64)
    diag = np.full(n, -1, np.int64)
    i = j = 0
    for c in range(n):
        for k in range(indptr[c], indptr[c + 1]):
            if keep[k]:
                if indices[k] == c:
                    diag[c] = i
                p_indices[i] = indices[k]
                p_data[i] = data[k]
                kept[i] = k
                i += 1
            else:
                dropped[j] = k
                j += 1
        p_indptr[c + 1] = i
    return p_indptr, p_indices, p_data, kept, dropped, diag, keep


@numba.njit(cache=True, nogil=True)
def _compose(target, where):  # pragma: no cover - compiled
    """where[target] where target >= 0, else -1."""
    out = np.empty_like(target)
    for k in range(target.size):
        out[k] = where[target[k]] if target[k] >= 0 else -1
    return out


@numba.njit(cache=True, nogil=True)
def _pivots_ok(D, data, diag_idx, tolerance):  # pragma: no cover - compiled
    """Every |D[i]| above tolerance times |A_ii| (false for NaN)."""
    for i in range(D.size):
        k = diag_idx[i]
        a = abs(data[k]) if k >= 0 else 0.0
        if not abs(D[i]) > tolerance * a:
            return False
    return True


def _same_memory(a: np.ndarray, b: np.ndarray) -> bool:
    return a is b or (a.size == b.size and a.__array_interface__["data"][0] == b.__array_interface__["data"][0])


class CholmodCache:
    """The symbolic analysis of one sparsity pattern, reused by every refactorisation (the name is
    historical: the backend is ``backend``, by default the first of ``BACKENDS``).

    Entries that are exactly zero are left out of the analysed pattern while they stay zero: the
    tangent of a structure loaded in its plane of symmetry (a straight wing under self-weight)
    decouples the in-plane from the out-of-plane motions, half of the element pattern is zero
    and its Cholesky factor half as large. An entry that turns non-zero triggers one new analysis,
    of the whole pattern: under a general load the couplings turn on over the first iterations one
    group after the other, and analysing each grown pattern cost the 0.1 m wingbox four analyses
    at -1 g (each about the time of a factorisation) where one suffices.
    """

    def __init__(self, backend: str | None = None):
        if backend is None:
            backend = BACKENDS[0] if BACKENDS else None
        elif backend not in BACKENDS:
            raise SolverError(f"sparse factorisation backend '{backend}' is not installed (installed: {BACKENDS}; "
                             "pardiso: pip install pypardiso; cholmod: pip install scikit-sparse)")
        self.backend = backend
        self.factor_object = None
        self._full = None  # (shape, indptr, indices) of the full pattern the kept set refers to
        self._keep = None  # bool (nnz,): entries of the full pattern in the analysed one
        self._kept_idx = self._dropped_idx = None
        self._pruned = None  # csc matrix on the analysed pattern, its data overwritten each call
        self._diag_idx = None  # position of each diagonal entry in the pruned data
        self._analyses = 0
        self._blocks_key = self._block_targets = None  # element entries -> pruned data (factor_blocks)
        self._mass_key = self._mass_kept = None  # the mass data on the kept entries

    def _same_pattern(self, A: sp.csc_matrix) -> bool:
        if self._full is None:
            return False
        shape, indptr, indices = self._full
        if A.shape != shape or A.nnz != len(indices):
            return False
        # Matrices assembled on one Pattern share its index arrays (as views): no comparison needed.
        if _same_memory(A.indices, indices) and _same_memory(A.indptr, indptr):
            return True
        return np.array_equal(A.indptr, indptr) and np.array_equal(A.indices, indices)

    def _analyse(self, A: sp.csc_matrix, keep: np.ndarray):
        indptr, indices, data, self._kept_idx, self._dropped_idx, self._diag_idx, self._keep = _prune(
            A.data, A.indptr, A.indices, keep)
        self._pruned = sp.csc_matrix((data, indices, indptr), shape=A.shape)
        self._full = (A.shape, A.indptr, A.indices)
        if self.backend == "cholmod":
            self.factor_object = _cholmod.analyze(self._pruned, mode="simplicial")
        elif np.all(self._diag_idx >= 0):
            try:
                self.factor_object = PardisoLDL(indptr, indices, A.shape[0])
            except SolverError:  # the caller takes SuperLU
                self.factor_object = _NO_FACTOR
        else:  # PARDISO needs every diagonal entry stored; a missing one is a zero pivot anyway
            self.factor_object = _NO_FACTOR
        self._analyses += 1

    def factor_blocks(self, pattern, blocks: list[np.ndarray], mass_data: np.ndarray, alpha: float):
        """factor() of the symmetric part of element matrices ``blocks`` assembled on ``pattern``
        (an assembly.Pattern) plus alpha times a matrix with data ``mass_data`` on it, scattered
        straight into the analysed entries while they hold every non-zero (no full matrix)."""
        if self.backend is None:
            return None
        full = self._full
        if (self.factor_object is not None and full[0] == (pattern.n, pattern.n)
                and _same_memory(full[1], pattern.indptr) and _same_memory(full[2], pattern.indices)):
            if self._blocks_key != (id(pattern), self._analyses):
                where = np.full(pattern.nnz, -2, np.int64)
                where[self._kept_idx] = np.arange(len(self._kept_idx))
                self._block_targets = [_compose(t, where) for t in pattern._targets]
                self._blocks_key = (id(pattern), self._analyses)
            if self._mass_key is None or self._mass_key[0] is not mass_data or self._mass_key[1] != self._analyses:
                dropped = mass_data[self._dropped_idx]
                self._mass_kept = mass_data[self._kept_idx] if not np.any(dropped) else None
                self._mass_key = (mass_data, self._analyses)
            if self._mass_kept is not None:
                data = self._pruned.data
                np.multiply(self._mass_kept, alpha, out=data)
                grow = False
                for target, v in zip(self._block_targets, blocks):
                    if v.size:
                        grow |= scatter_add_symmetric(data, target, np.ascontiguousarray(v, dtype=float))
                if not grow:
                    return self._refactor()
        return self.factor(pattern.matrix(pattern.add_symmetric(alpha * mass_data, blocks)))

    def _refactor(self):
        """Numeric factorisation of the pruned matrix as it stands; None if a pivot is tiny."""
        if self.backend != "cholmod":
            return self.factor_object if self.factor_object.refactor(self._pruned.data) else None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                self.factor_object.cholesky_inplace(self._pruned)
            except _cholmod.CholmodNotPositiveDefiniteError:
                return None
        # The simplicial factor is LDL^T, computed without pivoting, for indefinite matrices too (the
        # symmetric part of a tangent at a stretched predicted state often is): accepted unless a
        # pivot is tiny against its diagonal entry, where unpivoted elimination loses accuracy.
        if not _pivots_ok(self.factor_object.D(), self._pruned.data, self._diag_idx, _PIVOT_TOLERANCE):
            return None
        return self.factor_object

    def factor(self, A: sp.csc_matrix):
        """Numeric LDL^T of symmetric A (only its lower triangle is read; in place, same symbolic
        analysis), or None if a pivot is tiny (a singular or badly indefinite matrix: use a pivoted
        LU). Pass both triangles where they are at hand: the simplicial factorisation of a
        lower-only matrix is measured 1.8x slower (it transposes).

        The returned object (``solve_A(b)``) is only valid until the next call.
        """
        if self.backend is None:
            return None
        if not (sp.isspmatrix_csc(A) and A.has_sorted_indices):
            A = sp.csc_matrix(A)
            A.sort_indices()
        if self.factor_object is None or not self._same_pattern(A):
            self._analyse(A, A.data != 0)
        elif _gather(A.data, self._kept_idx, self._dropped_idx, self._pruned.data):
            self._analyse(A, np.ones_like(self._keep))
        return self._refactor()


class _NoFactor:
    """An analysis that cannot factorise (a diagonal entry missing from the pattern: a zero pivot; or
    PARDISO's analysis failed): every refactorisation fails, so the caller takes SuperLU."""

    @staticmethod
    def refactor(data) -> bool:
        return False


_NO_FACTOR = _NoFactor()


def superlu(A: sp.csc_matrix):
    """SuperLU with the options that suit structural matrices (raises RuntimeError if singular)."""
    return spla.splu(A, permc_spec="COLAMD", options={"SymmetricMode": True})


def inertia(A: sp.spmatrix, cache: CholmodCache | None = None) -> tuple[int, int] | None:
    """(positive, negative) eigenvalue counts of symmetric A (its lower triangle is read) from the
    pivots of PARDISO's Bunch-Kaufman LDL^T (Sylvester's law of inertia; MKL's iparm(22)/(23)); None
    where PARDISO is not installed or had to perturb a pivot (A singular or nearly so: the count is
    then not the matrix's). cache: a PARDISO analysis of A's pattern to reuse (else a new one)."""
    if not HAVE_PARDISO:
        return None
    if cache is None or cache.backend != "pardiso":
        cache = CholmodCache("pardiso")
    factor = cache.factor(sp.csc_matrix(A))
    if factor is None:
        return None
    positive, negative = factor.inertia
    return (positive, negative) if positive + negative == A.shape[0] else None
