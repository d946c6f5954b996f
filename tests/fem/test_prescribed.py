"""Enforced displacements and rotations (Configuration.prescribed, Nastran SPCD) against closed form."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError

from fem_builders import AL

L, W, T = 1.0, 0.05, 0.003


def cantilever(n=40):
    model = fg.Model("cantilever")
    x = np.linspace(0, L, n + 1)
    ids = model.add_nodes(np.c_[x, 0 * x, 0 * x])
    model.add_beams(np.c_[ids[:-1], ids[1:]], AL, fg.RectangularSection(width=W, height=T, shear=False),
                    orientation=(0, 0, 1), rotary_inertia=False)
    return model, ids


def test_enforced_tip_deflection_gives_the_cubic_shape():
    """Cantilever with its tip pushed by d (rotation free): w(x) = d (3 x^2 L - x^3) / (2 L^3)."""
    model, ids = cantilever()
    d = 1e-4
    cfg = fg.Configuration("push", fixed={int(ids[0]): "123456"}, prescribed={int(ids[-1]): {3: d}})
    for state in (fg.solve_linear_static(model, cfg), fg.solve_static(model, cfg)):
        x = model.xyz[:, 0]
        w = state.displacements[:, 2]
        np.testing.assert_allclose(w, d * (3 * x**2 * L - x**3) / (2 * L**3), rtol=1e-6, atol=1e-6 * d)


def test_enforced_end_rotation_rolls_the_beam_into_an_arc():
    """Tip rotation theta prescribed (translations free): pure bending, a circular arc of curvature
    theta / L; the tip at (L sin(theta) / theta, 0, L (1 - cos(theta)) / theta). Exact for any theta."""
    model, ids = cantilever()
    theta = 2.0  # rad: a large rotation
    cfg = fg.Configuration("roll", fixed={int(ids[0]): "123456", int(ids[-1]): "46"},
                           prescribed={int(ids[-1]): {5: -theta}})  # about -y lifts the tip towards +z
    state = fg.solve_static(model, cfg)
    tip = state.positions[-1]
    np.testing.assert_allclose(tip, [L * np.sin(theta) / theta, 0.0, L * (1 - np.cos(theta)) / theta], atol=1e-6 * L)
    EI = AL.E * W * T**3 / 12
    # The reaction of a pure bending state is the moment EI theta / L everywhere: no axial force.
    assert np.abs(state.axial_forces).max() < 1e-6 * EI * theta / L / T


def test_prescribed_input_errors():
    model, ids = cantilever(4)
    with pytest.raises(ModelError, match="other rotations"):
        fg.Configuration("bad", prescribed={int(ids[-1]): {4: 0.1}})
    with pytest.raises(ModelError, match="one component"):
        fg.Configuration("bad", prescribed={int(ids[-1]): {"13": 0.1}})
    with pytest.raises(ModelError, match="prescribed"):
        fg.solve_static(model, fg.Configuration("bad", fixed={int(ids[0]): "123456"}, prescribed={999: {1: 0.1}}))
