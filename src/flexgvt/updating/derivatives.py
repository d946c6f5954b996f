"""Derivatives of a configuration's equilibrium and modes with respect to the design variables.

At an equilibrium R(u, p) = 0 of the reduced residual:

    du/dp  = -K^-1 dR/dp                         (one factorisation of the tangent K, any number of p)
    dK/dp|total = dK/dp|u + (dK/du)[du/dp]       (and the same for the mass matrix M)
    d lambda_i  = phi_i^T (dK - lambda_i dM) phi_i        (mass-normalised phi_i)
    d phi_i     : Nelson's method, (K - lambda_i M) v = -(dK - lambda_i dM - d lambda_i M) phi_i

dR/dp, dK/dp and dM/dp at the fixed state: the assembly is linear in what a variable changes
(beam kernel coefficients, mass per length and inertia, point masses, spring and cord rates). Beam
variables go through fem.beam_basis: element blocks per unit beam value, evaluated once per state,
combined with the sparse matrices of every variable's value derivatives, so their cost does not
grow with their number; no per-variable matrix is assembled (the modes need only quadratic forms
and products with the mode shapes). Other variables use fem.sensitivity.value_derivative on the
items they change. A beam group's values are differentiated by complex step (E, G, rho, a
rectangle's width and height, all variables in one vectorised evaluation) or by a four-point rule
on other section formulas (truncation ~1e-12), masses (linear) and their offsets (quadratic) by an
exact central difference, cord attachment offsets by a four-point rule on the cord's forces.

The state part (dK/du)[du/dp] of the modes' derivatives comes from element-level derivatives with
exploded nodes (fem.sensitivity.modal_state_terms: 36 kernel calls whatever the number of
variables), with rigid links' own terms in closed form (linear constraints need none: their map is
constant); systems with interpolation links, and shell systems with fewer variables than the 84
kernel passes of a quad's element-level derivatives would cost (_directions_cheaper), use a
four-point difference of the tangent along each du/dp instead (state_direction), h |du| = 1e-3 rad
or 1e-3 of the structure's size. Mode-shape derivatives are projected on what the objective reads
(the sensors, or one MAC per mode) and solved by the adjoint when that has fewer rows than there
are variables.

Accuracy limit: du solves K du = -dR, and K of a flexible structure is ill-conditioned (cond
~1e9-1e10: axial EA/L against bending and suspension stiffness); the round-off of its stiff
entries leaves ~eps cond(K) relative errors in du, which the stress stiffening of the stiff
members turns into up to ~5e-5 (clamped strip under self-weight, first mode) or ~3e-4 (the
3.66 m strip on 5 N/m cords, pitch mode) of a pre-stressed mode's slope. Refining du with the
nonlinear residual's directional difference made it worse (that difference is itself
truncation-bound by the members' stretch along straight lines in the state).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolverError
from ..fem.beam_basis import N_VALUES, beam_basis, local_unit_masses, mass_values
from ..fem.linsolve import superlu
from ..fem.sensitivity import (ValueChange, closed_form_links, groups_derivatives, link_force_blocks,
                               modal_state_terms, value_derivative)
from ..fem.system import compile_model, group_values
from ..model import RectangularSection
from .variables import Parametrisation, shell_property

_EXACT_STEP = 0.25  # normalised step of the two-point rule where the assembly is linear or quadratic
_SECTION_STEP = 1e-3  # of the four-point rule on a beam group's values (section properties are not linear)
_OFFSET_STEP = 1e-4  # [m] of the four-point rule on a cord's attachment offset
_STATE_STEP = 1e-3  # largest rotation [rad] or translation / size of the state perturbation (four-point rule)


@dataclass
class DesignChanges:
    """What every variable changes in the compiled values at one design point.

    changes[k]: variable k's ValueChange where it does not depend on the configuration (None for
    variables on configuration items); beam variables also as sparse (8 k, n_var) matrices of the
    value derivatives of the elements ``rows`` they reach (DK: kernel coefficients, DM: mass values,
    fem.beam_basis order), ``batched`` marking them."""

    changes: list
    rows: np.ndarray
    DK: sp.csc_matrix
    DM: sp.csc_matrix
    batched: np.ndarray
    _local: dict = field(default_factory=dict, repr=False)

    def local_units(self, beams) -> np.ndarray:
        """The rows' element-axes mass matrices per unit mass value (the same for every configuration)."""
        if "units" not in self._local:
            self._local["units"] = local_unit_masses(beams, self.rows)
        return self._local["units"]

    @classmethod
    def of(cls, changes: list) -> "DesignChanges":
        n = len(changes)
        batched = np.array([c is not None and c.beams_only for c in changes], bool)
        rows = np.unique(np.concatenate([np.asarray(changes[k].beams[0], int) for k in np.flatnonzero(batched)]
                                        + [np.zeros(0, int)]))
        entries = {"K": ([], [], []), "M": ([], [], [])}
        for k in np.flatnonzero(batched):
            r, dcoeff, drhoA, drhoI = changes[k].beams
            pos = np.searchsorted(rows, np.asarray(r, int))
            for key, values in (("K", np.asarray(dcoeff, float)), ("M", mass_values(drhoA, drhoI))):
                at = (N_VALUES * pos[:, None] + np.arange(N_VALUES)[None, :]).ravel()
                v = values.ravel()
                nz = v != 0
                entries[key][0].append(at[nz])
                entries[key][1].append(np.full(int(nz.sum()), k))
                entries[key][2].append(v[nz])
        shape = (N_VALUES * len(rows), n)

        def matrix(key):
            r, c, v = (np.concatenate(a + [np.zeros(0, t)]) for a, t in zip(entries[key], (int, int, float)))
            return sp.csc_matrix((v, (r, c)), shape=shape)

        return cls(changes, rows, matrix("K"), matrix("M"), batched)


