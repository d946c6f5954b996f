"""Derivatives of the residual, tangent and mass matrix with respect to the compiled values of the
element families (beam coefficients and mass, point masses, spring rates, cords) and to the state:
the foundation of gradient-based updating (flexgvt.updating.derivatives builds the changes).

The beam kernel is linear in its coefficients s = (EA, GJ, kd_y, ko_y, kd_z, ko_z, dd_y, dd_z),
and the mass matrix in the end values of (rho A, rho Ip, rho Iy, rho Iz), so d(residual, K)/dp is the same kernel
evaluated with ds/dp, and dM/dp the same mass assembly with the derivative mass terms: one
element pass per parameter, exact, at any (deformed) state.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from ..model import RectangularSection, end_properties
from .beam import (
    element_coefficients,
)
from .rotations import skew, spin

BEAM_PARAMETERS = ("E", "G", "rho", "width", "height")


def _section_props_complex(section, parameter: str, h: float) -> dict:
    """(A, Iy, Iz, J, Ip, Ay, Az) of a rectangular section with ``parameter`` (width or height) stepped
    by i h (complex step)."""
    if not isinstance(section, RectangularSection):
        kind = type(section).__name__
        raise ModelError(f"derivative with respect to '{parameter}' needs a RectangularSection, not a {kind}"
                         + ("; a tapered group's section dimensions are not design variables (use E, G or rho, "
                            "or give the group a uniform RectangularSection)" if kind == "TaperedSection" else ""))
    b, t = section.width, section.height
    db, dt = (1j * h, 0.0) if parameter == "width" else (0.0, 1j * h)
    bc, tc = b + db, t + dt
    A = bc * tc
    n = 2 * np.arange(50) + 1
    if b >= t:
        J = bc * tc**3 / 3 * (1 - 192 / np.pi**5 * tc / bc * np.sum(np.tanh(n * np.pi * bc / (2 * tc)) / n**5))
    else:
        J = tc * bc**3 / 3 * (1 - 192 / np.pi**5 * bc / tc * np.sum(np.tanh(n * np.pi * tc / (2 * bc)) / n**5))
    shear = 5 / 6 * A if section.shear else 0.0 * A
    return {"A": A, "Iy": bc * tc**3 / 12, "Iz": tc * bc**3 / 12, "J": J, "Ip": A * (bc * bc + tc * tc) / 12,
            "Ay": shear, "Az": shear}


def _stepped(group, parameter: str, h: float, properties: dict):
    """(E, G, rho, pa, pb) of a beam group with ``parameter`` stepped by i h; properties: a cache of
    the sections' end properties."""
    mat, sec = group.material, group.section
    E, G, rho = complex(mat.E), complex(mat.shear_modulus), complex(mat.rho)
    if id(sec) not in properties:
        properties[id(sec)] = (sec, end_properties(sec))  # the section kept alive: its id stays unique
    pa, pb = properties[id(sec)][1]
    if parameter == "E":
        E += 1j * h
        if mat.G is None:  # G = E / (2 (1 + nu)) follows E
            G += 1j * h / (2 * (1 + mat.nu))
    elif parameter == "G":
        G += 1j * h
    elif parameter == "rho":
        rho += 1j * h
    elif parameter in ("width", "height"):
        pa = pb = _section_props_complex(sec, parameter, h)
    else:
        raise ModelError(f"unknown beam parameter '{parameter}'; choose one of {BEAM_PARAMETERS}")
    return E, G, rho, pa, pb


