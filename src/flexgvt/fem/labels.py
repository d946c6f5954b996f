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


CLASSES = ("OOP", "IP", "T", "EXT", "RB")
CLASS_NAMES = {"OOP": "out-of-plane bending", "IP": "in-plane bending", "T": "torsion", "EXT": "extension",
               "RB": "rigid body / suspension"}
_RIGID = ("fore-aft", "lateral", "plunge", "roll", "pitch", "yaw")


def energy_fractions(modes, state) -> np.ndarray:
    """(n_modes, 5) fractions of OOP bending, IP bending, torsion, extension and 'rigid/suspension'.

    The strain energy of each mode comes from the element families that split theirs
    (Family.strain_energies: the beams, per element in its deformed local axes, bending about the
    local axis closer to the global vertical plane being out-of-plane). Whatever of the mode's
    potential energy (omega^2, mass-normalised) is not strain energy (springs, cords, gravity)
    counts as rigid/suspension.
    """
    shapes = modes.shapes
    out = np.zeros((len(shapes), 5))
    for family in state.system.families:
        energies = getattr(family, "strain_energies", None)  # an optional hook of the element families
        if energies is not None:
            out[:, :4] += energies(shapes, state.positions, state.rotations)
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


mac_matrix = mac_columns  # fem's name for the one MAC kernel (flexgvt.modal.mac_columns)
