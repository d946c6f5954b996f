"""One configuration's rows of the updating problem: residuals (frequencies, 1 - MAC, static
deflections, cross-orthogonality), constraints (MAC >= mac_min) and their exact Jacobian rows."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..correlation.mac import realise
from ..errors import SolverError
from ..model import Model
from .derivatives import eigenvalue_derivatives, eigenvector_derivatives, modal_terms, state_derivatives
from .modesolve import ModeSolver
from .points import Block, ConfigurationPoint
from .targets import Measured, Objective
from .variables import Parametrisation


class ConfigurationBlocks:
    """The rows of each configuration at a design point of ``par`` on the working model ``work``,
    weighted by ``objective`` against ``measured`` ({configuration: Measured}); follow_sensors: the
    sensors turn with their nodes."""

    def __init__(self, par: Parametrisation, work: Model, objective: Objective, measured: dict[str, Measured],
                 follow_sensors: bool = True):
        self.par = par
        self.work = work
        self.objective = objective
        self.measured = measured
        self.follow_sensors = follow_sensors

    def block(self, x: np.ndarray, p: ConfigurationPoint, gradient: bool, changes=None) -> Block:
        """Residuals (frequencies, 1 - MAC, static deflections), constraints (MAC >= mac_min) and,
        with gradient, their exact Jacobian rows for one configuration."""
        w = self.objective
        name, meas = p.name, self.measured[p.name]
        fm = meas.frequencies_hz
        ok = p.paired >= 0
        idx = np.maximum(p.paired, 0)
        fa = p.frequencies_hz[idx]
        wf = self.frequency_weights(meas)
        use_mac = meas.shapes is not None and w.mac > 0
        use_static = bool(meas.static) and w.static > 0
        use_mac_min = meas.shapes is not None and w.mac_min is not None
        use_xor = meas.shapes is not None and w.orthogonality > 0
        res = [np.where(ok, w.frequency * wf * (fa - fm) / fm, 0.0)]
        names = [f"{name}: f{i + 1}" for i in range(len(fm))]
        if use_mac:
            res.append(np.where(ok, w.mac * (1.0 - np.nan_to_num(p.mac)), 0.0))
            names += [f"{name}: 1-MAC{i + 1}" for i in range(len(fm))]
        if use_static:
            ref = np.array(list(meas.static.values()))
            scale = np.maximum(np.abs(ref), 1e-3)
            res.append(w.static * (p.static - ref) / scale)
            names += [f"{name}: static {k}" for k in meas.static]
        if use_xor:  # over all measured modes, so the vector keeps its length if a pair is lost
            pi = np.flatnonzero(ok)
            full = np.zeros((len(fm), len(fm)))
            full[np.ix_(pi, pi)] = _cross_orthogonality(realise(meas.shapes[pi]), p.sensor_shapes[p.paired[pi]]) \
                - np.eye(len(pi))
            res.append(w.orthogonality * full.ravel())
            names += [f"{name}: XOR[{a + 1},{b + 1}]" for a in range(len(fm)) for b in range(len(fm))]
        con, con_names = np.zeros(0), []
        if use_mac_min:
            con = np.where(ok, np.nan_to_num(p.mac) - w.mac_min, 0.0)
            con_names = [f"{name}: MAC{i + 1} >= {w.mac_min}" for i in range(len(fm))]
        block = Block(np.concatenate(res), names, con, con_names)
        if not gradient:
            return block
        solver = _solver(p)
        d = state_derivatives(self.par, self.work, x, p.state, p.tangent, changes=changes, solver=solver)
        need_vectors = use_mac or use_mac_min or use_xor
        terms = modal_terms(d, p.state, p.phi[:, idx], p.eigenvalues[idx], need_vectors)
        forms = d.quadratic(p.phi[:, idx])
        dlam = eigenvalue_derivatives(p.eigenvalues[idx], p.phi[:, idx], d, terms, forms)
        df = dlam / (8 * np.pi**2 * np.where(fa > 0, fa, 1.0))[:, None]
        rows = [np.where(ok[:, None], (w.frequency * wf / fm)[:, None] * df, 0.0)]
        shapes = self._shape_derivatives(p, meas, d, dlam, terms, forms[1], mac_only=not use_xor, solver=solver) \
            if need_vectors else None
        dmac = self._mac_derivatives(meas, shapes, mac_only=not use_xor) if (use_mac or use_mac_min) else None
        if use_mac:
            rows.append(np.where(ok[:, None], -w.mac * dmac, 0.0))
        if use_static:
            rows.append(w.static * self._static_derivatives(p, meas, d) / scale[:, None])
        if use_xor:
            pi = np.flatnonzero(ok)
            A = np.column_stack([shapes[i][0] for i in pi])
            dA = np.stack([shapes[i][1] for i in pi], axis=1)  # (n_sensors, n_pairs, n_var)
            full = np.zeros((len(fm), len(fm), len(self.par)))
            full[np.ix_(pi, pi)] = _cross_orthogonality_derivative(realise(meas.shapes[pi]), A, dA).reshape(
                len(pi), len(pi), -1)
            rows.append(w.orthogonality * full.reshape(len(fm) ** 2, -1))
        block.jacobian = np.vstack(rows)
        block.constraint_jacobian = np.where(ok[:, None], dmac, 0.0) if use_mac_min else np.zeros((0, len(self.par)))
        return block

    def frequency_weights(self, meas: Measured) -> np.ndarray:
        """1, or (median relative scatter / relative scatter) of each mode when standard deviations are given."""
        if not self.objective.use_std or meas.frequency_std_hz is None or not np.any(meas.frequency_std_hz > 0):
            return np.ones(len(meas.frequencies_hz))
        rel = meas.frequency_std_hz / meas.frequencies_hz
        floor = np.median(rel[rel > 0])
        return floor / np.maximum(rel, floor * 0.1)

    def _shape_derivatives(self, p: ConfigurationPoint, meas: Measured, d, dlam, terms=None, dmass=None,
                           mac_only: bool = False, solver=None) -> dict:
        """{measured mode i: (a, da)}: the paired analytical shape at the sensors (n_sensors,) and its
        derivative (n_sensors, n_var), the shape moving with p (Nelson) and the sensors turning with
        the structure; mac_only: da is the MAC's derivative (1, n_var) instead, by the adjoint of
        the MAC's gradient with respect to the shape (two solves per mode whatever the number of
        variables)."""
        system = p.state.system
        T = system.transformation(p.state.positions, p.state.rotations) if system.has_links else None
        S = meas.sensors.matrix(p.state.node_ids, p.state, follow=self.follow_sensors)
        S = (S @ T).tocsr() if T is not None else S[:, np.flatnonzero(system.dof_map >= 0)]  # on reduced DOFs
        turn = self.follow_sensors and np.any(d.du)
        if turn:  # the sensors turn with their nodes as the state moves with p
            rows = meas.sensors.rows(p.state.node_ids)
            spins = system.expand(d.du, T).reshape(system.n_nodes, 6, -1)[rows, 3:]  # (n_sensors, 3, n_var)
        out = {}
        n_var = d.du.shape[1]
        parts = {}
        for i, j in enumerate(p.paired):
            if j < 0:
                continue
            a = S @ p.phi[:, j]
            g = _mac_gradient(meas.shapes[i], a)[None, :] if mac_only else None
            parts[i] = (a, g, S if g is None else np.asarray(S.T @ g[0])[None, :])
        adjoints = _adjoints(solver, p, parts, n_var)
        for i, (a, g, project) in parts.items():
            j = p.paired[i]
            phi = p.phi[:, j]
            da = eigenvector_derivatives(p.K, p.M, p.eigenvalues[j], phi, dlam[i], d, terms, mode=i,
                                         dmass=None if dmass is None else dmass[i], project=project,
                                         solver=solver, index=int(j), adjoint=adjoints.get(i))
            if turn:
                turning = np.einsum("sc,sck->sk", meas.sensors.turning(p.state.node_ids, p.state,
                                                                        system.expand(phi, T)), spins)
                da += turning if g is None else g @ turning
            out[i] = (a, da)
        return out

    def _mac_derivatives(self, meas: Measured, shapes: dict, mac_only: bool = False) -> np.ndarray:
        """(n_measured, n_var) dMAC/dp of each pair from the analytical shapes' derivatives (or the
        MAC's own with mac_only)."""
        out = np.zeros((len(meas.frequencies_hz), len(self.par)))
        for i, (a, da) in shapes.items():
            out[i] = da.reshape(-1) if mac_only else _mac_gradient(meas.shapes[i], a) @ da
        return out

    def _static_derivatives(self, p: ConfigurationPoint, meas: Measured, d) -> np.ndarray:
        system = p.state.system
        T = system.transformation(p.state.positions, p.state.rotations) if system.has_links else None
        du = system.expand(d.du, T).reshape(system.n_nodes, 6, -1)
        rows = [du[p.state.node(node), int(c) - 1] for (node, c) in meas.static]
        return np.array(rows)


