"""solve_static returns one type: a State, with the states at load_factors in its steps."""

import numpy as np
import pytest

import flexgvt as fg
from fem_builders import straight_beam


def _cantilever():
    model, ids = straight_beam(20)
    return model, fg.Configuration("self weight", fixed={int(ids[0]): "123456"}, gravity=1.0)


def test_steps_hold_the_states_at_the_requested_load_factors():
    model, cfg = _cantilever()
    state = fg.solve_static(model, cfg, load_factors=[0.25, 0.5])
    assert isinstance(state, fg.State)
    assert [s.load_factor for s in state.steps] == pytest.approx([0.25, 0.5])
    assert state.load_factor == 1.0
    tip = [abs(s.positions[-1, 2] - s.system.cm.xyz[-1, 2]) for s in (*state.steps, state)]
    assert tip[0] < tip[1] < tip[2]
    assert fg.solve_static(model, cfg).steps == ()


def test_keep_steps_still_returns_the_pair_and_warns():
    model, cfg = _cantilever()
    with pytest.warns(DeprecationWarning, match=r"\.steps"):
        final, saved = fg.solve_static(model, cfg, load_factors=[0.5], keep_steps=True)
    assert isinstance(saved, list) and len(saved) == 1
    np.testing.assert_array_equal(saved[0].positions, final.steps[0].positions)
