"""Interpolation links (Nastran RBE3): the reference node follows the weighted best-fit rigid
motion of its nodes, exactly at any rotation.

With normalised weights w_i, undeformed arms r_i = X_i - C and current arms y_i = x_i - c (C, c
the weighted centroids), Q is the rotation of the polar decomposition of A = sum w_i y_i r_i^T
and the reference sits at c + Q (X_ref - C) with rotation Q. Differentiating A Q^T = Q S Q^T
(symmetric) gives the spin of Q,

    (tr(B) I - B) dw = sum_i w_i (Q r_i) x dx_i,   B = sum_i w_i y_i (Q r_i)^T,

which at the undeformed state is the least-squares rotation of Nastran's linear RBE3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .rotations import skew


@dataclass(frozen=True)
class InterpolationData:
    """Interpolation links of a model as arrays (node indices, not ids)."""

    reference: np.ndarray  # (m,) reference node index
    tied: np.ndarray  # (m, 6) bool: the reference's DOFs the link sets
    nodes: tuple[np.ndarray, ...]  # per link: node indices (n_i,)
    weights: tuple[np.ndarray, ...]  # per link: weights normalised to sum 1
    arms0: tuple[np.ndarray, ...]  # per link: X_i - C (n_i, 3)
    ref_arm0: np.ndarray  # (m, 3): X_ref - C

    def __len__(self) -> int:
        return len(self.reference)


def compile_interpolations(model, xyz: np.ndarray) -> InterpolationData:
    refs, tied, nodes, weights, arms, ref_arms = [], [], [], [], [], []
    for link in model.interpolations:
        idx = model.index_of(list(link.nodes))
        w = np.asarray(link.weights, float) / np.sum(link.weights)
        c = w @ xyz[idx]
        ref = model.index_of([link.reference])[0]
        refs.append(ref)
        row = np.zeros(6, bool)
        row[[int(ch) - 1 for ch in link.components]] = True
        tied.append(row)
        nodes.append(idx)
        weights.append(w)
        arms.append(xyz[idx] - c)
        ref_arms.append(xyz[ref] - c)
    return InterpolationData(np.array(refs, int), np.array(tied, bool).reshape(-1, 6), tuple(nodes), tuple(weights),
                             tuple(arms), np.array(ref_arms, float).reshape(-1, 3))


def fit(x_nodes: np.ndarray, w: np.ndarray, arms0: np.ndarray,
        ref_arm0: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reference position [m] and rotation Q of the best-fit rigid motion, and the current arms y_i."""
    c = w @ x_nodes
    y = x_nodes - c
    U, _, Vt = np.linalg.svd((w[:, None] * y).T @ arms0)
    D = np.ones(3)
    D[2] = np.sign(np.linalg.det(U @ Vt))
    Q = (U * D) @ Vt
    return c + Q @ ref_arm0, Q, y


def jacobian(x_nodes: np.ndarray, w: np.ndarray, arms0: np.ndarray, ref_arm0: np.ndarray) -> np.ndarray:
    """d(x_ref, spin_ref) / d(x_1, ..., x_n): (6, 3 n) at the current node positions."""
    _, Q, y = fit(x_nodes, w, arms0, ref_arm0)
    rho = arms0 @ Q.T
    B = (w[:, None] * y).T @ rho
    H = np.trace(B) * np.eye(3) - B
    rhs = (w[:, None, None] * skew(rho)).transpose(1, 0, 2).reshape(3, -1)
    # Nodes on a line leave the spin about it undefined (H singular there): the least-norm spin is
    # taken, which moves a reference on the line correctly (its arm has no lever about the line).
    spin = np.linalg.lstsq(H, rhs, rcond=1e-10)[0] if len(w) < 3 or np.linalg.cond(H) > 1e10 \
        else np.linalg.solve(H, rhs)  # (3, 3n)
    trans = np.kron(w[None, :], np.eye(3)) - skew(Q @ ref_arm0) @ spin
    return np.vstack([trans, spin])


def geometric_block(x_nodes, w, arms0, ref_arm0, load: np.ndarray) -> np.ndarray:
    """d(J^T load)/d(x_1..x_n) (3n, 3n) for a fixed reference load (force, moment): the
    stiffness of the rotating fit, by central differences of the analytic Jacobian (error ~1e-10
    relative; the block is small and exact differentiation of the polar decomposition twice is
    not worth its code)."""
    n3 = 3 * len(w)
    h = 1e-5 * max(np.abs(arms0).max(), 1e-3)
    out = np.empty((n3, n3))
    flat = x_nodes.reshape(-1)
    for j in range(n3):
        e = np.zeros(n3)
        e[j] = h
        plus = jacobian((flat + e).reshape(-1, 3), w, arms0, ref_arm0).T @ load
        minus = jacobian((flat - e).reshape(-1, 3), w, arms0, ref_arm0).T @ load
        out[:, j] = (plus - minus) / (2 * h)
    return out
