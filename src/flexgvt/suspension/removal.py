"""Removing the suspension: the same model with no suspension (free-free, its six rigid-body modes
at zero) and, optionally, with a softer proposed suspension, beside the tested configuration;
every elastic mode's shift caused by the suspension, paired by MAC (docs/method.md section 3 step 4)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError
from ..fem import Modes, solve_modes, solve_static
from ..model import Configuration, Model


@dataclass
class Removal:
    """suspended / free / proposed: the Modes of each case (proposed may be None); rows: one per
    free elastic mode with its frequency in each case, the shift the suspension causes and the MACs
    of the pairing (a free mode with no partner above the MAC floor is left blank)."""

    suspended: Modes
    free: Modes
    proposed: Modes | None
    rows: list[dict] = field(default_factory=list)

    def table(self) -> list[dict]:
        """The rows (one per free elastic mode)."""
        return self.rows


def _material_shapes(modes: Modes, n_nodes: int) -> np.ndarray:
    """(n_dof, n_modes) shapes at the model's first ``n_nodes`` nodes (a distributed cord's interior
    points, which follow them, left out) turned back into each node's undeformed orientation (R^T u,
    R^T theta), so that modes about a bowed hung shape compare with the flat free-free ones as the
    structure sees them (a bending mode stays normal to the strip)."""
    R = modes.state.rotations[:n_nodes]
    s = modes.shapes[:, :n_nodes].reshape(len(modes.shapes), -1, 2, 3)
    local = np.einsum("nji,mnkj->mnki", R, s)
    return local.reshape(len(modes.shapes), -1).T


def _mass_mac(a: Modes, b: Modes, M) -> np.ndarray:
    """Mass-weighted MAC (phi_a^T M phi_b)^2 / ((phi_a^T M phi_a)(phi_b^T M phi_b)) between two mode
    sets of one model (full shapes in the nodes' own orientation), M: the free model's mass matrix."""
    n = M.shape[0] // 6
    A = _material_shapes(a, n)
    B = _material_shapes(b, n)
    MB = M @ B
    num = (A.T @ MB) ** 2
    den = np.outer(np.einsum("ij,ij->j", A, M @ A), np.einsum("ij,ij->j", B, MB))
    return num / np.where(den > 0, den, 1.0)


def _cord_modes(configuration: Configuration) -> int:
    """How many modes a configuration's cords add below the structure's: one per cord, and a
    distributed cord's own (three per interior point: surge and two string planes)."""
    return sum(1 + 3 * max(int(getattr(c, "segments", 0)) - 1, 0) for c in configuration.suspension)


def remove_suspension(model: Model, configuration: Configuration, n_modes: int = 12,
                      proposed: Configuration | None = None, free_gravity: float = 0.0,
                      mac_floor: float = 0.6) -> Removal:
    """Modes of ``model`` in the tested ``configuration``, free-free (no suspension, no supports,
    gravity factor ``free_gravity``: 0, a structure in free fall, is the flight prediction without
    aerodynamic trim loads) and in ``proposed`` (e.g. 20 m bungees). The free-free elastic modes
    are paired with the others by the mass-weighted MAC of the full shapes (the suspension modes,
    whose energy is mostly in the cords, left out)."""
    if configuration.fixed and proposed is None:
        raise ModelError(f"configuration '{configuration.name}' fixes DOFs: removing its suspension leaves the "
                         "supports; give the free-flying case as a configuration without fixed DOFs")
    extra = 6 + _cord_modes(configuration)  # the suspension modes come first
    suspended = solve_modes(solve_static(model, configuration), n_modes + extra, damped=False)
    free_cfg = Configuration(f"{configuration.name} (free-free)", gravity=free_gravity,
                             gravity_direction=configuration.gravity_direction, g=configuration.g,
                             masses=configuration.masses)
    free_state = solve_static(model, free_cfg)
    free = solve_modes(free_state, n_modes + 6, damped=False)
    other = None
    if proposed is not None:
        other = solve_modes(solve_static(model, proposed), n_modes + 6 + _cord_modes(proposed), damped=False)
    elastic = np.flatnonzero(free.frequencies_hz > 0)[:n_modes]
    M = free_state.system.full_mass_matrix(free_state.positions, free_state.rotations)
    rows = []
    pairs = {}
    for key, modes in (("suspended", suspended), ("proposed", other)):
        if modes is None:
            continue
        from scipy.optimize import linear_sum_assignment
        m = _mass_mac(free, modes, M)[elastic]
        # Modes whose energy is mostly in the suspension (pendulum, plunge) have no free partner.
        m[:, modes.energy_fractions[:, 4] > 0.5] = 0.0
        r, c = linear_sum_assignment(-m)
        pairs[key] = {int(elastic[i]): (int(j), float(m[i, j])) for i, j in zip(r, c) if m[i, j] >= mac_floor}
    for k in elastic:
        row = {"free_mode": int(k) + 1, "label": free.labels[k] if free.labels else "",
               "free_hz": float(free.frequencies_hz[k])}
        for key, modes in (("suspended", suspended), ("proposed", other)):
            if modes is None:
                continue
            got = pairs[key].get(int(k))
            if got is None:
                row.update({f"{key}_mode": None, f"{key}_hz": None, f"{key}_shift_percent": None, f"{key}_mac": None})
                continue
            j, mac = got
            f = float(modes.frequencies_hz[j])
            row.update({f"{key}_mode": j + 1, f"{key}_hz": f,
                        f"{key}_shift_percent": 100 * (f - row["free_hz"]) / row["free_hz"], f"{key}_mac": mac})
        rows.append(row)
    return Removal(suspended, free, other, rows)