def groups_derivatives(items) -> list[tuple]:
    """group_derivatives of many (group, parameter, L), the uniform groups in one vectorised
    complex-step evaluation (their values stacked element by element)."""
    h = 1e-30
    out = [None] * len(items)
    properties: dict = {}
    uniform = []
    for i, (group, parameter, L) in enumerate(items):
        E, G, rho, pa, pb = _stepped(group, parameter, h, properties)
        rot = 1.0 if group.rotary_inertia else 0.0
        if pb is pa:
            uniform.append((i, E, G, rho, pa, rot, np.asarray(L, float)))
            continue
        n = len(L)
        coefficients = element_coefficients(E, G, pa, pb, L)
        mass = np.tile([rho * pa["A"], rho * pb["A"]], (n, 1))
        inertia = np.tile([[rho * p["Ip"], rot * rho * p["Iy"], rot * rho * p["Iz"]] for p in (pa, pb)], (n, 1, 1))
        out[i] = (coefficients.imag / h, mass.imag / h, inertia.imag / h)
    if uniform:
        counts = [len(u[6]) for u in uniform]

        def per_element(values):
            return np.repeat(np.array(values, dtype=complex), counts)

        E, G, rho, rot = (per_element([u[k] for u in uniform]) for k in (1, 2, 3, 5))
        p = {key: per_element([u[4][key] for u in uniform]) for key in ("A", "Iy", "Iz", "J", "Ip", "Ay", "Az")}
        L = np.concatenate([u[6] for u in uniform])
        coefficients = element_coefficients(E, G, p, p, L).imag / h
        rhoA = (rho * p["A"]).imag / h
        line = np.stack([(rho * p["Ip"]).imag, (rot * rho * p["Iy"]).imag, (rot * rho * p["Iz"]).imag], axis=1) / h
        splits = np.cumsum(counts)[:-1]
        for (i, *_), c, m, r in zip(uniform, np.split(coefficients, splits), np.split(rhoA, splits),
                                   np.split(line, splits)):
            out[i] = (c, np.column_stack([m, m]), np.stack([r, r], axis=1))
    return out


@dataclass(frozen=True)
class ValueChange:
    """d(compiled values)/dp of one parameter, per item (items not listed do not change).

    beams: (element indices (k,), d kernel coefficients (k, 8) (see beam.element_coefficients),
    d rho A (k, 2), d inertia per length (k, 2, 3) at the elements' two nodes); masses: (indices into the system's
    point masses,
    (mass, offset) at p + h, (mass, offset) at p - h, 1 / (2 h)): masses enter linearly and
    offsets quadratically, so this central difference is exact; springs: (indices, d stiffness
    (k, 6)); cords: (indices, d stiffness (k,)); cord_offsets: (indices, samples) with samples
    [(offsets (k, 3), weight)] a finite-difference rule in the attachment offset (the cord's
    line of action is not polynomial in it); cord_along: (indices, samples) the same rule in the
    attachment fraction along the element. Derivatives are per unit of the parameter.
    Each field belongs to one element family (Family.value_fields); a family without a field here
    (a new one) takes its items from ``others`` by its field names.
    """

    beams: tuple | None = None
    masses: tuple | None = None
    springs: tuple | None = None
    cords: tuple | None = None
    cord_offsets: tuple | None = None  # (indices, [(offsets (k, 3), weight), ...]): a difference rule in the offset
    cord_along: tuple | None = None  # (indices, [(fractions (k,), weight), ...]): the same in the attachment fraction
    others: dict = field(default_factory=dict)  # {field name: item} of families without a field above
    cache: dict = field(default_factory=dict, compare=False, repr=False)  # state-independent pieces, computed once

    def item(self, name: str) -> tuple | None:
        """The change's item for a family's value field ``name`` (None: unchanged)."""
        return getattr(self, name) if name in _OWN_FIELDS else self.others.get(name)

    @property
    def beams_only(self) -> bool:
        """Only beam values change."""
        return self.beams is not None and not self.others and all(
            getattr(self, name) is None for name in _OWN_FIELDS if name != "beams")


_OWN_FIELDS = ("beams", "masses", "springs", "cords", "cord_offsets", "cord_along")


