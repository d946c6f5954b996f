"""The modal assurance criterion: the one kernel every MAC in flexgvt calls."""

from __future__ import annotations

import numpy as np


def mac_columns(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(na, nb) MAC between the columns of a (n, na) and b (n, nb), real or complex:
    |a^H b|^2 / ((a^H a)(b^H b)); 0 where a vector is zero."""
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return num / np.where(den > 0, den, 1.0)


def mac_rows(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """(na, nb) MAC between the rows of A (na, n) and B (nb, n) (shapes as modes x DOFs)."""
    return mac_columns(np.asarray(A).T, np.asarray(B).T)


def mac_paired(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """(n,) MAC of each row of A (n, m) with the same row of B (n, m) (or with B (m,) for every row)."""
    A = np.asarray(A)
    B = np.broadcast_to(np.asarray(B), A.shape)
    num = np.abs(np.sum(A.conj() * B, axis=1)) ** 2
    den = np.sum(np.abs(A) ** 2, axis=1) * np.sum(np.abs(B) ** 2, axis=1)
    return num / np.where(den > 0, den, 1.0)
