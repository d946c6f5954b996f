"""Each installed symmetric factorisation backend (fem.linsolve.BACKENDS: MKL PARDISO, CHOLMOD) solves
as SuperLU does on definite and indefinite systems, reuses its analysis while the pattern holds,
refuses a singular matrix (the caller then takes SuperLU), and the solver falls back to SuperLU
when no backend imports."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from flexgvt.errors import SolverError
from flexgvt.fem.linsolve import BACKENDS, CholmodCache, superlu

SRC = Path(__file__).resolve().parents[2] / "src"
backends = pytest.mark.parametrize("backend", BACKENDS or [pytest.param("none", marks=pytest.mark.skip(
    reason="no symmetric backend installed (pip install pypardiso): SuperLU only"))])


def _frame(rng, n_el=40, shift=0.0):
    """A chain of 4-DOF beam-like elements (a sparse symmetric matrix with both triangles stored) minus
    shift times a diagonal mass: definite for shift 0, indefinite above the lowest eigenvalues."""
    n = 2 * n_el + 2
    rows, cols, vals = [], [], []
    for e in range(n_el):
        d = np.arange(2 * e, 2 * e + 4)
        k = np.array([[12, 6, -12, 6], [6, 4, -6, 2], [-12, -6, 12, -6], [6, 2, -6, 4]], float)
        k *= 1.0 + 0.5 * rng.random()
        rows.append(np.repeat(d, 4))
        cols.append(np.tile(d, 4))
        vals.append(k.ravel())
    K = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).toarray()
    K[0, 0] += 1e3  # held at one end
    K[1, 1] += 1e3
    A = sp.csc_matrix(K - shift * np.eye(n))
    A.sort_indices()
    return A


@backends
@pytest.mark.parametrize("shift", [0.0, 0.05], ids=["definite", "indefinite"])
def test_backend_solves_as_superlu(backend, shift):
    rng = np.random.default_rng(3)
    A = _frame(rng, shift=shift)
    if shift:
        assert np.sum(np.linalg.eigvalsh(A.toarray()) < 0) >= 2  # really indefinite
    B = rng.standard_normal((A.shape[0], 3))
    cache = CholmodCache(backend)
    f = cache.factor(A)
    assert f is not None
    reference = superlu(A).solve(B[:, 0])
    np.testing.assert_allclose(f.solve_A(B[:, 0]), reference, rtol=1e-9, atol=1e-12 * np.abs(reference).max())
    X = f.solve_A(B)  # several right-hand sides at once
    np.testing.assert_allclose(A @ X, B, atol=1e-9 * np.abs(B).max())
    # New values on the same pattern: refactorised on the same analysis.
    A2 = A.copy()
    A2.data *= 1.0 + 0.1 * rng.random(A2.nnz)
    A2 = sp.csc_matrix(0.5 * (A2 + A2.T))
    A2.sort_indices()
    analyses = cache._analyses
    f2 = cache.factor(A2)
    assert cache._analyses == analyses
    np.testing.assert_allclose(A2 @ f2.solve_A(B[:, 1]), B[:, 1], atol=1e-9 * np.abs(B).max())


@backends
def test_backend_refuses_a_singular_matrix(backend):
    """A zero pivot (exactly singular) gives None, so the caller takes a pivoted LU (or a stabilising
    term), as the CHOLMOD path always did; so does a pattern without one of its diagonal entries."""
    singular = sp.csc_matrix(np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 2.0]]))
    assert CholmodCache(backend).factor(singular) is None
    missing = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 2.0]]))
    missing.eliminate_zeros()
    assert CholmodCache(backend).factor(missing) is None


@backends
def test_backend_in_the_newton_path(backend):
    """factor_blocks (the Newton solve's scatter straight into the analysed pattern) with each backend."""
    from flexgvt.fem.assembly import Pattern

    rng = np.random.default_rng(1)
    n_el, d = 6, 4
    dofs = np.array([[2 * e + k for k in range(d)] for e in range(n_el)])
    n = int(dofs.max()) + 1
    pattern = Pattern([dofs], np.arange(n), n)
    mass = pattern.data([np.tile(np.eye(d), (n_el, 1, 1))])
    cache = CholmodCache(backend)
    b = rng.standard_normal(n)
    for _ in range(3):
        B = rng.standard_normal((n_el, d, d))
        B = B @ np.swapaxes(B, 1, 2) + d * np.eye(d) + 0.3 * rng.standard_normal((n_el, d, d))
        f = cache.factor_blocks(pattern, [B], mass, 0.5)
        A = pattern.matrix(pattern.add_symmetric(0.5 * mass, [B]))
        np.testing.assert_allclose(A @ f.solve_A(b), b, atol=1e-10)
    assert cache._analyses == 1


def test_unknown_backend_is_a_clear_error():
    with pytest.raises(SolverError, match="not installed"):
        CholmodCache("no-such-solver")


_FALLBACK = """
import json, sys
for name in ("pypardiso", "sksparse"):
    sys.modules[name] = None  # the import fails as on a machine without the wheel
import numpy as np
import flexgvt as fg
from flexgvt.fem import linsolve
sys.path.insert(0, {tests!r})
from fem_builders import straight_beam
model, ids = straight_beam(60)
state = fg.solve_static(model, fg.Configuration("g", fixed={{int(ids[0]): "123456"}}, gravity=1.0))
print(json.dumps({{"backends": list(linsolve.BACKENDS), "tip": state.positions[-1].tolist(),
                   "f": fg.solve_modes(state, 6).frequencies_hz.tolist()}}))
"""


def test_superlu_fallback_when_no_backend_imports():
    """Without pypardiso and scikit-sparse the same model solves through SuperLU to the same state and
    frequencies as with the default backend."""
    import flexgvt as fg
    from fem_builders import straight_beam

    script = _FALLBACK.format(tests=str(Path(__file__).resolve().parent))
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         env={"PYTHONPATH": str(SRC), "PATH": "/usr/bin:/bin", "MPLBACKEND": "Agg"})
    assert out.returncode == 0, out.stderr[-2000:]
    fallback = json.loads(out.stdout.strip().splitlines()[-1])
    assert fallback["backends"] == []
    model, ids = straight_beam(60)
    state = fg.solve_static(model, fg.Configuration("g", fixed={int(ids[0]): "123456"}, gravity=1.0))
    np.testing.assert_allclose(state.positions[-1], fallback["tip"], atol=1e-9)
    np.testing.assert_allclose(fg.solve_modes(state, 6).frequencies_hz, fallback["f"], rtol=1e-8)