def value_derivative(system, x: np.ndarray, R: np.ndarray, lam: float, change: ValueChange,
                     full_mass: bool = False) -> tuple[np.ndarray, sp.csc_matrix, sp.csc_matrix]:
    """Exact d(residual) (reduced), dK (reduced, the consistent tangent's derivative) and dM (reduced,
    or over all DOFs with full_mass) at the state (x, R) and load factor lam, for a change of the
    compiled values. Only the items that change are evaluated, each by its family
    (Family.derivative; a family's ValueChange fields are its value_fields)."""
    n = system.n_nodes
    p = system.pattern
    K_data = np.zeros(p.nnz)
    mass_pattern = system.full_pattern if full_mass else p
    M_data = np.zeros(mass_pattern.nnz)
    g_full = np.zeros((n, 6))
    f_full = np.zeros((n, 6))
    gvec = system.config.gravity_vector
    for block, family in enumerate(system.families):
        for name in family.value_fields:
            item = change.item(name)
            if item is None:
                continue
            d = family.derivative(name, item, x, R, lam, gvec, change.cache)
            nodes = family.nodes[d.rows]
            for out, v in ((g_full, d.forces), (f_full, d.applied)):
                if v is not None:
                    for a in range(nodes.shape[1]):
                        np.add.at(out, nodes[:, a], v[:, 6 * a:6 * a + 6])
            if d.tangent is not None:
                p.data_subset(block, d.rows, d.tangent, K_data)
            if d.mass is not None:
                mass_pattern.data_subset(block, d.rows, d.mass, M_data)
    r_full = (g_full - f_full).reshape(-1)
    dM = mass_pattern.matrix(M_data)
    if not system.has_links:
        return r_full[system.dof_map >= 0], p.matrix(K_data), dM
    T = system.transformation(x, R)
    dK = system._reduce_with_links(p.matrix(K_data), T, x, R, r_full)
    if not full_mass:
        dM = (T.T @ dM @ T).tocsc()
    return T.T @ r_full, dK, dM


@dataclass(frozen=True)
class ModalStateTerms:
    """How the modal quadratic forms change with the state, for modes phi_i (reduced, mass-normalised):

    gK[i] = d(phi_i^T K(u) phi_i)/du and gM[i] = d(phi_i^T M(u) phi_i)/du (reduced, (m, n_free)),
    so that d lambda_i = ... + (gK[i] - lambda_i gM[i]) . du for any state change du; and
    H[i] = d((sym K(u) - lambda_i M(u)) phi_i)/du (reduced, sparse) for mode-shape derivatives.
    """

    gK: np.ndarray
    gM: np.ndarray
    H: list | None


def _element_state_derivatives(fn, xn, Rn, h_t, h_r, translation_invariant: bool = False,
                               rotations=None):
    """Yield (node, component, dK, dM): derivatives of element blocks (K, M) = fn(x, R) with respect
    to each DOF (dx or spatial spin) of each of their nodes, every element at once (their nodes are
    exploded: xn (n, p, 3), Rn (n, p, 3, 3)). Four-point central differences: a two-point rule
    left 0.5 % errors in the first mode's slope of the strip under self-weight (the stretch of a
    short element is steeply nonlinear in its end positions). translation_invariant (elements
    whose blocks depend on the differences of their nodes' positions only, as the corotational
    beam's and shell's): the first node's translation derivatives are minus the sum of the others'.
    rotations: the tangent-only fn(x, R) for the rotation DOFs of a family whose mass depends on the
    positions alone (dM is then exactly zero there and yielded as None)."""
    p = xn.shape[1]
    mirror = translation_invariant and p >= 2
    sums = {}  # component -> (sum of dK, sum of dM) over the nodes after the first
    for a in range(p):
        for c in range(6):
            if mirror and a == 0 and c < 3:
                continue  # yielded with the last node's below
            h = h_t if c < 3 else h_r
            call = fn if c < 3 or rotations is None else rotations
            dK = dM = 0.0
            for off, w in zip((2 * h, h, -h, -2 * h), (-1 / 12, 8 / 12, -8 / 12, 1 / 12)):
                xs, Rs = xn, Rn
                if c < 3:
                    xs = xn.copy()
                    xs[:, a, c] += off
                else:
                    Rs = Rn.copy()
                    phi = np.zeros((len(Rn), 3))
                    phi[:, c - 3] = off
                    Rs[:, a] = spin(Rn[:, a], phi)
                K, M = call(xs, Rs)
                dK = dK + (w / h) * K
                if M is not None:
                    dM = dM + (w / h) * M
            dM = dM if M is not None else None
            yield a, c, dK, dM
            if mirror and c < 3:
                if a == 1:
                    sums[c] = (dK, dM)
                else:
                    sK, sM = sums[c]
                    sums[c] = (sK + dK, None if dM is None else sM + dM)
                if a == p - 1:
                    sK, sM = sums.pop(c)
                    yield 0, c, -sK, (None if sM is None else -sM)


