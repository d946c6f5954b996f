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