SHARED_FACTOR_MIN_DOF = 2000  # below: Nelson's per-mode factorisations (cheap there, and bit for bit as before)


def _solver(p: ConfigurationPoint):
    """The configuration's ModeSolver at this point (one factorisation for the state's and every
    paired mode's derivative), or None for small systems (SHARED_FACTOR_MIN_DOF: their per-mode
    LUs take milliseconds, and their results stay those of the direct solves) and where the modes
    do not allow it (not mass-normalised, a singular shift): each solve then factorises its own
    matrix (the tangent; Nelson's pinned K - lambda M per mode)."""
    if p.K.shape[0] < SHARED_FACTOR_MIN_DOF:
        return None
    try:
        return ModeSolver(p.K, p.M, p.eigenvalues, p.phi)
    except SolverError:
        return None


def _adjoints(solver, p: ConfigurationPoint, parts: dict, n_var: int) -> dict:
    """{measured mode: adjoint vectors G_i P^T} of the modes whose shape derivative is projected by
    the adjoint, all in one block solve ({} without a solver, or where the block fails: each mode
    then solves its own)."""
    if solver is None or not parts:
        return {}
    try:
        cols, modes, where = [], [], {}
        for i, (_, _, P) in parts.items():
            if P.shape[0] + 1 < n_var:
                Pt = P.T.toarray() if sp.issparse(P) else np.asarray(P, float).T
                where[i] = (sum(c.shape[1] for c in cols), Pt.shape[1])
                cols.append(Pt)
                modes += [int(p.paired[i])] * Pt.shape[1]
        W = solver.solve(np.hstack(cols), np.array(modes)) if cols else None
    except SolverError:
        return {}
    return {i: W[:, s:s + k] for i, (s, k) in where.items()}