def modal_state_terms(system, x: np.ndarray, R: np.ndarray, lam: float, phi: np.ndarray, eigenvalues: np.ndarray,
                      vectors: bool = True) -> ModalStateTerms:
    """ModalStateTerms of the modes ``phi`` (n_free, m) with ``eigenvalues`` (m,) at the state (x, R),
    load factor lam. Each element's tangent and mass depend only on its own nodes, so every element's
    derivative with respect to each of its DOFs comes from one evaluation of all elements with
    exploded nodes: 9 DOFs x 4 points = 36 beam-kernel calls (the first node's translations mirror
    the second's), whatever the number of design variables. Rigid links add their own terms in
    closed form (_rigid_link_terms); interpolation links are not handled here."""
    if not closed_form_links(system):
        raise ModelError("modal_state_terms: systems with interpolation links need the per-direction derivative")
    n, m = system.n_nodes, phi.shape[1]
    T = system.transformation(x, R) if system.has_links else None
    full = system.expand(phi, T).reshape(n, 6, m)
    # Steps of 1e-4 of the shortest element (translations) and 1e-4 rad: the stretch of a short
    # element changes its axial force at EA/L, so a step scaled on the structure's size would
    # strain it by percents.
    lengths = np.concatenate([system.cm.beams.L0] + [
        np.linalg.norm(np.diff(s.corotational.X, axis=1, append=s.corotational.X[:, :1]), axis=2).ravel()
        for s in system.cm.shells])
    h_t = 1e-4 * (float(lengths.min()) if len(lengths) else max(float(np.ptp(system.cm.xyz, axis=0).max()), 1e-3))
    h_r = 1e-4
    gK = np.zeros((n, 6, m))
    gM = np.zeros((n, 6, m))
    H_blocks = [[] for _ in range(m)] if vectors else None
    kinds = [(lambda xs, Rs, f=family: f.exploded_terms(xs, Rs, lam), family.nodes, family.translation_invariant,
              (lambda xs, Rs, f=family: f.exploded_terms(xs, Rs, lam, mass=False))
              if getattr(family, "mass_from_positions", False) else None)
             for family in system.families]
    for fn, nodes, mirror, rotations in kinds:
        if len(nodes) == 0:
            if vectors:
                width = 6 * max(nodes.shape[1], 1)
                for i in range(m):
                    H_blocks[i].append(np.zeros((0, width, width)))
            continue
        ne, p = nodes.shape
        ph = full[nodes].reshape(ne, 6 * p, m)
        Hb = np.zeros((m, ne, 6 * p, 6 * p)) if vectors else None
        for a, c, dK, dM in _element_state_derivatives(fn, x[nodes], R[nodes], h_t, h_r, mirror,
                                                         rotations):
            Kphi = dK @ ph  # batched (e, d, d) @ (e, d, m)
            np.add.at(gK[:, c], nodes[:, a], np.sum(ph * Kphi, axis=1))
            if dM is not None:
                Mphi = dM @ ph
                np.add.at(gM[:, c], nodes[:, a], np.sum(ph * Mphi, axis=1))
            if vectors:
                v = 0.5 * (Kphi + np.swapaxes(dK, 1, 2) @ ph)
                if dM is not None:
                    v -= eigenvalues[None, None, :] * Mphi
                Hb[:, :, :, 6 * a + c] = np.moveaxis(v, 2, 0)
        if vectors:
            for i in range(m):
                H_blocks[i].append(Hb[i])
    H = [system.pattern.assemble(blocks) for blocks in H_blocks] if vectors else None
    if T is None:
        free = system.dof_map >= 0
        return ModalStateTerms(gK.reshape(6 * n, m)[free].T, gM.reshape(6 * n, m)[free].T, H)
    # Links: the element part over all DOFs, reduced (u_full moves by T du), plus the rigid links'
    # own terms (T and the links' geometric stiffness turn with the independent nodes; a linear
    # constraint's rows of T are constant).
    CK, CM = _rigid_link_terms(system, x, R, lam, phi, full.reshape(6 * n, m), T)
    gK = np.stack([T.T @ gK.reshape(6 * n, m)[:, i] + CK[i].T @ phi[:, i] for i in range(m)])
    gM = np.stack([T.T @ gM.reshape(6 * n, m)[:, i] + CM[i].T @ phi[:, i] for i in range(m)])
    if vectors:
        H = [(T.T @ H[i] @ T + CK[i] - eigenvalues[i] * CM[i]).tocsc() for i in range(m)]
    return ModalStateTerms(gK, gM, H)