pardiso_only = pytest.mark.skipif("pardiso" not in BACKENDS, reason="pypardiso not installed")


@pardiso_only
def test_pardiso_inertia_counts_the_negative_eigenvalues():
    """MKL's iparm(22)/(23) from the Bunch-Kaufman LDL^T: the eigenvalue signs of an indefinite matrix
    (Sylvester), and no count for a singular one (its perturbed pivot's sign is not the matrix's)."""
    from flexgvt.fem.linsolve import inertia

    for shift in (0.0, 0.05, 0.4):
        A = _frame(np.random.default_rng(3), shift=shift)
        negative = int(np.sum(np.linalg.eigvalsh(A.toarray()) < 0))
        assert inertia(A) == (A.shape[0] - negative, negative)
    assert inertia(sp.csc_matrix(np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 2.0]]))) is None


def _column(over: float):
    """A pinned-pinned steel column (40 elements, 1 m, 20 x 12 mm) compressed to ``over`` times its weak
    Euler load P_E, held straight by load control (the fundamental path): unstable above 1, its strong
    axis above (20 / 12)^2 = 2.78, the second weak mode above 4."""
    import flexgvt as fg
    from fem_builders import straight_beam

    section = fg.RectangularSection(width=0.02, height=0.012)
    model, ids = straight_beam(40, length=1.0, section=section, material=fg.Material("steel", E=2.1e11, nu=0.3,
                                                                                     rho=7850.0))
    p_euler = np.pi**2 * 2.1e11 * min(section.properties()["Iy"], section.properties()["Iz"])
    config = fg.Configuration("compressed", fixed={int(ids[0]): "1235", int(ids[-1]): "13"},
                              forces=(fg.NodalLoad(int(ids[-1]), force=(0.0, -over * p_euler, 0.0)),))
    return fg.solve_static(model, config, settings=fg.fem.static.StaticSettings(buckling="ignore"))


