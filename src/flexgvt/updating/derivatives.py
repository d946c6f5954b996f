"""Derivatives of a configuration's equilibrium and modes with respect to the design variables.

At an equilibrium R(u, p) = 0 of the reduced residual:

    du/dp  = -K^-1 dR/dp                         (one factorisation of the tangent K, any number of p)
    dK/dp|total = dK/dp|u + (dK/du)[du/dp]       (and the same for the mass matrix M)
    d lambda_i  = phi_i^T (dK - lambda_i dM) phi_i        (mass-normalised phi_i)
    d phi_i     : Nelson's method, (K - lambda_i M) v = -(dK - lambda_i dM - d lambda_i M) phi_i

dR/dp, dK/dp and dM/dp at the fixed state come from fem.sensitivity.value_derivative: the
assembly is linear in what a variable changes (beam kernel coefficients, mass per length and
inertia, point masses, spring and cord rates), so it is evaluated with the derivative of those
values on the affected items only; a beam group's values are differentiated by a four-point rule
on the section formulas (truncation ~1e-12), masses (linear) and their offsets (quadratic) by an
exact central difference, cord attachment offsets by a four-point rule on the cord's forces.

The state part (dK/du)[du/dp] of the modes' derivatives comes from element-level derivatives with
exploded nodes (fem.sensitivity.modal_state_terms: 48 kernel calls whatever the number of
variables); systems with rigid or interpolation links use a four-point difference of the tangent
along each du/dp instead (state_direction), h |du| = 1e-3 rad or 1e-3 of the structure's size.

Accuracy limit: du solves K du = -dR, and K of a flexible structure is ill-conditioned (cond
~1e9-1e10: axial EA/L against bending and suspension stiffness); the round-off of its stiff
entries leaves ~eps cond(K) relative errors in du, which the stress stiffening of the stiff
members turns into up to ~5e-5 (clamped strip under self-weight, first mode) or ~3e-4 (the
3.66 m strip on 5 N/m cords, pitch mode) of a pre-stressed mode's slope. Refining du with the
nonlinear residual's directional difference made it worse (that difference is itself
truncation-bound by the members' stretch along straight lines in the state).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolverError
from ..fem.sensitivity import ValueChange, modal_state_terms, value_derivative
from ..fem.system import group_values
from .variables import Parametrisation

_EXACT_STEP = 0.25  # normalised step of the two-point rule where the assembly is linear or quadratic
_SECTION_STEP = 1e-3  # of the four-point rule on a beam group's values (section properties are not linear)
_OFFSET_STEP = 1e-4  # [m] of the four-point rule on a cord's attachment offset
_STATE_STEP = 1e-3  # largest rotation [rad] or translation / size of the state perturbation (four-point rule)


@dataclass
class StateDerivatives:
    """Total derivatives at one configuration's state, per design variable k: du[:, k] (reduced),
    dK[k] and dM[k] (reduced; dK of the consistent tangent, whose symmetric part the modes use:
    quadratic forms phi^T dK phi need no symmetrising)."""

    du: np.ndarray
    dK: list
    dM: list
    includes_state: bool = True  # dK, dM hold the change along du too (else: modal_terms)


def value_change(par: Parametrisation, model, x: np.ndarray, k: int, configuration: str) -> ValueChange:
    """What variable k changes in the compiled values of ``configuration``, per unit of its
    normalised value, with ``model`` (the working copy) at design point x."""
    b = par.bindings[k]
    v = b.variable
    if v.kind == "beam":
        starts = np.cumsum([0] + [len(g.ids) for g in model.beams])
        rows, dsec, drhoA, drhoI = [], [], [], []
        h = _SECTION_STEP
        for idx in b.indices:
            group = model.beams[idx]
            L = np.linalg.norm(np.diff(model.xyz[model.index_of(group.nodes)], axis=1)[:, 0], axis=1)
            acc = None
            for off, w in zip((2 * h, h, -h, -2 * h), (-1 / 12, 8 / 12, -8 / 12, 1 / 12)):
                mat, sec = par.beam_entities(group, b, idx, x[k] + off)
                vals = group_values(mat, sec, group.rotary_inertia, L)
                acc = [w / h * a for a in vals] if acc is None else [c + w / h * a for c, a in zip(acc, vals)]
            rows.append(np.arange(starts[idx], starts[idx + 1]))
            dsec.append(acc[0])
            drhoA.append(acc[1])
            drhoI.append(acc[2])
        return ValueChange(beams=(np.concatenate(rows), np.vstack(dsec), np.concatenate(drhoA), np.vstack(drhoI)))
    if v.kind == "mass" and v.per_configuration:
        mine = [i for c, i in b.indices if c == configuration]
        if not mine:
            return ValueChange()
        h = _EXACT_STEP
        values = [par.mass_entities(model, b, x[k] + off, configuration) for off in (h, -h)]
        # The system stores the model's masses first, then the configuration's own.
        return ValueChange(masses=(len(model.masses) + np.asarray(mine, int), values[0], values[1], 1 / (2 * h)))
    if v.kind == "mass":
        h = _EXACT_STEP
        values = [par.mass_entities(model, b, x[k] + off) for off in (h, -h)]
        return ValueChange(masses=(np.asarray(b.indices, int), values[0], values[1], 1 / (2 * h)))
    if v.kind == "spring":
        if not (v.attribute == "stiffness" or v.attribute[0] == "k"):
            return ValueChange()  # dampers change neither the equilibrium nor the undamped modes
        base = np.array([par.model.springs[i].stiffness for i in b.indices], float)
        if v.attribute[1:].isdigit():
            mask = np.zeros(6)
            mask[int(v.attribute[1]) - 1] = 1.0
            base = base * mask
        return ValueChange(springs=(np.asarray(b.indices, int), base))
    mine = [(i, k0) for (c, i), k0 in zip(b.indices, b.initial) if c == configuration]
    if not mine or v.attribute == "damping":
        return ValueChange()
    rows = np.array([i for i, _ in mine], int)
    if v.attribute == "along":  # attachment position along the element [m]: four-point rule on the fraction
        cords = par.configurations[configuration].suspension
        xyz = {int(n): p for n, p in zip(model.node_ids, model.xyz)}
        span = np.array([np.linalg.norm(xyz[cords[i].node_b] - xyz[cords[i].node]) for i in rows])
        current = np.array([k0 for _, k0 in mine]) + (x[k] - 1.0) * v.scale
        h = _OFFSET_STEP / v.scale
        samples = [((current + off * v.scale) / span, w / h)
                   for off, w in zip((2 * h, h, -h, -2 * h), (-1 / 12, 8 / 12, -8 / 12, 1 / 12))]
        return ValueChange(cord_along=(rows, samples))
    if v.shifts:  # attachment offset [m]: four-point rule on the cord's forces and tangent
        base = np.array([par.configurations[configuration].suspension[i].offset for i in rows], float)
        current = base.copy()
        axis = "xyz".index(v.attribute[-1])
        current[:, axis] = np.array([k0 for _, k0 in mine]) + (x[k] - 1.0) * v.scale
        h = _OFFSET_STEP / v.scale  # normalised step
        samples = []
        for off, w in zip((2 * h, h, -h, -2 * h), (-1 / 12, 8 / 12, -8 / 12, 1 / 12)):
            o = current.copy()
            o[:, axis] += off * v.scale
            samples.append((o, w / h))
        return ValueChange(cord_offsets=(rows, samples))
    return ValueChange(cords=(rows, np.array([k0 for _, k0 in mine], float)))


def partial_derivatives(par: Parametrisation, model, x: np.ndarray, state, k: int, change: ValueChange | None = None):
    """dR/dp_k (reduced), dK/dp_k, dM/dp_k at ``state`` (held fixed), p_k the normalised variable;
    ``model`` is the working model at design point x (left unchanged); change: variable k's
    ValueChange when already known (it is the same in every configuration but for cords)."""
    if change is None:
        change = value_change(par, model, x, k, state.configuration.name)
    return value_derivative(state.system, state.positions, state.rotations, state.load_factor, change)


def shared_changes(par: Parametrisation, model, x: np.ndarray) -> list:
    """Every variable's ValueChange that does not depend on the configuration (None for those on
    configuration items)."""
    return [None if b.variable.per_configuration else value_change(par, model, x, k, "") for k, b in enumerate(par.bindings)]


def state_direction(system, state, v: np.ndarray):
    """(dK/du)[v] and (dM/du)[v] by a four-point central difference along the reduced direction v."""
    pos, rot, lam = state.positions, state.rotations, state.load_factor
    size = max(float(np.ptp(system.cm.xyz, axis=0).max()), 1e-3)
    vt = np.abs(v[~system.rotation_mask]).max(initial=0.0) / size
    vr = np.abs(v[system.rotation_mask]).max(initial=0.0)
    scale = max(vt, vr)
    if scale == 0:
        n = system.n_free
        return sp.csc_matrix((n, n)), sp.csc_matrix((n, n))
    h = _STATE_STEP / scale
    pattern = system.pattern
    dK = dM = None
    for off, w in zip((2 * h, h, -h, -2 * h), (-1 / 12, 8 / 12, -8 / 12, 1 / 12)):
        xs, Rs = system.update(pos, rot, off * v)
        if system.has_links:
            K = system.evaluate(xs, Rs, lam).tangent
            M = system.mass_matrix(xs, Rs)
            dK = (w / h) * K if dK is None else dK + (w / h) * K
            dM = (w / h) * M if dM is None else dM + (w / h) * M
            continue
        # One pattern: combine the stored entries, build one matrix at the end.
        ev = system.evaluate(xs, Rs, lam, assemble=False)
        K, M = pattern.data(ev.blocks), pattern.data(system._mass_values(xs, Rs))
        dK = (w / h) * K if dK is None else dK + (w / h) * K
        dM = (w / h) * M if dM is None else dM + (w / h) * M
    if system.has_links:
        return dK.tocsc(), dM.tocsc()
    return pattern.matrix(dK), pattern.matrix(dM)


def state_derivatives(par: Parametrisation, model, x: np.ndarray, state, tangent: sp.csc_matrix,
                      per_direction: bool | None = None, changes: list | None = None) -> StateDerivatives:
    """du/dp and the partial dK/dp, dM/dp of every variable at ``state``.

    tangent: the (full, possibly unsymmetric) reduced tangent at ``state``, factorised once.
    The tangent's and mass matrix's change along du/dp is added per variable (four-point
    difference along each du, `state_direction`) only for systems with links (per_direction=None)
    or when asked; otherwise `modal_terms` gives it for the modes, whatever the number of variables."""
    system = state.system
    n = len(par)
    changes = changes or [None] * n
    partial = [partial_derivatives(par, model, x, state, k, changes[k]) for k in range(n)]
    dR = np.column_stack([p[0] for p in partial])
    if np.any(dR):
        try:
            lu = spla.splu(tangent.tocsc())
            du = -lu.solve(dR)
            du = np.atleast_2d(du.T).T if du.ndim == 1 else du
        except RuntimeError as exc:
            raise SolverError(f"configuration '{state.configuration.name}': the tangent at the equilibrium is "
                              f"singular ({exc}), so the state's derivative is undefined; restrain the "
                              "mechanism (a suspension or a boundary condition)") from None
    else:
        du = np.zeros((system.n_free, n))
    per_direction = system.has_links if per_direction is None else per_direction
    dK, dM = [], []
    for k in range(n):
        Kk, Mk = partial[k][1], partial[k][2]
        if per_direction and np.any(du[:, k]):
            Ku, Mu = state_direction(system, state, du[:, k])
            Kk, Mk = _add(Kk, Ku), _add(Mk, Mu)
        dK.append(Kk)
        dM.append(Mk)
    return StateDerivatives(du, dK, dM, includes_state=per_direction or not np.any(du))


def modal_terms(d: StateDerivatives, state, phi: np.ndarray, lam: np.ndarray, vectors: bool):
    """The state part of the modes' derivatives (fem.sensitivity.modal_state_terms), or None when
    ``d`` already holds it."""
    if d.includes_state:
        return None
    return modal_state_terms(state.system, state.positions, state.rotations, state.load_factor, phi, lam, vectors)


def _add(A: sp.csc_matrix, B: sp.csc_matrix) -> sp.csc_matrix:
    """A + B, by their stored entries when they share one pattern (the system's)."""
    if A.nnz == B.nnz and A.shape == B.shape and np.array_equal(A.indptr, B.indptr) and \
            np.array_equal(A.indices, B.indices):
        return sp.csc_matrix((A.data + B.data, A.indices, A.indptr), shape=A.shape)
    return (A + B).tocsc()


def eigenvalue_derivatives(lam: np.ndarray, phi: np.ndarray, d: StateDerivatives, terms=None) -> np.ndarray:
    """(n_modes, n_var) d lambda / dp for mass-normalised reduced eigenvectors phi (n_free, n_modes)."""
    out = np.empty((len(lam), len(d.dK)))
    for k, (Kk, Mk) in enumerate(zip(d.dK, d.dM)):
        out[:, k] = np.einsum("ij,ij->j", phi, Kk @ phi) - lam * np.einsum("ij,ij->j", phi, Mk @ phi)
    if terms is not None:
        out += (terms.gK - lam[:, None] * terms.gM) @ d.du
    return out


def eigenvector_derivatives(K: sp.csc_matrix, M: sp.csc_matrix, lam: float, phi: np.ndarray, dlam: np.ndarray,
                            d: StateDerivatives, terms=None, mode: int = 0) -> np.ndarray:
    """(n_free, n_var) d phi / dp of one mass-normalised mode by Nelson's method (distinct eigenvalue).

    K: the symmetric tangent, M: the mass matrix the mode solves, lam its eigenvalue; terms and
    mode: the state part (ModalStateTerms) and this mode's row in it."""
    n = len(phi)
    k = int(np.argmax(np.abs(phi) * np.sqrt(np.abs(M.diagonal()) + 1e-300)))
    keep = np.r_[0:k, k + 1:n]
    A = (K - lam * M).tocsc()[keep][:, keep]
    rhs = np.column_stack([-(0.5 * (Kk @ phi + Kk.T @ phi) - lam * (Mk @ phi) - dl * (M @ phi))
                           for Kk, Mk, dl in zip(d.dK, d.dM, dlam)])
    dmass = np.array([phi @ (Mk @ phi) for Mk in d.dM])
    if terms is not None:
        rhs -= terms.H[mode] @ d.du
        dmass += terms.gM[mode] @ d.du
    try:
        sol = spla.splu(A.tocsc()).solve(rhs[keep])
    except RuntimeError as exc:
        raise SolverError(f"mode shape derivative: K - lambda M is singular after removing one DOF ({exc}); the "
                          "eigenvalue is repeated, so its shape derivative is not unique") from None
    v = np.zeros((n, len(dlam)))
    v[keep] = sol.reshape(len(keep), -1)
    Mphi = M @ phi
    c = -(Mphi @ v) - 0.5 * dmass  # keeps phi^T M phi = 1
    return v + phi[:, None] * c[None, :]


def sensor_matrix_direction(sensors, state, v: np.ndarray, follow: bool):
    """d(sensor matrix)/dp along the reduced state derivative v (sensors turn with the nodes they
    sit on when they follow the structure); zero otherwise."""
    system = state.system
    if not follow or not np.any(v):
        return None
    scale = max(np.abs(v[system.rotation_mask]).max(initial=0.0), 1e-300)
    h = _STATE_STEP / scale
    out = []
    for sign in (1.0, -1.0):
        xs, Rs = system.update(state.positions, state.rotations, sign * h * v)
        out.append(sensors.matrix(state.node_ids, replace(state, positions=xs, rotations=Rs), follow=True))
    return (out[0] - out[1]) / (2 * h)


__all__ = ["StateDerivatives", "eigenvalue_derivatives", "eigenvector_derivatives",
           "partial_derivatives", "sensor_matrix_direction", "state_derivatives", "state_direction"]