def closed_form_links(system) -> bool:
    """True when modal_state_terms handles the system's constraints: rigid links (their own terms in
    closed form) and linear constraints (a constant map), but no interpolation links."""
    return len(system.cm.interp) == 0


def link_force_blocks(r: np.ndarray, tied: np.ndarray, a: np.ndarray) -> np.ndarray:
    """(k, 3, 3) B with sym(G(f)) phi = B f at the independent nodes' rotations: how the links'
    geometric term (System._reduce_with_links) acting on a mode with rotation a (k, 3) at the
    node changes with the force f (k, 3) at each dependent (offset r, tied translations ``tied``)."""
    return -0.5 * (skew(np.cross(r, a)) + skew(r) @ skew(a)) * tied[:, None, :]


def _rigid_link_terms(system, x, R, lam, phi, full, T):
    """Per mode i, the rigid links' part of d(sym K_red phi_i)/du and d(M_red phi_i)/du (reduced,
    sparse): K_red = T^T K T + G(f), M_red = T^T M T, where T and the links' geometric term G turn
    with each independent node i and G carries the link forces f of the dependents (see
    System._reduce_with_links). For a dependent d at the rotated offset r from its node, a spin
    dtheta of the node moves r by dtheta x r, so (a: the mode's rotation at the node, z: the full
    (A phi)'s force at d, A = sym K or M, t the tied translations):
      d(T^T z) = skew(z) skew(r) dtheta                      (rows and columns: the node's rotations)
      T^T A dT phi, dT phi at d = -skew(a) skew(r) dtheta    (columns: the node's rotations)
      d(sym G phi) = B (K T du)_d + 1/2 (skew(f) skew(a) + skew(f x a)) skew(r) dtheta,
      B = -1/2 (skew(r x a) + skew(r) skew(a))               (rows: the node's rotations)."""
    n_red, m = phi.shape[0], phi.shape[1]
    r_full, K_full, M_full = system.full_state(x, R, lam)
    K_sym = (0.5 * (K_full + K_full.T)).tocsc()
    deps, ind, r = system.link_offsets(R)
    tied = system.cm.link_dofs[deps, :3].astype(float)  # (k, 3)
    rot = system.dof_map[6 * ind[:, None] + 3 + np.arange(3)]  # (k, 3) reduced, -1 where held
    trans = 6 * deps[:, None] + np.arange(3)  # (k, 3) full rows of the dependents' translations
    f = r_full.reshape(-1, 6)[deps, :3] * tied
    Sr = skew(r)
    n_full = full.shape[0]
    KT = (K_full @ T).tocsr()

    def block(values, rows, cols, shape):
        """Sum of (k, 3, 3) blocks at rows (k, 3) x cols (k, 3), entries with a negative index dropped."""
        rr = np.repeat(rows, 3, axis=1).reshape(-1, 3, 3)
        cc = np.tile(cols, (1, 3)).reshape(-1, 3, 3)
        keep = (rr >= 0) & (cc >= 0)
        return sp.csc_matrix((values[keep], (rr[keep], cc[keep])), shape=shape)

    CK, CM = [], []
    for i in range(m):
        a = full[:, i].reshape(-1, 6)[ind, 3:]  # (k, 3) the mode's rotation at each dependent's node
        Sa = skew(a)
        out = []
        for A in (K_sym, M_full):
            z = (A @ full[:, i]).reshape(-1, 6)[deps, :3] * tied
            C = block(skew(z) @ Sr, rot, rot, (n_red, n_red))
            P = block(-tied[:, :, None] * (Sa @ Sr), trans, rot, (n_full, n_red))  # dT phi per spin
            C = C + T.T @ (A @ P)
            out.append(C)
        B = link_force_blocks(r, tied, a)
        Q = block(np.swapaxes(B, 1, 2), trans, rot, (n_full, n_red))  # Q^T = B on the force rows
        CK.append((out[0] + Q.T @ KT + block(0.5 * (skew(f) @ Sa + skew(np.cross(f, a))) @ Sr, rot, rot,
                                                         (n_red, n_red))).tocsc())
        CM.append(out[1].tocsc())
    return CK, CM
