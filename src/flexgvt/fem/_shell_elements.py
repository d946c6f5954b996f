"""Linear flat shell elements (quad MITC4 + Allman/Hughes-Brezzi membrane, triangle DKMT + ANDES-OPT
membrane): per-element global stiffness and mass from the compiled kernels, and a plain sparse
assembly used by the element tests and benchmarks (the solver's own assembly lives elsewhere)."""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from ._shell_kernel import _CHUNK, OK, _geometric_chunk, _quad_chunk, _tri_chunk, quad_kernel, tri_kernel

DRILL_FACTOR = 1.0  # Hughes-Brezzi penalty gamma = DRILL_FACTOR * A33 (Ibrahimbegovic et al. 1990: gamma = G)


@dataclass(frozen=True)
class ShellMatrices:
    """Element matrices K, M (n, 6 nn, 6 nn) on [u, v, w, rx, ry, rz] per node, in global axes (or in
    the element frames when asked for local ones); frames (n, 3, 3) the element frames (columns x, y,
    z); coords (n, nn, 3) each corner's local x, y on the element's (mean) plane and its height h
    above it [m] (the rigid link of a warped quad)."""

    K: np.ndarray
    M: np.ndarray | None
    frames: np.ndarray
    coords: np.ndarray


def shell_matrices(X: np.ndarray, C: np.ndarray, mass: np.ndarray | None = None, lumped=False,
                   drill_factor: float = DRILL_FACTOR, ids: np.ndarray | None = None,
                   local: bool = False, drill: np.ndarray | None = None) -> ShellMatrices:
    """Stiffness (and mass if ``mass`` is given) of n quads (X (n, 4, 3) corners [m]) or triangles
    (X (n, 3, 3)). C (n, 8, 8) section matrices in element axes, mass (n, 3) [m0, m1, m2] per
    area (_shell_section.section_arrays), lumped: bool or (n,) bools. ids: element ids for the
    error messages (default: the row numbers). local: the matrices in the element frames (what a
    corotational wrapper rotates), else in global axes. drill: (n,) the drilling penalties when
    given (default: drill_factor_penalty of C), so that a quad's matrices are linear in (C, drill)."""
    X = np.ascontiguousarray(X, dtype=float)
    n, nn = X.shape[0], X.shape[1]
    if X.ndim != 3 or nn not in (3, 4) or X.shape[2] != 3:
        raise ModelError(f"shell elements: corner array of shape {X.shape}; expected (n, 4, 3) or (n, 3, 3)")
    C = np.ascontiguousarray(C, dtype=float)
    want_mass = mass is not None
    mass = np.ascontiguousarray(mass if want_mass else np.zeros((n, 3)), dtype=float)
    lumped = np.ascontiguousarray(np.broadcast_to(np.asarray(lumped, dtype=bool), (n,)))
    drill = np.ascontiguousarray(drill_factor_penalty(X, C, drill_factor) if drill is None else drill, dtype=float)
    nd = 6 * nn
    K = np.empty((n, nd, nd))
    M = np.empty((n, nd, nd)) if want_mass else np.empty((0, nd, nd))
    frames = np.empty((n, 3, 3))
    coords = np.empty((n, nn, 3))
    status = np.empty(n, dtype=np.int64)
    chunk, kernel = (_quad_chunk, quad_kernel) if nn == 4 else (_tri_chunk, tri_kernel)
    args = (X, C, mass, drill, lumped, want_mass, bool(local), K, M, frames, coords, status)
    if n < 2 * _CHUNK:
        chunk(*args, 0, n)
    else:
        kernel(*args, numba.get_num_threads())
    bad = np.flatnonzero(status != OK)
    if bad.size:
        names = (np.arange(n) if ids is None else np.asarray(ids))[bad[:10]]
        kind = "quad" if nn == 4 else "triangle"
        raise ModelError(f"{bad.size} {kind} element(s) are inverted, degenerate or too distorted "
                         f"(det J <= 0 at an integration point), e.g. {', '.join(str(i) for i in names)}: "
                         "check the corner order (counter-clockwise about the normal, no crossing sides)")
    return ShellMatrices(K, M if want_mass else None, frames, coords)


def shell_geometric(X: np.ndarray, N: np.ndarray) -> np.ndarray:
    """Initial-stress (geometric) stiffness (n, 6 nn, 6 nn), global axes, of quads X (n, 4, 3) or
    triangles X (n, 3, 3) under membrane resultants N (n, 3) = [Nx, Ny, Nxy] [N/m] in element axes
    (tension positive): int grad(c)^T N grad(c) dA for each translation c, with the corners'
    bilinear (quad) or linear (triangle) fields. Linear buckling: (K + lambda K_sigma) phi = 0."""
    X = np.ascontiguousarray(X, dtype=float)
    N = np.ascontiguousarray(N, dtype=float)
    if X.ndim != 3 or X.shape[1] not in (3, 4) or N.shape != (X.shape[0], 3):
        raise ModelError(f"shell_geometric: corners of shape {X.shape} and resultants of shape {N.shape}; "
                         "expected (n, 4 or 3, 3) and (n, 3)")
    out = np.empty((X.shape[0], 6 * X.shape[1], 6 * X.shape[1]))
    _geometric_chunk(X, N, out, 0, X.shape[0])
    return out


def drill_factor_penalty(X: np.ndarray, C: np.ndarray, drill_factor: float = DRILL_FACTOR,
                         like: np.ndarray | None = None) -> np.ndarray:
    """(n,) the drilling penalty of sections C (n, 8, 8) on elements X: drill_factor A33, or where a
    section has no membrane (A33 <= 0) drill_factor 12 D33 / size^2 (the bending stiffness ties the
    drilling rotation instead). like: the sections that choose the branch (C is then a change of
    them: the penalty is linear in C within a branch)."""
    membrane = (C if like is None else like)[:, 2, 2] > 0
    return np.where(membrane, drill_factor * C[:, 2, 2],
                    drill_factor * 12.0 * C[:, 5, 5] / np.maximum(_size2(X), 1e-300))


def _size2(X):
    """Squared mean side length of each element (scale of the fallback drilling stiffness)."""
    d = X - np.roll(X, 1, axis=1)
    return np.mean(np.sum(d * d, axis=2), axis=1)


def assemble(conn: np.ndarray, Ke: np.ndarray, n_nodes: int) -> sp.csr_matrix:
    """Global sparse matrix (6 n_nodes square) from element matrices Ke (n, 6 nn, 6 nn) on nodes conn (n, nn)."""
    conn = np.asarray(conn)
    n, nn = conn.shape
    dofs = (6 * conn[:, :, None] + np.arange(6)[None, None, :]).reshape(n, 6 * nn)
    rows = np.broadcast_to(dofs[:, :, None], Ke.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], Ke.shape).ravel()
    return sp.csr_matrix((Ke.ravel(), (rows, cols)), shape=(6 * n_nodes, 6 * n_nodes))
