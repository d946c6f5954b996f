"""A synthetic GVT of a model hung in a configuration: FRFs through the suspension at chosen sensors
and references, with noise, as a test lab would write them (UFF 58).

The FRF is the modal superposition of the suspended, pre-stressed structure's real modes with the
full (non-proportional) modal damping matrix of the cords' dashpots plus a structural modal
damping: H(w) = S Phi (Omega^2 - w^2 I + i w C_m)^-1 Phi^T F. Exact within the retained modes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..fem.points import cord_damping
from ..io.uff import FRFs


@dataclass(frozen=True)
class SyntheticGVT:
    """FRFs (receptance, UFF point ids and direction codes), the modes they were built from
    (frequencies_hz, the damping ratios of the damped modal model) and the points' positions."""

    frfs: FRFs
    frequencies_hz: np.ndarray
    damping_ratio: np.ndarray
    point_xyz: dict


def _code(direction) -> int:
    """UFF direction code (+-1..3) of the global axis nearest ``direction``."""
    d = np.asarray(direction, float)
    k = int(np.argmax(np.abs(d)))
    return int(np.sign(d[k])) * (k + 1)


def synthetic_gvt(model, configuration, sensors: dict, references: list[str], *, f_max_hz: float = 10.0,
                  df_hz: float = 0.02, n_modes: int = 40, structural_damping: float = 0.015,
                  snr_db: float | None = 30.0, seed: int = 0) -> SyntheticGVT:
    """FRFs of ``model`` in ``configuration`` at ``sensors`` ({name: (node, offset (3,), direction (3,))};
    each reads along the global axis nearest its direction, as UFF direction codes 1-3 say; test
    point k + 1 per distinct (node, offset) in order) for forces
    at the ``references`` (sensor names: driving points along their directions). Lines df_hz to
    f_max_hz [Hz]; structural_damping: modal damping ratio of every mode, scattered +-30 % per mode
    (seeded), the cords' dashpots on top; snr_db: complex noise relative to each line's magnitude."""
    from ..correlation import Sensor, Sensors
    from ..fem import solve_modes, solve_static
    from .project import case_points

    rng = np.random.default_rng(seed)
    state = solve_static(model, configuration)
    modes = solve_modes(state, n_modes, damped=False, label=False)
    node_map, offsets = case_points(type("C", (), {"sensors": sensors})())
    point_of = {(n, tuple(np.round(offsets[p], 9))): p for p, n in node_map.items()}
    names = list(sensors)
    items, outputs = [], []
    for name in names:
        node, off, d = sensors[name]
        code = _code(d)
        items.append(Sensor(int(node), np.sign(code) * np.eye(3)[abs(code) - 1], np.asarray(off, float), name))
        outputs.append((point_of[(int(node), tuple(np.round(np.asarray(off, float), 9)))], code))
    unknown = [r for r in references if r not in sensors]
    if unknown:
        raise ModelError(f"synthetic GVT: references {unknown} are not sensors")
    S = Sensors(items).matrix(modes.node_ids, state)  # readings turn with the deformed structure
    Phi = modes.matrix()  # (6n, m) mass-normalised
    Phi_s = np.asarray(S @ Phi)  # (n_sensors, m)
    w_n = 2 * np.pi * np.maximum(modes.frequencies_hz, 0.0)
    zeta = structural_damping * (1 + 0.3 * rng.uniform(-1, 1, len(w_n)))
    C = np.diag(2 * zeta * w_n)
    ids = list(modes.node_ids)
    system = state.system
    if len(system.cord_nodes):  # the cords' dashpots along their lines, projected on the modes
        Ce = cord_damping(*system.cord_state(state.positions, state.rotations), system.cord_offset,
                          system.cord_anchor, system.cord_c, system.cord_w)  # (n_cords, 12, 12)
        Pe = modes.shapes[:, np.column_stack([system.cord_nodes, system.cord_nodes_b]), :]  # (m, n_cords, 2, 6)
        Pe = Pe.reshape(len(w_n), len(system.cord_nodes), 12)
        C += np.einsum("mci,cij,ncj->mn", Pe, Ce, Pe)
    f = np.arange(df_hz, f_max_hz + 0.5 * df_hz, df_hz)
    w = 2 * np.pi * f
    ref = [names.index(r) for r in references]
    H = np.empty((len(f), len(names), len(ref)), complex)
    W2 = np.diag(w_n**2)
    for i, wi in enumerate(w):
        X = np.linalg.solve(W2 - wi**2 * np.eye(len(w_n)) + 1j * wi * C, Phi_s[ref].T)
        H[i] = Phi_s @ X
    if snr_db is not None:
        sigma = np.abs(H) / np.sqrt(2 * 10 ** (snr_db / 10))
        H = H + sigma * (rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape))
    # The damped system's poles: what an identification should find.
    A = np.block([[np.zeros_like(C), np.eye(len(w_n))], [-W2, -C]])
    s = np.linalg.eigvals(A)
    s = s[s.imag > 0]
    s = s[np.argsort(np.abs(s))]
    out = np.array(outputs)
    xyz = {int(p): state.positions[ids.index(n)] + state.rotations[ids.index(n)] @ offsets[p]
           for p, n in node_map.items()}
    return SyntheticGVT(FRFs(f, H, out, out[ref], "m/N"), np.abs(s) / (2 * np.pi), -s.real / np.abs(s), xyz)