@pardiso_only
@pytest.mark.parametrize("over", [0.8, 1.5, 3.5])
def test_stability_count_by_pardiso_agrees_with_superlu(over):
    """fem.stability's negative eigenvalue count through PARDISO's inertia equals SuperLU's diagonal-
    pivot count and the dense eigenvalue count on a compressed column: none below the Euler load,
    one above it, two above the strong axis's."""
    from flexgvt.fem.linsolve import inertia
    from flexgvt.fem.stability import _matrices, negative_eigenvalues, shifted, superlu_negative_pivots

    state = _column(over)
    s, x, R = state.system, state.positions, state.rotations
    K, M = _matrices(s, x, R, 1.0)
    A = shifted(s, K, M)
    dense = int(np.sum(np.linalg.eigvalsh(A.toarray()) < 0))
    assert dense == {0.8: 0, 1.5: 1, 3.5: 2}[over]
    assert inertia(A) == (A.shape[0] - dense, dense)
    assert negative_eigenvalues(s, x, R, 1.0) == dense
    assert superlu_negative_pivots(A) == dense


@pardiso_only
def test_shift_invert_through_pardiso_agrees_with_superlu():
    """The modes' shift-invert with PARDISO's factor equals SuperLU's on a free beam with point masses
    and massless rotations (above the dense limit), its five rigid-body modes with mass included (the
    spin about its axis has none)."""
    import flexgvt as fg
    from fem_builders import straight_beam

    model, ids = straight_beam(60, material=fg.Material("Al", E=70e9, nu=0.33, rho=0.0))
    for i in ids:
        model.add_mass(int(i), 0.05)
    state = fg.solve_static(model, fg.Configuration("free"))
    fast = fg.solve_modes(state, 12, damped=False)
    slow = fg.solve_modes(state, 12, damped=False, cholmod=False)
    elastic = slow.frequencies_hz > 0
    assert np.sum(~elastic) == 5 and np.all(fast.frequencies_hz[~elastic] == 0.0)
    np.testing.assert_allclose(fast.frequencies_hz[elastic], slow.frequencies_hz[elastic], rtol=1e-9)


@pardiso_only
@pytest.mark.parametrize("over", [0.9, 1.5, 2.5])
def test_stability_count_by_pardiso_on_a_compressed_plate(over):
    """The same three counts on a shell plate under in-plane compression past its first buckling loads
    (test_buckling's simply supported plate, 8 x 8 quads, held flat by load control): none below the
    first, one past it, two past the second."""
    import flexgvt as fg
    from flexgvt.fem.linsolve import inertia
    from flexgvt.fem.stability import _matrices, negative_eigenvalues, shifted, superlu_negative_pivots
    from test_buckling import _plate

    model, config, _ = _plate(8, over)
    state = fg.solve_static(model, config, settings=fg.fem.static.StaticSettings(buckling="ignore"))
    s, x, R = state.system, state.positions, state.rotations
    A = shifted(s, *_matrices(s, x, R, 1.0))
    dense = int(np.sum(np.linalg.eigvalsh(A.toarray()) < 0))
    assert dense == {0.9: 0, 1.5: 1, 2.5: 2}[over]  # k = 4 (m = 1), then 6.25 (m = 2) of the closed form
    assert inertia(A) == (A.shape[0] - dense, dense)
    assert negative_eigenvalues(s, x, R, 1.0) == dense == superlu_negative_pivots(A)