@dataclass
class StateDerivatives:
    """Total derivatives at one configuration's state, per design variable k: du[:, k] (reduced),
    and the partial dK/dp_k, dM/dp_k (reduced; dK of the consistent tangent) held as ``matrices``
    {k: (dK, dM)} for variables outside the beam basis, and as basis @ (DK, DM) columns for the
    beam variables. The modes use them only through ``quadratic``, ``products`` and ``bilinear``.
    includes_state: dK, dM hold the change along du too (else: modal_terms)."""

    du: np.ndarray
    matrices: dict
    system: object
    basis: object | None = None
    DK: sp.csc_matrix | None = None
    DM: sp.csc_matrix | None = None
    includes_state: bool = True
    T: sp.csr_matrix | None = None  # rigid links: the full <- reduced map at the state
    dr_full: np.ndarray | None = None  # rigid links: the beam variables' d(residual) over all DOFs (6 n, n_var)
    _rotations: np.ndarray | None = None  # rigid links: the nodes' rotations at the state
    _cache: dict = field(default_factory=dict, repr=False)

    def _full(self, v: np.ndarray) -> np.ndarray:
        return self.system.expand(v, self.T)

    def quadratic(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(m, n_var) phi_i^T dK_k phi_i and phi_i^T dM_k phi_i of reduced modes phi (n_free, m)."""
        m, n = phi.shape[1], self.du.shape[1]
        qK, qM = np.zeros((m, n)), np.zeros((m, n))
        if self.basis is not None:
            full = self._full(phi)
            eK, eM = self.basis.quadratic(self.basis.element_values(full))
            qK += np.asarray(self.DK.T @ eK).T
            qM += np.asarray(self.DM.T @ eM).T
            if self.T is not None:  # the links' geometric term carries the change of the link forces
                for i in range(m):
                    qK[i] += self._link_forms(full[:, i], full[:, i:i + 1])[0]
        for k, (Kk, Mk) in self.matrices.items():
            qK[:, k] = np.einsum("ij,ij->j", phi, Kk @ phi)
            qM[:, k] = np.einsum("ij,ij->j", phi, Mk @ phi)
        return qK, qM

    def products(self, phi: np.ndarray, lam: float) -> np.ndarray:
        """(n_free, n_var) (sym(dK_k) - lam dM_k) phi of one reduced mode phi (n_free,)."""
        n_free, n = self.du.shape
        out = np.zeros((n_free, n))
        if self.basis is not None:
            full = self._full(phi)
            links = self.T is not None
            G = self.basis.products(self.basis.element_values(full), lam, full=links)
            out += (self.T.T @ (G @ self.D)).toarray() if links else (G @ self.D).toarray()
            if links:  # the links' geometric term: B f at the independent nodes' rotations
                ind, r, tied, trans = self._links
                B = link_force_blocks(r, tied, full.reshape(-1, 6)[ind, 3:])
                rot = self.system.dof_map[6 * ind[:, None] + 3 + np.arange(3)]
                contrib = B @ self.dr_full[trans]  # (k, 3, n_var)
                keep = rot >= 0
                np.add.at(out, rot[keep], contrib[keep])
        for k, (Kk, Mk) in self.matrices.items():
            out[:, k] = 0.5 * (Kk @ phi + Kk.T @ phi) - lam * (Mk @ phi)
        return out

    def bilinear(self, phi: np.ndarray, W: np.ndarray, lam: float) -> np.ndarray:
        """(n_out, n_var) W^T (sym(dK_k) - lam dM_k) phi of one reduced mode phi (n_free,) and
        reduced vectors W (n_free, n_out), without forming the products."""
        out = np.zeros((W.shape[1], self.du.shape[1]))
        if self.basis is not None:
            b = self.basis
            full, Wf = self._full(phi), self._full(W)
            out += np.asarray(self.D.T @ b.bilinear(b.element_values(full), b.element_values(Wf), lam)).T
            if self.T is not None:
                out += self._link_forms(full, Wf)
        for k, (Kk, Mk) in self.matrices.items():
            out[:, k] = W.T @ (0.5 * (Kk @ phi + Kk.T @ phi) - lam * (Mk @ phi))
        return out

    @property
    def _links(self):
        """(independent nodes, rotated offsets, tied translations, the dependents' translation DOFs)."""
        if "links" not in self._cache:
            deps, ind, r = self.system.link_offsets(self._rotations)
            self._cache["links"] = (ind, r, self.system.cm.link_dofs[deps, :3].astype(float),
                                    6 * deps[:, None] + np.arange(3))
        return self._cache["links"]

    def _link_forms(self, full: np.ndarray, Wf: np.ndarray) -> np.ndarray:
        """(n_out, n_var) w^T sym(G(dr_k)) phi of the links' geometric term, for a mode over all
        DOFs ``full`` (6 n,) and vectors Wf (6 n, n_out) over all DOFs."""
        ind, r, tied, trans = self._links
        B = link_force_blocks(r, tied, full.reshape(-1, 6)[ind, 3:])  # (k, 3, 3)
        wa = Wf.reshape(-1, 6, Wf.shape[1])[ind, 3:]  # (k, 3, n_out)
        v = np.swapaxes(B, 1, 2) @ wa  # (k, 3 force comps, n_out)
        return v.reshape(-1, Wf.shape[1]).T @ self.dr_full[trans.ravel()]

    @property
    def D(self) -> sp.csr_matrix:
        """(16 k, n_var): DK over DM, in the order of BeamBasis.products' columns."""
        if "D" not in self._cache:
            self._cache["D"] = _interleave(self.DK, self.DM)
        return self._cache["D"]


def _interleave(DK: sp.csc_matrix, DM: sp.csc_matrix) -> sp.csr_matrix:
    """Rows (e, 0..7) of DK then (e, 0..7) of DM per element e: (16 k, n) from two (8 k, n)."""
    k = DK.shape[0] // N_VALUES
    order = (np.arange(k)[:, None] * N_VALUES + np.arange(N_VALUES)[None, :])
    perm = np.concatenate([order, order + k * N_VALUES], axis=1).ravel()
    return sp.vstack([DK, DM]).tocsr()[perm]


def _beam_changes(par: Parametrisation, model, x: np.ndarray, ks) -> dict:
    """{k: ValueChange} of beam variables ks: one vectorised complex-step evaluation for all those
    it covers (E, G, rho; a rectangle's width and height), a four-point rule on the section
    formulas for the others."""
    starts = np.cumsum([0] + [len(g.ids) for g in model.beams])
    lengths = compile_model(model).beams.L0  # cached for the model's revision
    items, where = [], []
    for k in ks:
        b = par.bindings[k]
        for idx in b.indices:
            group = model.beams[idx]
            if _complex_step_applies(group, b.variable.attribute):
                items.append((group, b.variable.attribute, lengths[starts[idx]:starts[idx + 1]]))
                where.append((k, idx))
    exact = dict(zip(where, groups_derivatives(items)))
    out = {}
    h = _SECTION_STEP
    for k in ks:
        b = par.bindings[k]
        v = b.variable
        rows, dsec, drhoA, drhoI = [], [], [], []
        for idx in b.indices:
            group = model.beams[idx]
            if (k, idx) in exact:
                dp = v.scale if v.shifts else b.initial[b.indices.index(idx)]
                acc = [dp * a for a in exact[(k, idx)]]
            else:  # any section formula: four-point rule
                L = lengths[starts[idx]:starts[idx + 1]]
                acc = None
                for off, w in zip((2 * h, h, -h, -2 * h), (-1 / 12, 8 / 12, -8 / 12, 1 / 12)):
                    mat, sec = par.beam_entities(group, b, idx, x[k] + off)
                    vals = group_values(mat, sec, group.rotary_inertia, L)
                    acc = [w / h * a for a in vals] if acc is None else [c + w / h * a for c, a in zip(acc, vals)]
            rows.append(np.arange(starts[idx], starts[idx + 1]))
            dsec.append(acc[0])
            drhoA.append(acc[1])
            drhoI.append(acc[2])
        out[k] = ValueChange(beams=(np.concatenate(rows), np.vstack(dsec), np.concatenate(drhoA), np.vstack(drhoI)))
    return out


def value_change(par: Parametrisation, model, x: np.ndarray, k: int, configuration: str) -> ValueChange:
    """What variable k changes in the compiled values of ``configuration``, per unit of its
    normalised value, with ``model`` (the working copy) at design point x."""
    b = par.bindings[k]
    v = b.variable
    if v.kind == "beam":
        return _beam_changes(par, model, x, [k])[k]
    if v.kind == "shell":
        # A four-point rule in the property value: the sections are polynomial in thickness (t, t^3)
        # and rational in E and G (through nu), so the rule is exact to round-off for t, rho, nsm.
        h = _SECTION_STEP
        item = {}
        for g, p0 in zip(b.indices, b.initial):
            current = model.shells[g].property
            item[g] = [(shell_property(current, {v.attribute: float(p0 * (x[k] + off))}), w / h)
                       for off, w in zip((2 * h, h, -h, -2 * h), (-1 / 12, 8 / 12, -8 / 12, 1 / 12))]
        return ValueChange(others={"shells": item})
    if v.kind == "mass" and v.per_configuration:
        mine = [i for c, i in b.indices if c == configuration]
        if not mine:
            return ValueChange()
        h = _EXACT_STEP
        values = [par.mass_entities(model, b, x[k] + off, configuration, x) for off in (h, -h)]
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


def _complex_step_applies(group, attribute: str) -> bool:
    """fem.sensitivity's complex-step group derivative covers E, G, rho of any section, and width and
    height of a uniform rectangle."""
    return attribute in ("E", "G", "rho") or (attribute in ("width", "height")
                                              and isinstance(group.section, RectangularSection))


def partial_derivatives(par: Parametrisation, model, x: np.ndarray, state, k: int, change: ValueChange | None = None):
    """dR/dp_k (reduced), dK/dp_k, dM/dp_k at ``state`` (held fixed), p_k the normalised variable;
    ``model`` is the working model at design point x (left unchanged); change: variable k's
    ValueChange when already known (it is the same in every configuration but for cords)."""
    if change is None:
        change = value_change(par, model, x, k, state.configuration.name)
    return value_derivative(state.system, state.positions, state.rotations, state.load_factor, change)


def shared_changes(par: Parametrisation, model, x: np.ndarray) -> DesignChanges:
    """Every variable's ValueChange that does not depend on the configuration (None for those on
    configuration items), with the beam variables' value-derivative matrices."""
    beams = _beam_changes(par, model, x, [k for k, b in enumerate(par.bindings) if b.variable.kind == "beam"])
    return DesignChanges.of([beams[k] if k in beams else None if b.variable.per_configuration
                             else value_change(par, model, x, k, "") for k, b in enumerate(par.bindings)])


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
                      per_direction: bool | None = None, changes: DesignChanges | None = None,
                      solver=None) -> StateDerivatives:
    """du/dp and the partial dK/dp, dM/dp of every variable at ``state``.

    tangent: the (full, possibly unsymmetric) reduced tangent at ``state``, factorised once.
    changes: shared_changes at x (computed here when None). The tangent's and mass matrix's change
    along du/dp is added per variable (four-point difference along each du, `state_direction`)
    for systems with interpolation links, for shell systems with fewer variables than a shell has
    DOFs less three (per_direction=None: `_directions_cheaper`; no beam-basis variables) or when
    asked; otherwise `modal_terms` gives it for the modes, whatever the number of variables. solver: the
    configuration's ModeSolver (updating.modesolve), whose factor solves du where the tangent is
    symmetric (no factorisation of its own)."""
    system = state.system
    n = len(par)
    design = changes if changes is not None else shared_changes(par, model, x)
    if per_direction is None:
        per_direction = not closed_form_links(system) or (not design.batched.any() and _directions_cheaper(system, n))
    batched = design.batched if not per_direction else np.zeros(n, bool)
    dR = np.zeros((system.n_free, n))
    basis = T = dr_full = None
    if batched.any():
        basis = beam_basis(system, state.positions, state.rotations, state.load_factor, design.rows,
                           design.local_units(system.cm.beams))
        if system.has_links:  # rigid links: over all DOFs, then reduced
            T = system.transformation(state.positions, state.rotations)
            dr_full = (basis.scatter(basis.g, True) @ design.DK - basis.scatter(basis.f, True) @ design.DM).toarray()
            dR += T.T @ dr_full
        else:
            dR += (basis.scatter(basis.g) @ design.DK - basis.scatter(basis.f) @ design.DM).toarray()
    matrices = {}
    for k in np.flatnonzero(~batched):
        r, Kk, Mk = partial_derivatives(par, model, x, state, k, design.changes[k])
        dR[:, k] = r
        matrices[k] = (Kk, Mk)
    du = None
    if np.any(dR) and solver is not None and _symmetric(tangent):
        try:
            du = -solver.solve_stiffness(dR)
        except SolverError:  # not positive definite: the LU below decides
            du = None
    if du is not None:
        pass
    elif np.any(dR):
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
    if per_direction:
        for k, (Kk, Mk) in matrices.items():
            if np.any(du[:, k]):
                Ku, Mu = state_direction(system, state, du[:, k])
                matrices[k] = (_add(Kk, Ku), _add(Mk, Mu))
    return StateDerivatives(du, matrices, system, basis, design.DK if basis is not None else None,
                            design.DM if basis is not None else None,
                            includes_state=per_direction or not np.any(du), T=T, dr_full=dr_full,
                            _rotations=state.rotations)


def _directions_cheaper(system, n: int) -> bool:
    """The modes' state part along each variable's du (state_direction: 4 evaluations of the whole
    system per variable) takes fewer shell-kernel passes than the element-level derivatives
    (modal_state_terms: 4 per DOF of a shell, 84 for quads): n variables below 6 p - 3. Only for
    systems with shells, whose corotational kernel is the cost of both (the 0.25 m wingbox's
    Jacobian, 5 variables: 3.0 -> 1.5 CPU s, the same to 1.2e-6 of each row's largest entry);
    beams keep the element-level form (36 cheap beam-kernel calls)."""
    shells = [f.nodes.shape[1] for f in system.families if "shells" in f.value_fields and len(f.nodes)]
    return bool(shells) and n < 6 * max(shells) - 3


def _symmetric(A: sp.spmatrix) -> bool:
    """A equals its transpose to 1e-12 of its largest entry."""
    A = sp.csc_matrix(A)
    top = abs(A).max() if A.nnz else 0.0
    return bool(top == 0 or abs(A - A.T).max() <= 1e-12 * top)


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


def eigenvalue_derivatives(lam: np.ndarray, phi: np.ndarray, d: StateDerivatives, terms=None,
                           forms: tuple | None = None) -> np.ndarray:
    """(n_modes, n_var) d lambda / dp for mass-normalised reduced eigenvectors phi (n_free, n_modes);
    forms: d.quadratic(phi) when already known."""
    qK, qM = d.quadratic(phi) if forms is None else forms
    out = qK - lam[:, None] * qM
    if terms is not None:
        out += (terms.gK - lam[:, None] * terms.gM) @ d.du
    return out


def eigenvector_derivatives(K: sp.csc_matrix, M: sp.csc_matrix, lam: float, phi: np.ndarray, dlam: np.ndarray,
                            d: StateDerivatives, terms=None, mode: int = 0, dmass: np.ndarray | None = None,
                            project=None, solver=None, index: int = 0, adjoint: np.ndarray | None = None) -> np.ndarray:
    """(n_free, n_var) d phi / dp of one mass-normalised mode by Nelson's method (distinct eigenvalue),
    or P d phi / dp ((n_out, n_var)) with project=P ((n_out, n_free), e.g. the sensors).

    K: the symmetric tangent, M: the mass matrix the mode solves, lam its eigenvalue; terms and
    mode: the state part (ModalStateTerms) and this mode's row in it; dmass: phi^T dM_k phi at the
    fixed state (n_var,) when already known (StateDerivatives.quadratic). With fewer outputs than
    variables, the projection is solved by the adjoint: P A^-1 = (A^-1 P^T)^T (A symmetric), n_out + 1
    solves whatever the number of variables. solver: the configuration's ModeSolver (updating.modesolve:
    one factorisation for every mode, this mode its computed mode ``index``) instead of a factorisation
    of the pinned K - lam M; adjoint: solver.solve(P^T) when already known (all modes in one block)."""
    if solver is not None:
        try:
            return _with_solver(M, lam, phi, dlam, d, terms, mode, dmass, project, solver, index, adjoint)
        except SolverError:  # repeated or not converged: the pinned factorisation decides
            pass
    n = len(phi)
    k = int(np.argmax(np.abs(phi) * np.sqrt(np.abs(M.diagonal()) + 1e-300)))
    try:
        lu = superlu(_pinned(K - lam * M, k))  # DOF k held at zero: the singular K - lam M made regular
    except RuntimeError as exc:
        raise SolverError(f"mode shape derivative: K - lambda M is singular after removing one DOF ({exc}); the "
                          "eigenvalue is repeated, so its shape derivative is not unique") from None
    Mphi = M @ phi
    if dmass is None:
        dmass = d.quadratic(phi[:, None])[1][0]
    if terms is not None:
        dmass = dmass + terms.gM[mode] @ d.du
    if project is not None and project.shape[0] + 1 < d.du.shape[1]:
        # Adjoint: W = A^-1 [P^T, M phi] (A symmetric, W[k] plays no part as rhs[k] = 0), then W^T rhs
        # from the element bilinear forms, never forming rhs itself.
        P = project
        Pt = P.T.toarray() if sp.issparse(P) else np.asarray(P, float).T
        W = lu.solve(np.column_stack([Pt, Mphi]))
        W[k] = 0.0
        Y = -d.bilinear(phi, W, lam) + (W.T @ Mphi)[:, None] * dlam[None, :]
        if terms is not None:
            Y -= (terms.H[mode].T @ W).T @ d.du
        c = -Y[-1] - 0.5 * dmass  # keeps phi^T M phi = 1
        return Y[:-1] + np.asarray(P @ phi).reshape(-1)[:, None] * c[None, :]
    rhs = -d.products(phi, lam) + Mphi[:, None] * dlam[None, :]
    if terms is not None:
        rhs -= terms.H[mode] @ d.du
    rhs[k] = 0.0
    v = lu.solve(rhs).reshape(n, -1)
    c = -(Mphi @ v) - 0.5 * dmass  # keeps phi^T M phi = 1
    if project is None:
        return v + phi[:, None] * c[None, :]
    return np.asarray(project @ v) + np.asarray(project @ phi).reshape(-1)[:, None] * c[None, :]


def _with_solver(M, lam, phi, dlam, d, terms, mode, dmass, project, solver, index, adjoint):
    """eigenvector_derivatives with a ModeSolver: v = G_i rhs is M-orthogonal to phi, so Nelson's
    normalisation term is -dmass / 2 alone."""
    Mphi = M @ phi
    if dmass is None:
        dmass = d.quadratic(phi[:, None])[1][0]
    if terms is not None:
        dmass = dmass + terms.gM[mode] @ d.du
    c = -0.5 * dmass
    if project is not None and project.shape[0] + 1 < d.du.shape[1]:
        P = project
        if adjoint is None:
            Pt = P.T.toarray() if sp.issparse(P) else np.asarray(P, float).T
            adjoint = solver.solve(Pt, np.full(Pt.shape[1], index))
        W = adjoint
        Y = -d.bilinear(phi, W, lam) + (W.T @ Mphi)[:, None] * dlam[None, :]
        if terms is not None:
            Y -= (terms.H[mode].T @ W).T @ d.du
        return Y + np.asarray(P @ phi).reshape(-1)[:, None] * c[None, :]
    rhs = -d.products(phi, lam) + Mphi[:, None] * dlam[None, :]
    if terms is not None:
        rhs -= terms.H[mode] @ d.du
    v = solver.solve(rhs, np.full(rhs.shape[1], index))
    c = c - Mphi @ v
    if project is None:
        return v + phi[:, None] * c[None, :]
    return np.asarray(project @ v) + np.asarray(project @ phi).reshape(-1)[:, None] * c[None, :]


def _pinned(A: sp.spmatrix, k: int) -> sp.csc_matrix:
    """A with row and column k zeroed and a unit diagonal there (A[keep][:, keep] without copying
    the pattern)."""
    A = sp.csc_matrix(A)
    A.sum_duplicates()
    A.data[A.indices == k] = 0.0
    start, end = A.indptr[k], A.indptr[k + 1]
    A.data[start:end] = 0.0
    diag = start + np.flatnonzero(A.indices[start:end] == k)
    if len(diag):
        A.data[diag] = 1.0
        return A
    return (A + sp.csc_matrix(([1.0], ([k], [k])), shape=A.shape)).tocsc()


__all__ = ["DesignChanges", "StateDerivatives", "eigenvalue_derivatives", "eigenvector_derivatives",
           "partial_derivatives", "state_derivatives", "state_direction"]
