"""Builders shared by the solver tests (imported by name: pytest puts this folder on sys.path)."""

import numpy as np
import flexgvt as fg

AL = fg.Material("Al", E=70e9, nu=0.33, rho=2700.0)


def straight_beam(n, length=1.5, section=None, material=AL, axis=(0.0, 1.0, 0.0), orientation=(0.0, 0.0, 1.0),
                  rotary_inertia=False, origin=(0.0, 0.0, 0.0)):
    """A straight beam of n elements from origin along axis; returns (model, node ids)."""
    model = fg.Model("beam")
    t = np.linspace(0, length, n + 1)[:, None]
    ids = model.add_nodes(np.asarray(origin) + t * np.asarray(axis, float))
    section = section or fg.RectangularSection(width=0.05, height=0.003, shear=False)
    model.add_beams(np.c_[ids[:-1], ids[1:]], material, section, orientation=orientation,
                    rotary_inertia=rotary_inertia)
    return model, ids



def perturbed_state(system, seed: int):
    """A deformed, non-equilibrium state of ``system``: random displacements ~2 cm, rotations ~0.2 rad."""
    rng = np.random.default_rng(seed)
    x, R = system.undeformed
    return system.update(x, R, 0.02 * rng.standard_normal(system.n_free) * np.where(system.rotation_mask, 10.0, 1.0))


def tangent_error(system, x, R, lam: float, h: float = 1e-6) -> tuple[float, np.ndarray]:
    """(max |K - K_fd| / max |K|, K): the assembled tangent at (x, R, lam) against central finite
    differences of the residual (internal - external forces), one reduced DOF at a time."""
    def residual(xs, Rs):
        ev = system.evaluate(xs, Rs, lam, tangent=False)
        return ev.internal - ev.external

    K = system.evaluate(x, R, lam).tangent.toarray()
    FD = np.empty_like(K)
    for j in range(system.n_free):
        e = np.zeros(system.n_free)
        e[j] = h
        FD[:, j] = (residual(*system.update(x, R, e)) - residual(*system.update(x, R, -e))) / (2 * h)
    return float(np.abs(FD - K).max() / np.abs(K).max()), K
