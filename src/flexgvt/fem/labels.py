"""Mode labelling from strain-energy fractions.

Labelling sits under the eigen kernel and solve_modes (which label their modes); tracking modes
across load levels (fem.tracking) solves, so it sits above fem.static and fem.modes: two modules,
one each side of the solver. ``mac_matrix`` is fem's name for the one MAC kernel
(flexgvt.modal.mac_columns).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..modal.mac import mac_columns
from .interpolation import fit


CLASSES = ("OOP", "IP", "T", "EXT", "RB", "LOCAL")  # the columns of energy_fractions
CLASS_NAMES = {"OOP": "out-of-plane bending", "IP": "in-plane bending", "T": "torsion", "EXT": "extension",
               "RB": "rigid body / suspension", "LOCAL": "local (panel) deformation of the cross-sections"}
_ELASTIC = (0, 1, 2, 3, 5)
_RIGID = ("fore-aft", "lateral", "plunge", "roll", "pitch", "yaw")


def energy_fractions(modes, state) -> np.ndarray:
    """(n_modes, 6) fractions of OOP bending, IP bending, torsion, extension, 'rigid/suspension' and
    local deformation (the columns of CLASSES).

    The strain energy of each mode comes from the element families that split theirs
    (Family.strain_energies: the beams, per element in its deformed local axes, bending about the
    local axis closer to the global vertical plane being out-of-plane; the shells by the
    cross-sections' motion, section_fractions). Whatever of the mode's potential energy (omega^2,
    mass-normalised) is not strain energy (springs, cords, gravity) counts as rigid/suspension.
    """
    shapes = modes.shapes
    out = np.zeros((len(shapes), 6))
    for family in state.system.families:
        energies = getattr(family, "strain_energies", None)  # an optional hook of the element families
        if energies is not None:
            e = energies(shapes, state.positions, state.rotations)
            out[:, :4] += e[:, :4]
            if e.shape[1] > 4:
                out[:, 5] += e[:, 4]
    total_pe = 0.5 * np.abs(modes.eigenvalues.real if modes.eigenvalues is not None else 0.0)
    if modes.complex_shapes is not None:
        total_pe = 0.5 * (2 * np.pi * modes.frequencies_hz) ** 2
    strain = out[:, _ELASTIC].sum(axis=1)
    total = np.maximum(total_pe, strain)
    out[:, 4] = np.maximum(total - strain, 0.0)
    return out / np.where(total > 0, total, 1.0)[:, None]


def section_fractions(shapes: np.ndarray, x: np.ndarray, mass: np.ndarray, stations: int | None = None,
                      reference: np.ndarray | None = None) -> np.ndarray:
    """(n_modes, 5) fractions of OOP, IP, torsion, extension and local motion of mode shapes
    (n_modes, n, 6) of a built-up structure with nodes x (n, 3) and translational masses (n,) [kg].

    The structure's principal axes (mass-weighted) give the span s (largest extent), the chord c
    and the normal v (smallest: out-of-plane). The nodes are cut into stations along s; each
    station's translations are fitted by a rigid motion of its cross-section (least squares,
    mass-weighted), whose kinetic energy splits into OOP (along v, and turning about c), IP (along
    c, and turning about v), torsion (turning about s) and extension (along s); the rest of the
    kinetic energy, which no rigid cross-section motion explains (a skin panel's own bending, a
    rib's), is local. reference: the nodes' undeformed positions (n, 3); then the axes and stations
    are the undeformed structure's, and each station's axes turn with it (the rotation that best
    maps its and its neighbours' undeformed nodes onto x), so a strip curled by its load keeps
    its flatwise modes out-of-plane, as the beams' deformed element axes do.
    """
    m = np.maximum(np.asarray(mass, float), 0.0)
    w = m / max(m.sum(), 1e-300)
    X = x if reference is None else np.asarray(reference, float)
    centre = w @ X
    r0 = X - centre
    evals, axes = np.linalg.eigh((r0 * w[:, None]).T @ r0)
    v0, c0, s0 = axes[:, 0], axes[:, 1], axes[:, 2]
    v, c, s = v0, c0, s0
    along = r0 @ s
    extent = max(float(np.ptp(along)), 1e-300)
    levels, st = np.unique(np.round(along / (1e-6 * extent)), return_inverse=True)
    if stations or len(levels) > len(x) / 3:  # no spanwise layout of cross-sections: equal bins
        nb = stations or int(np.clip(round(np.sqrt(len(x))), 2, 200))
        st = np.clip(((along - along.min()) / extent * nb).astype(int), 0, nb - 1)
    st = np.asarray(st).reshape(-1)
    u = np.asarray(shapes, float)[:, :, :3]
    parts = np.zeros((len(u), 5))
    order = np.unique(st)
    for j, k in enumerate(order):
        idx = np.flatnonzero(st == k)
        mk = m[idx]
        if mk.sum() <= 0:
            continue
        if reference is not None:
            near = np.flatnonzero(np.isin(st, order[max(j - 1, 0):j + 2]))
            turn = _best_rotation(X[near], x[near], m[near])
            v, c, s = turn @ v0, turn @ c0, turn @ s0
        r = x[idx] - (mk @ x[idx]) / mk.sum()
        A = np.zeros((len(idx), 3, 6))  # u_i = a + theta x r_i = a - skew(r_i) theta
        A[:, :, :3] = np.eye(3)
        A[:, 0, 4], A[:, 0, 5] = r[:, 2], -r[:, 1]
        A[:, 1, 3], A[:, 1, 5] = -r[:, 2], r[:, 0]
        A[:, 2, 3], A[:, 2, 4] = r[:, 1], -r[:, 0]
        N = np.einsum("i,iab,iac->bc", mk, A, A)
        b = np.einsum("i,iab,mia->mb", mk, A, u[:, idx])
        p = b @ np.linalg.pinv(N, rcond=1e-10).T  # (modes, 6): a, theta
        a, th = p[:, :3], p[:, 3:]
        fit = np.einsum("iab,mb->mia", A, p)
        total = np.einsum("i,mia,mia->m", mk, u[:, idx], u[:, idx])
        fitted = np.einsum("i,mia,mia->m", mk, fit, fit)
        # kinetic energy of the cross-section turning about each axis: (theta . e)^2 sum m |e x r|^2
        arm = {k: np.sum(mk * np.sum(np.cross(e[None, :], r) ** 2, axis=1)) for k, e in (("v", v), ("c", c), ("s", s))}
        parts[:, 0] += mk.sum() * (a @ v) ** 2 + (th @ c) ** 2 * arm["c"]
        parts[:, 1] += mk.sum() * (a @ c) ** 2 + (th @ v) ** 2 * arm["v"]
        parts[:, 2] += (th @ s) ** 2 * arm["s"]
        parts[:, 3] += mk.sum() * (a @ s) ** 2
        parts[:, 4] += np.maximum(total - fitted, 0.0)
    return parts / np.maximum(parts.sum(axis=1, keepdims=True), 1e-300)


def _best_rotation(X: np.ndarray, x: np.ndarray, m: np.ndarray) -> np.ndarray:
    """(3, 3) the rotation that best maps the points X onto x about their mass centres (the polar
    decomposition of interpolation.fit, mass-weighted); the identity where they do not fix one
    (fewer than three points off a line)."""
    if m.sum() <= 0:
        return np.eye(3)
    w = m / m.sum()
    arms = X - w @ X
    sv = np.linalg.svd(arms * np.sqrt(w)[:, None], compute_uv=False)
    if sv[1] <= 1e-9 * max(sv[0], 1e-300):
        return np.eye(3)
    return fit(x, w, arms, np.zeros(3))[1]


def _rigid_name(phi: np.ndarray, x: np.ndarray) -> str:
    """Dominant rigid-body motion of a shape: least-squares fit of the nodes' translations and
    rotations (times the half size, so a rotation about a beam's own axis counts too)."""
    c = x.mean(axis=0)
    size = np.ptp(x, axis=0).max() / 2 or 1.0
    A = np.zeros((len(x), 6, 6))
    for a in range(3):
        e = np.zeros(3)
        e[a] = 1.0
        A[:, a, a] = 1.0
        A[:, :3, 3 + a] = np.cross(e, x - c)
        A[:, 3 + a, 3 + a] = size
    b = np.concatenate([phi[:, :3], size * phi[:, 3:6]], axis=1)
    coef = np.linalg.lstsq(A.reshape(-1, 6), b.reshape(-1), rcond=None)[0]
    coef[3:] *= size
    return _RIGID[int(np.argmax(np.abs(coef)))]


OVERDAMPED = 1.0 - 1e-9  # a complex root with this damping ratio is real: it decays without vibrating


def label_modes(modes):
    """Label each mode 'k CLASS' (e.g. '1 OOP', '2 T', 'RB plunge') from energy fractions; a mode
    mostly in a distributed cord's interior points 'k bungee surge' or 'k bungee string'; a real
    (overdamped) root of the damped problem 'overdamped k', outside the classes' numbering."""
    state = modes.state
    fr = energy_fractions(modes, state)
    counts = {c: 0 for c in CLASSES}
    labels = []
    # A family's own modes (a distributed cord's surge and string modes: family hook mode_kinds)
    own = [None] * len(fr)
    for family in state.system.families:
        kinds = getattr(family, "mode_kinds", None)
        if kinds is not None:
            own = [a or b for a, b in zip(own, kinds(modes.shapes, state.positions))]
    overdamped = 0
    zeta = np.asarray(modes.damping_ratio, float)
    for m in range(len(fr)):
        if zeta[m] >= OVERDAMPED and modes.frequencies_hz[m] != 0.0:  # a real root: no vibration, no class
            overdamped += 1
            labels.append(f"overdamped {overdamped}")
            continue
        if own[m] is not None and modes.frequencies_hz[m] != 0.0:
            counts[own[m]] = counts.get(own[m], 0) + 1
            labels.append(f"{counts[own[m]]} {own[m]}")
            continue
        if modes.frequencies_hz[m] == 0.0 or fr[m, 4] > 0.5:
            labels.append("RB " + _rigid_name(modes.shapes[m], state.positions))
            continue
        elastic = np.array(_ELASTIC)
        order = elastic[np.argsort(fr[m, elastic])[::-1]]
        cls = CLASSES[order[0]]
        counts[cls] += 1
        second = fr[m, order[1]] / max(fr[m, elastic].sum(), 1e-300)
        tag = f"{counts[cls]} {cls}" + (f"/{CLASSES[order[1]]}" if second > 0.3 else "")
        labels.append(tag)
    return replace(modes, labels=tuple(labels), energy_fractions=fr)


mac_matrix = mac_columns  # fem's name for the one MAC kernel (flexgvt.modal.mac_columns)
