"""Sparse factorisations for the Newton solve: CHOLMOD where scikit-sparse is installed (symbolic
analysis once per sparsity pattern, numeric refactorisation each iteration), SuperLU otherwise.

CHOLMOD factorises the symmetric part of K + alpha M, which equals the tangent at equilibrium
(the skew part of the consistent tangent is proportional to the residual, and to applied nodal
moments); when the matrix is not positive definite (past a limit point, a negative-stiffness
direction) the LU of the full non-symmetric matrix is used for that iteration.
"""

from __future__ import annotations

import warnings

import scipy.sparse as sp
import scipy.sparse.linalg as spla

try:  # optional: pip install scikit-sparse (needs SuiteSparse headers, Debian libsuitesparse-dev)
    from sksparse import cholmod as _cholmod
except ImportError:  # pragma: no cover - depends on the machine
    _cholmod = None

HAVE_CHOLMOD = _cholmod is not None


class CholmodCache:
    """The symbolic analysis of one sparsity pattern, reused by every refactorisation."""

    def __init__(self):
        self.factor_object = None
        self.nnz = -1

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
                if self.factor_object is None or A.nnz != self.nnz:
                    self.factor_object = _cholmod.analyze(A, mode="simplicial")
                    self.nnz = A.nnz
                self.factor_object.cholesky_inplace(A)
                return self.factor_object
            except _cholmod.CholmodNotPositiveDefiniteError:
                self.factor_object = None
                return None


def superlu(A: sp.csc_matrix):
    """SuperLU with the options that suit structural matrices (raises RuntimeError if singular)."""
    return spla.splu(A, permc_spec="COLAMD", options={"SymmetricMode": True})
