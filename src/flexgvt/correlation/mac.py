"""MAC, auto-MAC, COMAC and cross-orthogonality between measured and analytical mode sets.

Mode sets are taken as they come: a ModalSet (shapes (n_modes, n_dofs), its DOF labels giving
the sensors), fem Modes (shapes (n_modes, n_nodes, 6), reduced to the sensors about their own
state), or plain (n_modes, n_dof) arrays. Two ModalSets with different DOF labels are compared
over the DOFs both have, aligned by label (fem Modes.at(sensors) gives FE modes at the sensors as
a ModalSet). MAC uses the conjugate transpose (flexgvt.modal's kernel), so real and complex
shapes mix.

Rigid-body modes: the zero-frequency modes of a free structure span a 6-dimensional space in
which any rotation of the basis is as valid as another, so their individual MACs mean nothing.
pair() leaves analytical modes at 0 Hz out; use subspace_mac() to compare rigid-body subspaces.
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..modal import aligned_shapes, mac_rows


def _is_fem_modes(x) -> bool:
    return hasattr(x, "node_ids") and hasattr(x, "shapes") and np.ndim(x.shapes) == 3


def shapes_of(x, sensors=None, complex: bool = False) -> np.ndarray:
    """(n_modes, n_rows) shapes of a ModalSet, Modes or array; Modes reduced to ``sensors`` about
    their state (complex shapes with complex=True when the modes have them)."""
    if _is_fem_modes(x):
        if sensors is None:
            return np.asarray(x.shapes).reshape(len(x.shapes), -1)
        src = x.complex_shapes if complex and getattr(x, "complex_shapes", None) is not None else x.shapes
        S = sensors.matrix(x.node_ids, getattr(x, "state", None))
        return np.asarray(S @ np.asarray(src).reshape(len(src), -1).T).T
    s = np.asarray(getattr(x, "shapes", x))
    if s.ndim == 1:
        s = s[None, :]
    if s.ndim != 2:
        raise ModelError(f"mode shapes must be (n_modes, n_dof), got {s.shape}")
    if not np.all(np.isfinite(s)):
        raise ModelError("mode shapes contain NaN or infinity; fix or drop those modes before correlating")
    return s


def sensors_of(x):
    """The sensors a ModalSet's outputs define (identity point -> node map), or None."""
    outputs = getattr(x, "outputs", None)
    if outputs is None or np.size(outputs) == 0 or _is_fem_modes(x):
        return None
    from .sensors import Sensors
    return Sensors.from_outputs(outputs)


def _labelled(x) -> bool:
    return not _is_fem_modes(x) and getattr(x, "shapes", None) is not None and np.size(getattr(x, "dofs", ())) > 0


def _pair_shapes(a, b, sensors):
    if sensors is None and _labelled(a) and _labelled(b):
        shapes_of(a), shapes_of(b)  # checked
        A, B = aligned_shapes(a, b)
        return A, B, None
    sensors = sensors or sensors_of(a) or sensors_of(b)
    A, B = shapes_of(a, sensors), shapes_of(b, sensors)
    if A.shape[1] != B.shape[1]:
        raise ModelError(f"mode sets of {A.shape[1]} and {B.shape[1]} components: reduce the analytical modes to the "
                         "measured sensors (give sensors=...)")
    return A, B, sensors


def mac_of(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """MAC between the rows of A (na, n) and B (nb, n), real or complex (flexgvt.modal.mac_rows)."""
    return mac_rows(A, B)


def mac(a, b, sensors=None) -> np.ndarray:
    """(n_a, n_b) modal assurance criterion |a^H b|^2 / ((a^H a)(b^H b))."""
    A, B, _ = _pair_shapes(a, b, sensors)
    return mac_of(A, B)


def auto_mac(a, sensors=None) -> np.ndarray:
    """MAC of a set with itself (off-diagonal terms near 1 flag shapes the sensors cannot tell apart)."""
    A = shapes_of(a, sensors or sensors_of(a))
    return mac_of(A, A)


def comac(a, b, pairs=None, sensors=None) -> np.ndarray:
    """(n_rows,) coordinate MAC over the paired modes, |sum_r a_r conj(b_r)|^2 / (sum |a_r|^2 sum
    |b_r|^2) per row, each pair's analytical shape first scaled onto the measured one (modal scale
    factor). The signed sum, not Allemang's sum of |a b|: a sensor reading with the wrong sign or
    in the wrong direction lowers its COMAC instead of hiding behind the absolute values."""
    A, B, _ = _pair_shapes(a, b, sensors)
    if pairs is None:
        pairs = (np.arange(min(len(A), len(B))),) * 2
    ia, ib = (np.asarray(p, int) for p in pairs)
    A, B = A[ia], B[ib]
    msf = (np.sum(A.conj() * B, axis=1) / np.maximum(np.sum(np.abs(B) ** 2, axis=1), 1e-300))[:, None]
    B = B * msf
    num = np.abs(np.sum(A.conj() * B, axis=0)) ** 2
    den = np.sum(np.abs(A) ** 2, axis=0) * np.sum(np.abs(B) ** 2, axis=0)
    return num / np.where(den > 0, den, 1.0)


def cross_orthogonality(measured, modes, sensors=None, mass=None) -> np.ndarray:
    """(n_measured, n_analytical) cross-orthogonality Phi_m^T M Phi_a.

    With ``mass`` (a full (n_dof, n_dof) matrix) the measured shapes must be full-size. Otherwise
    the analytical mass is reduced to the sensors by SEREP, M_r = pinv(Phi_a)^T pinv(Phi_a), with
    Phi_a the analytical (mass-normalised) shapes at the sensors; each measured shape is first
    scaled to unit generalised mass in M_r (real parts; complex shapes rotated to their dominant
    real direction). 1 on the diagonal and ~0 off it for a perfect model; the usual acceptance is
    diagonal > 0.9 and off-diagonal < 0.1."""
    A, B, sensors = _pair_shapes(measured, modes, sensors)
    A = realise(A)
    B = np.real(B)
    if mass is not None:
        M = mass
    else:
        P = np.linalg.pinv(B.T)  # (n_a, n_rows)
        M = P.T @ P
    scale = np.sqrt(np.abs(np.einsum("ij,jk,ik->i", A, M, A)))
    A = A / np.where(scale > 0, scale, 1.0)[:, None]
    scale_b = np.sqrt(np.abs(np.einsum("ij,jk,ik->i", B, M, B)))
    B = B / np.where(scale_b > 0, scale_b, 1.0)[:, None]
    return A @ M @ B.T


def realise(A: np.ndarray) -> np.ndarray:
    """Real shapes from complex ones: each rotated to its dominant real direction."""
    if not np.iscomplexobj(A):
        return A
    out = np.empty(A.shape)
    for k, row in enumerate(A):
        angle = 0.5 * np.angle(np.sum(row * row))
        out[k] = np.real(row * np.exp(-1j * angle))
    return out


def subspace_mac(a, b, sensors=None) -> float:
    """Squared cosine of the largest principal angle between span(a) and span(b): 1 when span(a) lies
    in span(b). For rigid-body mode sets, whose bases are arbitrary."""
    A, B, _ = _pair_shapes(a, b, sensors)
    qa, _ = np.linalg.qr(A.T)
    qb, _ = np.linalg.qr(B.T)
    s = np.linalg.svd(qa.conj().T @ qb, compute_uv=False)
    return float(np.min(s) ** 2)
