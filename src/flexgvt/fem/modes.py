"""Modal analysis about any state: real modes with the tangent stiffness (stress stiffening and load
stiffness included), sparse shift-invert, rigid-body modes, and complex modes with viscous damping.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import FlexGVTWarning, ModelError
from ..modal import ModalSet, as_dofs
from .checks import check_matrix
from .eigen import (_NO_MASS, DEFAULT_SHIFT, DENSE_LIMIT, complex_modes, modal_frequencies_hz,  # noqa: F401
                    real_modes, rigid_count)
from .labels import OVERDAMPED
from .linsolve import serial_blas
from .reduction import guyan_modes, omitted_dofs
from .static import State


@dataclass(frozen=True)
class Modes:
    """Modes of a structure about a state.

    frequencies_hz (n_modes,): undamped natural frequencies (negative: unstable, the tangent is
    not positive definite there); damping_ratio (n_modes,): zero for real modes;
    damped_frequencies_hz (n_modes,); shapes (n_modes, n_nodes, 6): mass-normalised
    (phi^T M phi = 1) real modes, or the real part of complex modes normalised the same way;
    complex_shapes: (n_modes, n_nodes, 6) complex or None; node_ids (n_nodes,).
    """

    frequencies_hz: np.ndarray
    damping_ratio: np.ndarray
    damped_frequencies_hz: np.ndarray
    shapes: np.ndarray
    node_ids: np.ndarray
    labels: tuple[str, ...] = ()
    complex_shapes: np.ndarray | None = None
    eigenvalues: np.ndarray | None = None  # lambda = omega^2 [rad^2/s^2] (real) or s [rad/s] (complex)
    energy_fractions: np.ndarray | None = None  # (n_modes, 6): OOP, IP, T, EXT, rigid/suspension, local
    state: State | None = field(default=None, repr=False, compare=False)
    cautions: tuple[str, ...] = ()  # what makes these modes doubtful (see mode_cautions)

    def matrix(self, dofs: str = "all") -> np.ndarray:
        """(n_dof, n_modes) matrix of the shapes (node-major, 6 DOF per node; 'translations' for 3)."""
        s = self.shapes if dofs == "all" else self.shapes[:, :, :3]
        return s.reshape(len(s), -1).T

    @property
    def n_modes(self) -> int:
        return len(self.frequencies_hz)

    def table(self) -> list[dict]:
        return [{"mode": i + 1, "frequency_hz": float(f), "damping_ratio": float(z),
                 "label": self.labels[i] if self.labels else ""}
                for i, (f, z) in enumerate(zip(self.frequencies_hz, self.damping_ratio))]

    def at(self, sensors, complex: bool = False) -> ModalSet:
        """These modes at ``sensors`` as a ModalSet (shapes (n_modes, n_sensors), DOF-labelled like test
        modes, so MAC aligns the two by their common DOFs).

        sensors: a flexgvt.correlation.Sensors (readings d . (u + theta x r), turning with the nodes
        of ``state`` when the modes have one), or DOF labels (n, 2) of (node id, direction code
        +-1..6): the node's translation or rotation, with the code's sign. complex: the complex
        shapes where the modes have them (else the real, mass-normalised ones)."""
        src = self.complex_shapes if complex and self.complex_shapes is not None else self.shapes
        if hasattr(sensors, "matrix"):
            S = sensors.matrix(self.node_ids, self.state)
            shapes = np.asarray(S @ np.asarray(src).reshape(len(src), -1).T).T
            dofs = sensors.dofs
        else:
            dofs = as_dofs(sensors, "Modes.at")
            codes = dofs[:, 1].astype(int)
            if np.any(codes == 0):
                raise ModelError("Modes.at: direction code 0 (a scalar channel) is not a DOF of the FE nodes; use "
                                 "+-1..3 for translations and +-4..6 for rotations")
            order = np.argsort(self.node_ids)
            pos = np.clip(np.searchsorted(self.node_ids, dofs[:, 0], sorter=order), 0, len(order) - 1)
            rows = order[pos]
            missing = self.node_ids[rows] != dofs[:, 0]
            if np.any(missing):
                raise ModelError(f"Modes.at: node(s) {sorted(set(dofs[missing, 0].tolist()))[:10]} are not in the "
                                 "model; give DOFs of FE nodes (map test points with correlation.Sensors)")
            shapes = src[:, rows, np.abs(codes) - 1] * np.sign(codes)
        return ModalSet(self.frequencies_hz, self.damping_ratio, shapes, dofs=dofs, labels=self.labels)


def _align_rigid_modes(phi: np.ndarray, zero: np.ndarray, system, x: np.ndarray, T, M) -> np.ndarray:
    """Within the cluster of zero-frequency modes (any M-orthonormal basis of it is an
    eigenbasis), the basis closest to the free rigid motions (fore-aft, lateral, plunge, roll,
    pitch, yaw about the centroid, in that order): the orthogonal Procrustes rotation of the
    cluster onto their M-projections. Left as it is unless the cluster is exactly those motions."""
    idx = np.flatnonzero(zero)
    motions, basis = system.unrestrained_rigid_motions(x)
    if len(idx) < 2 or len(idx) != basis.shape[1]:
        return phi
    rigid = system.reduce_displacement(motions @ basis)
    C = phi[:, idx].T @ (M @ rigid)  # (cluster, motions): the motions' components in the cluster
    if not np.all(np.isfinite(C)):
        return phi
    u, sv, vt = np.linalg.svd(C)
    if sv.min() < 1e-6 * sv.max():  # the cluster does not span the rigid motions (not only them)
        return phi
    out = phi.copy()
    out[:, idx] = phi[:, idx] @ (u @ vt)
    return out


MASS_FRAMES = ("deformed", "undeformed")


@serial_blas
def solve_modes(state: State, n_modes: int = 15, *, damped: bool | None = None, shift: float | None = None,
                label: bool = True, cholmod: bool = True, mass_frame: str = "deformed",
                reduction: Mapping | None = None) -> Modes:
    """Modes about ``state`` with its tangent stiffness (symmetric part: stress and load stiffness included).

    damped: complex modes with the viscous dampers of springs and cords (default: when present).
    shift: eigenvalue shift [rad^2/s^2] (default: slightly negative, so rigid-body modes are found).
    cholmod: use the symmetric factorisation (PARDISO or CHOLMOD, fem.linsolve) for the shift-invert where
    StaticSettings.cholmod. Rigid-body modes of free structures come out at 0 Hz.
    mass_frame: "deformed" (default, physical: the sections' inertia and offset masses turn with
    the deformed structure) or "undeformed": the mass matrix of the undeformed configuration with
    the deformed stiffness, as MSC Nastran SOL 400 and OpenSees compute pre-stressed modes (use it
    to reproduce their numbers; docs/solver.md compares both with shell and brick models).
    reduction: Guyan reduction sets, {'ASET' and/or 'OMIT': {node id: components}} (a deck's
    ``BdfDeck.options``; fem.reduction): real modes of the statically condensed model, as Nastran.
    """
    if mass_frame not in MASS_FRAMES:
        raise ModelError(f"solve_modes: mass_frame='{mass_frame}' must be one of {MASS_FRAMES}")
    system = state.system
    x, R = state.positions, state.rotations
    ev = system.evaluate(x, R, state.load_factor, assemble=False)
    M = system.mass_matrix(x, R) if mass_frame == "deformed" else system.mass_matrix(x, R, frame="undeformed")
    K = system.newton_matrix(ev, M, 0.0)  # the symmetric part of the tangent
    check_matrix(system, K, "stiffness")
    check_matrix(system, M, "mass")
    if not np.any(M.data):
        raise ModelError(f"configuration '{system.config.name}': {_NO_MASS}")
    clamped = system.clamped
    T = system.transformation(x, R) if system.has_links else None
    n = system.n_nodes
    use_damping = system.has_damping if damped is None else damped
    n_rigid = 0 if clamped else rigid_count(system, x, T, K, M)
    omitted = omitted_dofs(system, reduction) if reduction else np.zeros(0, int)
    if use_damping and len(omitted):
        raise ModelError(f"configuration '{system.config.name}': Guyan reduction (reduction=...) applies to real "
                         "modes; pass damped=False, or leave the reduction out for complex modes")
    if use_damping:
        C = system.damping_matrix(x, R)
        s, v = complex_modes(K, C, M, n_modes, clamped, 0 if clamped else n_rigid)
        wn = np.abs(s)
        freq = np.where(wn < 1e-5 * max(wn.max(initial=0.0), 1.0), 0.0, wn / (2 * np.pi))
        zeta = np.where(wn > 0, -s.real / np.where(wn > 0, wn, 1), 0.0)
        wd = np.abs(s.imag) / (2 * np.pi)
        cshapes = system.expand(v, T).T.reshape(len(s), n, 6)
        real = np.real(cshapes)
        mm = np.real(np.einsum("ij,ij->j", v.real, M @ v.real))
        real = real / np.sqrt(np.where(mm > 0, mm, 1.0))[:, None, None]
        modes = Modes(freq, zeta, wd, real, system.cm.node_ids, complex_shapes=cshapes, eigenvalues=s, state=state)
    else:
        if len(omitted):
            lam, phi = guyan_modes(K, M, omitted, n_modes, shift, clamped)
        else:
            lam, phi = real_modes(K, M, n_modes, shift, clamped, system.cholmod_cache, use_cholmod=cholmod)
        f = modal_frequencies_hz(lam, K, M, system, x, T, n_rigid=n_rigid)  # counted once, above
        if not clamped:
            phi = _align_rigid_modes(phi, f == 0, system, x, T, M)
        shapes = system.expand(phi, T).T.reshape(len(lam), n, 6)
        modes = Modes(f, np.zeros(len(f)), f.copy(), shapes, system.cm.node_ids, eigenvalues=lam, state=state)
    if label:
        from .labels import label_modes
        modes = label_modes(modes)
    return mode_cautions(modes, n_rigid)


MECHANISM_RATIO = 1e-6  # a mode this far below the highest one found is a zero-energy mode


def mode_cautions(modes: Modes, n_rigid: int) -> Modes:
    """The modes with their cautions (a FlexGVTWarning for each) and honest labels:
    - real roots of the damped problem (damping ratio 1; labelled 'overdamped k' by label_modes) are
      named;
    - an unstable state: a negative eigenvalue (negative frequency) or a root with negative damping
      is labelled 'unstable k (CLASS)', never as an elastic mode;
    - mechanisms: more zero-frequency modes (below MECHANISM_RATIO of the highest one found) than
      the structure has rigid-body motions (n_rigid: none when it is restrained), with the DOFs that
      move most in each."""
    f = np.asarray(modes.frequencies_hz, float)
    name = modes.state.configuration.name if modes.state is not None else "?"
    labels = list(modes.labels) if modes.labels else [""] * len(f)
    notes = []
    unstable = np.flatnonzero((f < 0) | (np.asarray(modes.damping_ratio) < -1e-9))
    for k, m in enumerate(unstable):
        cls = labels[m].split(" ", 1)[-1] if labels[m] else ""
        labels[m] = f"unstable {k + 1}" + (f" ({cls})" if cls else "")
    if len(unstable):
        shown = ", ".join(f"{f[m]:.4g} Hz" for m in unstable[:4])
        notes.append(f"configuration '{name}': the state is unstable: {len(unstable)} mode(s) with a negative "
                     f"eigenvalue or negative damping ({shown}; labelled 'unstable'). The tangent stiffness is not "
                     "positive definite there: the structure has buckled or is loaded past a limit point, so these "
                     "are not elastic modes. Check the loads and supports, or solve at a lower load factor")
    slow = np.flatnonzero((np.asarray(modes.damping_ratio) >= OVERDAMPED) & (f != 0.0))
    if len(slow):
        shown = ", ".join(f"{f[m]:.4g}" for m in slow[:4])
        notes.append(f"configuration '{name}': {len(slow)} root(s) of the damped problem are real (overdamped: they "
                     f"decay without vibrating; |s| / 2 pi = {shown}{' ...' if len(slow) > 4 else ''} Hz), labelled "
                     "'overdamped k' and left out of the mode classes. A damper acting on a DOF with little or no "
                     "mass makes one (a rotational damper on a node's rotations, say): if that is not meant, give "
                     "the damper only the components it has")
    top = np.abs(f).max(initial=0.0)
    zero = np.flatnonzero(np.abs(f) <= MECHANISM_RATIO * top) if top > 0 else np.arange(len(f))
    if len(zero) > n_rigid:
        extra = zero[n_rigid:] if n_rigid else zero
        moving = []
        for k, m in enumerate(extra):
            labels[m] = f"mechanism {k + 1}"
            a = np.abs(modes.shapes[m])
            node, dof = np.unravel_index(int(np.argmax(a)), a.shape)
            moving.append(f"node {modes.node_ids[node]} {('T1', 'T2', 'T3', 'R1', 'R2', 'R3')[dof]}")
        moving = moving[:4]
        notes.append(f"configuration '{name}': {len(zero)} zero-frequency mode(s) where the structure has "
                     f"{n_rigid} rigid-body motion(s): {len(extra)} mechanism(s), moving most at "
                     f"{', '.join(moving)}{' ...' if len(extra) > 4 else ''}. A stiffness is missing or "
                     "absurdly small there (a section property, a released end, a spring or a support): check "
                     "the model's values at those nodes")
    for note in notes:
        warnings.warn(note, FlexGVTWarning, stacklevel=3)
    if not notes:
        return modes
    return replace(modes, labels=tuple(labels), cautions=modes.cautions + tuple(notes))
