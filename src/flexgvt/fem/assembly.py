"""Sparse assembly onto a fixed pattern: element blocks scattered into CSC data in one pass.

The pattern (which element entry lands in which stored entry of the global CSC matrix) is
computed once per system; every tangent, mass or damping matrix then shares its index arrays,
so sums such as K + alpha M and the symmetric part of K are elementwise operations on data.
"""

from __future__ import annotations

import numba
import numpy as np
import scipy.sparse as sp


@numba.njit(cache=True)
def _scatter_add(out, target, values):  # pragma: no cover - compiled
    for k in range(values.size):
        t = target[k]
        if t >= 0:
            out[t] += values[k]


@numba.njit(cache=True, nogil=True)
def scatter_add_symmetric(out, target, values):  # pragma: no cover - compiled
    """out[target] += the symmetric parts of element matrices values (n, d, d), entry by entry.
    target -1: a dropped (held) DOF; -2: an entry left out on purpose (a pruned pattern, see
    linsolve.CholmodCache.factor_blocks). True if one of the -2 entries gets a non-zero."""
    n, d = values.shape[0], values.shape[1]
    grow = False
    for e in range(n):
        base = e * d * d
        for a in range(d):
            for b in range(d):
                t = target[base + a * d + b]
                if t >= 0:
                    out[t] += 0.5 * (values[e, a, b] + values[e, b, a])
                elif t == -2 and values[e, a, b] + values[e, b, a] != 0.0:
                    grow = True
    return grow


@numba.njit(cache=True)
def _symmetric_part(K, M, mirror, alpha, out):  # pragma: no cover - compiled
    for k in range(out.size):
        out[k] = 0.5 * (K[k] + K[mirror[k]]) + alpha * M[k]


@numba.njit(cache=True)
def _block_entries(dofs, dof_map, rows, cols):  # pragma: no cover - compiled
    """Matrix row and column (dof_map of the DOFs) of every entry of the element blocks, row-major."""
    d = dofs.shape[1]
    k = 0
    for e in range(dofs.shape[0]):
        for a in range(d):
            for b in range(d):
                rows[k] = dof_map[dofs[e, a]]
                cols[k] = dof_map[dofs[e, b]]
                k += 1


@numba.njit(cache=True)
def _build_pattern(rows, cols, n):  # pragma: no cover - compiled
    """CSC pattern of the entries (rows[k], cols[k]) (negative: dropped) and the stored-entry index
    of each: a counting sort by column, then per column its distinct rows (marked, not sorted
    with their duplicates), sorted and numbered."""
    count = np.zeros(n + 1, np.int64)
    for k in range(rows.size):
        if rows[k] >= 0 and cols[k] >= 0:
            count[cols[k] + 1] += 1
    start = np.cumsum(count)
    fill = start[:-1].copy()
    order = np.empty(start[-1], np.int64)
    for k in range(rows.size):
        if rows[k] >= 0 and cols[k] >= 0:
            order[fill[cols[k]]] = k
            fill[cols[k]] += 1
    target = np.full(rows.size, -1, np.int64)
    indices = np.empty(start[-1], np.int32)
    indptr = np.zeros(n + 1, np.int32)
    mark = np.full(n, -1, np.int64)  # column in which a row was last seen
    pos = np.empty(n, np.int64)  # stored-entry index of a row in the current column
    nnz = 0
    for c in range(n):
        first = nnz
        for i in range(start[c], start[c + 1]):
            r = rows[order[i]]
            if mark[r] != c:
                mark[r] = c
                j = nnz  # insertion sort of the column's distinct rows (a few dozen)
                while j > first and indices[j - 1] > r:
                    indices[j] = indices[j - 1]
                    j -= 1
                indices[j] = r
                nnz += 1
        for j in range(first, nnz):
            pos[indices[j]] = j
        for i in range(start[c], start[c + 1]):
            target[order[i]] = pos[rows[order[i]]]
        indptr[c + 1] = nnz
    return target, indptr, indices[:nnz].copy()


class Pattern:
    """Sparse pattern of element blocks mapped to (reduced) DOFs.

    blocks: one (n_elements, n_dofs) array of global DOF numbers per element type; dof_map maps
    them to matrix rows (-1: dropped, e.g. fixed DOFs); n: matrix size.
    """

    def __init__(self, blocks: list[np.ndarray], dof_map: np.ndarray, n: int):
        sizes = [dofs.shape[0] * dofs.shape[1] ** 2 for dofs in blocks]
        rows = np.empty(sum(sizes), np.int64)
        cols = np.empty(sum(sizes), np.int64)
        dof_map = np.ascontiguousarray(dof_map, dtype=np.int64)
        start = 0
        for dofs, size in zip(blocks, sizes):
            if size:
                _block_entries(np.ascontiguousarray(dofs, dtype=np.int64), dof_map, rows[start:], cols[start:])
            start += size
        target, self.indptr, self.indices = _build_pattern(rows, cols, n)
        self._targets = np.split(target, np.cumsum(sizes)[:-1]) if sizes else []
        self._widths = [dofs.shape[1] for dofs in blocks]
        self.n = n
        self.nnz = len(self.indices)

    def data(self, values: list[np.ndarray]) -> np.ndarray:
        """Stored-entry values (nnz,) from one array of element matrices per block type."""
        out = np.zeros(self.nnz)
        for target, v in zip(self._targets, values):
            if v.size:
                _scatter_add(out, target, np.ascontiguousarray(v, dtype=float).reshape(-1))
        return out

    def data_subset(self, block: int, rows: np.ndarray, values: np.ndarray,
                    out: np.ndarray | None = None) -> np.ndarray:
        """Stored-entry values (nnz,) of the element matrices ``values`` (k, d, d) of elements ``rows``
        of block type ``block`` alone (the others zero), added to ``out`` when given."""
        out = np.zeros(self.nnz) if out is None else out
        target = self._targets[block]
        if len(rows) and target.size:
            per = self._widths[block] ** 2
            _scatter_add(out, np.ascontiguousarray(target.reshape(-1, per)[rows].reshape(-1)),
                         np.ascontiguousarray(values, dtype=float).reshape(-1))
        return out

    def add_symmetric(self, out: np.ndarray, values: list[np.ndarray]) -> np.ndarray:
        """Add the symmetric parts of element matrices (one (n, d, d) array per block type) to
        stored-entry data ``out`` in place, in one pass (no assembled unsymmetric matrix)."""
        for target, v in zip(self._targets, values):
            if v.size:
                scatter_add_symmetric(out, target, np.ascontiguousarray(v, dtype=float))
        return out

    def matrix(self, data: np.ndarray) -> sp.csc_matrix:
        A = sp.csc_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))
        A.has_sorted_indices = True  # by construction (spares CHOLMOD's callers a check)
        return A

    def assemble(self, values: list[np.ndarray]) -> sp.csc_matrix:
        return self.matrix(self.data(values))

    @property
    def transpose(self) -> np.ndarray:
        """Permutation p with data[p] the data of the transposed matrix (the pattern is symmetric)."""
        if not hasattr(self, "_transpose"):
            n = self.n
            keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(self.indptr)) * n + self.indices  # sorted
            swapped = (keys % n) * n + keys // n
            self._transpose = np.searchsorted(keys, swapped)
        return self._transpose

    def symmetric(self, K_data: np.ndarray, M_data: np.ndarray, alpha: float) -> sp.csc_matrix:
        """Symmetric part of K + alpha M (data of two matrices on this pattern), both triangles."""
        data = np.empty(self.nnz)
        _symmetric_part(K_data, M_data, self.transpose, alpha, data)
        return self.matrix(data)