def _mac_gradient(m: np.ndarray, a: np.ndarray) -> np.ndarray:
    """(n_sensors,) d MAC(m, a) / d a of a measured (real or complex) shape m and a real analytical a."""
    c = np.vdot(m, a)
    mm = np.real(np.vdot(m, m))
    aa = float(a @ a)
    mac = abs(c) ** 2 / (mm * aa)
    return 2 * np.real(np.conj(c) * m.conj()) / (mm * aa) - 2 * mac * a / aa


def _xor_parts(Psi: np.ndarray, A: np.ndarray):
    """Q = pinv(A) Psi^T: the measured shapes' coordinates in the paired analytical shapes at the
    sensors (the SEREP mass of those modes: Q is the cross-orthogonality before scaling)."""
    AtA_inv = np.linalg.inv(A.T @ A)
    P = AtA_inv @ A.T
    return P, AtA_inv, P @ Psi.T


def _cross_orthogonality(Psi: np.ndarray, A: np.ndarray) -> np.ndarray:
    """(n_pairs, n_pairs) cross-orthogonality of the measured shapes Psi (n, n_sensors) with the paired
    analytical ones (A: (n_pairs, n_sensors)) through the SEREP-reduced mass of the paired analytical
    modes: row i = measured mode i's coordinates in the analytical modes, scaled to unit generalised
    mass and signed so its diagonal term is positive (1 on the diagonal, 0 off it for a perfect model)."""
    _, _, Q = _xor_parts(Psi, A.T)
    Q = Q.T  # (n_measured, n_pairs)
    norm = np.linalg.norm(Q, axis=1, keepdims=True)
    sign = np.sign(np.diag(Q))[None, :]  # each analytical shape's arbitrary sign, turned to its pair's
    return sign * Q / np.where(norm > 0, norm, 1.0)


def _cross_orthogonality_derivative(Psi: np.ndarray, A: np.ndarray, dA: np.ndarray) -> np.ndarray:
    """d(cross-orthogonality).ravel() / dp ((n_pairs^2, n_var)) from the paired analytical shapes'
    derivatives dA (n_sensors, n_pairs, n_var): d pinv(A) = -pinv(A) dA pinv(A) + (A^T A)^-1 dA^T (I - A pinv(A))."""
    P, AtA_inv, Q = _xor_parts(Psi, A)
    resid = Psi.T - A @ Q  # (n_sensors, n_measured)
    n = Q.shape[1]
    out = np.empty((n * n, dA.shape[2]))
    Qt = Q.T
    norm = np.linalg.norm(Qt, axis=1, keepdims=True)
    sign = np.sign(np.diag(Qt))[None, :]
    for k in range(dA.shape[2]):
        dAk = dA[:, :, k]
        dQ = -P @ dAk @ Q + AtA_inv @ dAk.T @ resid
        dQt = dQ.T
        dnorm = np.sum(Qt * dQt, axis=1, keepdims=True) / norm
        out[:, k] = (sign * (dQt / norm - Qt * dnorm / norm**2)).ravel()
    return out

