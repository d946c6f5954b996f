"""Mode labelling from strain-energy fractions, and the MAC matrix.

Labelling sits under the eigen kernel and solve_modes (which label their modes); tracking modes
across load levels (fem.tracking) solves, so it sits above fem.static and fem.modes: two modules,
one each side of the solver. mac_matrix stays here until the single MAC kernel replaces it.
"""

from __future__ import annotations

from dataclasses import replace

import numba
import numpy as np

from .beam import current_frames

CLASSES = ("OOP", "IP", "T", "EXT", "RB")
CLASS_NAMES = {"OOP": "out-of-plane bending", "IP": "in-plane bending", "T": "torsion", "EXT": "extension",
               "RB": "rigid body / suspension"}
_RIGID = ("fore-aft", "lateral", "plunge", "roll", "pitch", "yaw")


@numba.njit(cache=True, inline="always")
def _bending_energy(kd, ko, dd, L, d1, r1, d2, r2, sign):  # pragma: no cover - compiled
    """Energy of a bending block 1/2 ((kd + dd) a^2 + 2 ko a b + (kd - dd) b^2), a and b the end
    rotations relative to the chord; sign=+1 for (v, rz), -1 for (w, ry)."""
    chord = sign * (d2 - d1) / L
    a, b = r1 - chord, r2 - chord
    return 0.5 * ((kd + dd) * a * a + 2 * ko * a * b + (kd - dd) * b * b)


@numba.njit(cache=True)
def _beam_energies(shapes, nodes, Rr, stiffness, L, vertical, out):  # pragma: no cover - compiled
    """out[m] += (OOP, IP, torsion, extension) strain energies of mode m summed over the beams
    (stiffness: the kernel coefficients, beam.element_coefficients)."""
    loc = np.empty((4, 3))  # local u1, t1, u2, t2
    for m in range(shapes.shape[0]):
        for e in range(nodes.shape[0]):
            for blk in range(4):
                node = nodes[e, blk // 2]
                off = 3 * (blk % 2)
                for j in range(3):
                    loc[blk, j] = (shapes[m, node, off] * Rr[e, 0, j] + shapes[m, node, off + 1] * Rr[e, 1, j]
                                   + shapes[m, node, off + 2] * Rr[e, 2, j])
            EA, GJ, kdy, koy, kdz, koz, ddy, ddz = stiffness[e]
            Le = L[e]
            ext = 0.5 * EA / Le * (loc[2, 0] - loc[0, 0]) ** 2
            tor = 0.5 * GJ / Le * (loc[3, 0] - loc[1, 0]) ** 2
            by = _bending_energy(kdy, koy, ddy, Le, loc[0, 2], loc[1, 1], loc[2, 2], loc[3, 1], -1.0)
            bz = _bending_energy(kdz, koz, ddz, Le, loc[0, 1], loc[1, 2], loc[2, 1], loc[3, 2], 1.0)
            out[m, 0] += by if vertical[e] else bz
            out[m, 1] += bz if vertical[e] else by
            out[m, 2] += tor
            out[m, 3] += ext


def energy_fractions(modes, state) -> np.ndarray:
    """(n_modes, 5) fractions of OOP bending, IP bending, torsion, extension and 'rigid/suspension'.

    Beam strain energy of each mode is split per element in its deformed local axes; bending
    about the local axis closer to the global vertical plane is out-of-plane. Whatever of the
    mode's potential energy (omega^2, mass-normalised) is not beam strain energy (springs,
    cords, gravity) counts as rigid/suspension.
    """
    system = state.system
    b = system.cm.beams
    shapes = modes.shapes
    out = np.zeros((len(shapes), 5))
    if len(b.L0):
        Rr = current_frames(state.positions, state.rotations, b)
        vertical = np.abs(Rr[:, 2, 2]) >= np.abs(Rr[:, 2, 1])  # local z closer to global z: bending about y is OOP
        _beam_energies(np.ascontiguousarray(shapes, dtype=float), b.nodes, np.ascontiguousarray(Rr),
                       np.ascontiguousarray(b.stiffness, dtype=float), b.L0, vertical, out)
    total_pe = 0.5 * np.abs(modes.eigenvalues.real if modes.eigenvalues is not None else 0.0)
    if modes.complex_shapes is not None:
        total_pe = 0.5 * (2 * np.pi * modes.frequencies_hz) ** 2
    beam = out[:, :4].sum(axis=1)
    total = np.maximum(total_pe, beam)
    out[:, 4] = np.maximum(total - beam, 0.0)
    return out / np.where(total > 0, total, 1.0)[:, None]


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


def label_modes(modes):
    """Label each mode 'k CLASS' (e.g. '1 OOP', '2 T', 'RB plunge') from energy fractions."""
    state = modes.state
    fr = energy_fractions(modes, state)
    counts = {c: 0 for c in CLASSES}
    labels = []
    for m in range(len(fr)):
        if modes.frequencies_hz[m] == 0.0 or fr[m, 4] > 0.5:
            labels.append("RB " + _rigid_name(modes.shapes[m], state.positions))
            continue
        order = np.argsort(fr[m, :4])[::-1]
        cls = CLASSES[order[0]]
        counts[cls] += 1
        second = fr[m, order[1]] / max(fr[m, :4].sum(), 1e-300)
        tag = f"{counts[cls]} {cls}" + (f"/{CLASSES[order[1]]}" if second > 0.3 else "")
        labels.append(tag)
    return replace(modes, labels=tuple(labels), energy_fractions=fr)


def mac_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """MAC between columns of a (n_dof, na) and b (n_dof, nb), complex allowed."""
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return num / np.where(den > 0, den, 1.0)
