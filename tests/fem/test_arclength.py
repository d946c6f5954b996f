"""Arc-length control (fem.arclength through StaticSettings(control="arc-length")): the path of a
shallow two-bar truss passes its limit point and snaps through, against the closed form."""

import numpy as np
import pytest
from scipy.optimize import brentq

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.static import StaticSettings

E, A, HALF, RISE = 70e9, 1e-4, 1.0, 0.1
L0 = np.hypot(HALF, RISE)


def _load(y: float) -> float:
    """Downward apex load [N] in equilibrium with the apex at height y [m]: two rods of chord
    strain (l - L0) / L0 (flexgvt's rods), P = 2 E A y (1 / l - 1 / L0)."""
    return 2 * E * A * y * (1 / np.hypot(HALF, y) - 1 / L0)


def _limit() -> tuple[float, float]:
    """dP/dy = 0 at l^3 = a^2 L0: (limit load [N], apex height there [m])."""
    l = (HALF**2 * L0) ** (1 / 3)
    y = np.sqrt(l * l - HALF**2)
    return _load(y), y


def _truss(over: float):
    model = fg.Model("von Mises truss")
    model.add_nodes([[-HALF, 0, 0], [0, 0, RISE], [HALF, 0, 0]], ids=[1, 2, 3])
    model.add_rods([[1, 2], [2, 3]], fg.Material("al", E, 2700.0, nu=0.3), area=A)
    p_cr = _limit()[0]
    config = fg.Configuration("snap", fixed={1: "123456", 3: "123456", 2: "2456"},
                              forces=(fg.NodalLoad(2, force=(0, 0, -over * p_cr)),))
    return model, config, p_cr


def test_two_bar_truss_snaps_through_its_limit_point():
    """Load 1.5 x the closed-form limit load: the arc-length path passes the limit point (found
    within 0.3 %: measured 0.9992 x P_cr), snaps through, and the states at the requested levels are
    those a slowly growing load reaches: 0.75 P_cr on the near branch, 1.35 P_cr and the full load
    on the far (inverted) branch, each the closed-form equilibrium there to 1e-6."""
    model, config, p_cr = _truss(1.5)
    state = fg.solve_static(model, config, settings=StaticSettings(control="arc-length", buckling="ignore"),
                            load_factors=np.array([0.5, 0.9]))
    event = state.instability
    assert event is not None and event.kind == "limit point"
    assert event.load_factor * 1.5 == pytest.approx(1.0, rel=3e-3)
    assert np.linalg.norm(event.shape[1, :3]) == pytest.approx(1.0)  # the apex moves
    y_cr = _limit()[1]
    near = brentq(lambda y: _load(y) - 0.75 * p_cr, y_cr, RISE)
    for got, level, y0 in ((state.steps[0], 0.5, near), (state.steps[1], 0.9, None), (state, 1.0, None)):
        if y0 is None:  # beyond the limit: the inverted branch, rods in tension
            y0 = brentq(lambda y, p=1.5 * level * p_cr: _load(y) - p, -10 * RISE, -RISE)
        assert got.load_factor == pytest.approx(level)
        assert got.positions[1, 2] == pytest.approx(y0, abs=1e-6 * RISE)
        assert abs(got.positions[1, 0]) < 1e-9


def test_arc_length_below_the_limit_matches_load_control():
    """Below the limit load both drivers find the same equilibrium (to 1e-9 of the rise)."""
    model, config, _ = _truss(0.8)
    arc = fg.solve_static(model, config, settings=StaticSettings(control="arc-length", buckling="ignore"))
    plain = fg.solve_static(model, config, settings=StaticSettings(buckling="ignore"))
    assert arc.instability is None
    np.testing.assert_allclose(arc.positions, plain.positions, atol=1e-9 * RISE)


def test_unknown_control_is_refused():
    model, config, _ = _truss(0.5)
    with pytest.raises(ModelError, match="control="):
        fg.solve_static(model, config, settings=StaticSettings(control="displacement"))
