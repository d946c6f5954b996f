"""Sparse factorisations for the Newton solve: CHOLMOD where scikit-sparse is installed (symbolic
analysis once per sparsity pattern, numeric refactorisation each iteration), SuperLU otherwise.

CHOLMOD factorises the symmetric part of K + alpha M, which equals the tangent at equilibrium
(the skew part of the consistent tangent is proportional to the residual, and to applied nodal
moments); when the matrix is not positive definite (past a limit point, a negative-stiffness
direction) the LU of the full non-symmetric matrix is used for that iteration.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

try:  # optional: pip install scikit-sparse (needs SuiteSparse headers, Debian libsuitesparse-dev)
    from sksparse import cholmod as _cholmod
except ImportError:  # pragma: no cover - depends on the machine
    _cholmod = None

HAVE_CHOLMOD = _cholmod is not None


class CholmodCache:
    """The symbolic analysis of one sparsity pattern, reused by every refactorisation.

    Entries that are exactly zero are left out of the analysed pattern while they stay zero: the
    tangent of a structure loaded in its plane of symmetry (a straight wing under self-weight)
    decouples the in-plane from the out-of-plane motions, half of the element pattern is zero
    and its Cholesky factor half as large. An entry that turns non-zero triggers a new analysis
    of the grown pattern (a few times at most: the kept set only grows).
    """

    def __init__(self):
        self.factor_object = None
        self._full = None  # (shape, indptr, indices) of the full pattern the kept set refers to
        self._keep = None  # bool (nnz,): entries of the full pattern in the analysed one
        self._kept_idx = self._dropped_idx = None
        self._pruned = None  # csc matrix on the analysed pattern, its data overwritten each call

    def _same_pattern(self, A: sp.csc_matrix) -> bool:
        if self._full is None:
            return False
        shape, indptr, indices = self._full
        return (A.shape == shape and A.nnz == len(indices)
                and (A.indices is indices or (np.array_equal(A.indptr, indptr) and np.array_equal(A.indices, indices))))

    def _analyse(self, A: sp.csc_matrix, keep: np.ndarray):
        cols = np.repeat(np.arange(A.shape[1]), np.diff(A.indptr))
        keep = keep | (A.indices == cols)  # the diagonal always
        counts = np.bincount(cols[keep], minlength=A.shape[1])
        indptr = np.concatenate([[0], np.cumsum(counts)]).astype(A.indptr.dtype)
        self._pruned = sp.csc_matrix((A.data[keep], A.indices[keep], indptr), shape=A.shape)
        self._full = (A.shape, A.indptr, A.indices)
        self._keep = keep
        self._kept_idx = np.flatnonzero(keep)
        self._dropped_idx = np.flatnonzero(~keep)
        self.factor_object = _cholmod.analyze(self._pruned, mode="simplicial")

    def factor(self, A: sp.csc_matrix):
        """Numeric Cholesky of symmetric A (only its lower triangle is read; in place, same symbolic
        analysis), or None if not positive definite. Pass both triangles where they are at hand:
        the simplicial factorisation of a lower-only matrix is measured 1.8x slower (it transposes).

        The returned object is only valid until the next call.
        """
        if _cholmod is None:
            return None
        if not (sp.isspmatrix_csc(A) and A.has_sorted_indices):
            A = sp.csc_matrix(A)
            A.sort_indices()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                if self.factor_object is None or not self._same_pattern(A):
                    self._analyse(A, A.data != 0)
                elif np.any(A.data[self._dropped_idx] != 0):
                    self._analyse(A, self._keep | (A.data != 0))
                else:
                    np.take(A.data, self._kept_idx, out=self._pruned.data)
                self.factor_object.cholesky_inplace(self._pruned)
            except _cholmod.CholmodNotPositiveDefiniteError:
                return None
        # The simplicial factor is LDL^T, which CHOLMOD computes for indefinite matrices too (without
        # pivoting, so possibly unstable): only positive pivots are accepted.
        if not np.all(self.factor_object.D() > 0):
            return None
        return self.factor_object


def superlu(A: sp.csc_matrix):
    """SuperLU with the options that suit structural matrices (raises RuntimeError if singular)."""
    return spla.splu(A, permc_spec="COLAMD", options={"SymmetricMode": True})
