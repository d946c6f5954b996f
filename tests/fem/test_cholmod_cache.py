"""The CHOLMOD cache leaves exactly-zero entries out of its analysis and re-analyses when one turns non-zero."""

import numpy as np
import pytest
import scipy.sparse as sp

from flexgvt.fem.linsolve import HAVE_CHOLMOD, CholmodCache

pytestmark = pytest.mark.skipif(not HAVE_CHOLMOD, reason="scikit-sparse not installed")


def _spd_on_pattern(rng, n, couple):
    """A symmetric positive definite matrix on a fixed dense pattern whose off-diagonal entries
    coupling the even and odd unknowns are zero unless ``couple``."""
    A = rng.standard_normal((n, n))
    A = A @ A.T + n * np.eye(n)
    parity = np.arange(n) % 2
    if not couple:
        A[parity[:, None] != parity[None, :]] = 0.0
    full = sp.csc_matrix(np.ones((n, n)))  # the assembled pattern keeps every entry
    full.data[:] = A.T.reshape(-1)  # column-major values of A on the dense pattern
    return full, A


def test_zero_entries_are_pruned_and_a_new_nonzero_triggers_a_new_analysis():
    rng = np.random.default_rng(0)
    n = 12
    cache = CholmodCache("cholmod")
    b = rng.standard_normal(n)
    A1, D1 = _spd_on_pattern(rng, n, couple=False)
    f = cache.factor(A1)
    assert f.L().nnz < n * (n + 1) // 2  # half the couplings left out
    np.testing.assert_allclose(D1 @ f.solve_A(b), b, atol=1e-10)
    first = cache.factor_object
    A2, D2 = _spd_on_pattern(rng, n, couple=False)  # same zeros: refactorisation only
    f = cache.factor(A2)
    assert cache.factor_object is first
    np.testing.assert_allclose(D2 @ f.solve_A(b), b, atol=1e-10)
    A3, D3 = _spd_on_pattern(rng, n, couple=True)  # the couplings turn non-zero
    f = cache.factor(A3)
    assert cache.factor_object is not first
    np.testing.assert_allclose(D3 @ f.solve_A(b), b, atol=1e-10)
    A4, D4 = _spd_on_pattern(rng, n, couple=False)  # the grown pattern holds the zeros too
    f = cache.factor(A4)
    np.testing.assert_allclose(D4 @ f.solve_A(b), b, atol=1e-10)


def test_indefinite_matrix_is_factorised_and_a_zero_pivot_refused():
    """LDL^T without pivoting: an indefinite matrix with sound pivots solves exactly; a zero pivot
    (singular leading block) gives None so that the caller takes a pivoted LU."""
    A = sp.csc_matrix(np.array([[1.0, 2.0], [2.0, 1.0]]))  # eigenvalues 3 and -1
    f = CholmodCache("cholmod").factor(A)
    np.testing.assert_allclose(A @ f.solve_A(np.array([1.0, 0.0])), [1.0, 0.0], atol=1e-14)
    assert CholmodCache("cholmod").factor(sp.csc_matrix(np.array([[1.0, 1.0], [1.0, 1.0]]))) is None


def test_a_diagonal_entry_missing_from_the_pattern_is_a_zero_pivot():
    A = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 2.0]]))
    A.eliminate_zeros()  # no stored (0, 0) entry
    assert CholmodCache("cholmod").factor(A) is None


def test_element_blocks_scattered_into_the_analysed_pattern_match_the_assembled_matrix():
    """factor_blocks (the Newton solve's path) factorises the symmetric part of element matrices
    plus alpha M as the assembled matrix would, refactorises on the same analysis while the zero
    couplings stay zero, and re-analyses when an element block turns one non-zero."""
    from flexgvt.fem.assembly import Pattern

    rng = np.random.default_rng(1)
    n_el, d = 6, 4  # a chain of 4-DOF elements sharing 2 DOFs with the next
    dofs = np.array([[2 * e + k for k in range(d)] for e in range(n_el)])
    n = int(dofs.max()) + 1
    pattern = Pattern([dofs], np.arange(n), n)
    mass = pattern.data([np.tile(np.eye(d), (n_el, 1, 1))])
    parity = np.arange(d) % 2

    def blocks(couple):
        B = rng.standard_normal((n_el, d, d))
        B = B @ np.swapaxes(B, 1, 2) + d * np.eye(d) + 0.3 * rng.standard_normal((n_el, d, d))  # not symmetric
        if not couple:
            B[:, parity[:, None] != parity[None, :]] = 0.0
        return B

    def assembled(B, alpha):
        A = pattern.matrix(pattern.add_symmetric(alpha * mass, [B])).toarray()
        np.testing.assert_allclose(A, A.T)
        return A

    cache = CholmodCache("cholmod")
    b = rng.standard_normal(n)
    B1 = blocks(couple=False)
    cache.factor_blocks(pattern, [B1], mass, 0.5)  # first call: analysis of the non-zero entries
    analyses = cache._analyses
    for couple in (False, False, True, False):
        B = blocks(couple)
        f = cache.factor_blocks(pattern, [B], mass, 0.5)
        np.testing.assert_allclose(assembled(B, 0.5) @ f.solve_A(b), b, atol=1e-10)
        assert cache._analyses == analyses + (1 if couple else 0)
        assert cache._blocks_key is not None  # the scattered path ran (not only the assembled one)
        analyses = cache._analyses
