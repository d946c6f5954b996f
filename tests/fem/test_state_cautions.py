"""A solution that converged but is physically doubtful says so: cords stretched past their allowance
and displacements larger than the structure (before: the X-HALE under 30 g hung 92 m below its
anchors without a word; its cords stretched 18,772 %)."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import FlexGVTWarning

from fem_builders import straight_beam


def _hung(gravity: float):
    """A 1 m strip (0.4 kg) on two 10 N/m cords of 0.9 m from anchors 1 m above its ends."""
    model, ids = straight_beam(10, length=1.0)
    cords = tuple(fg.Cord(node=int(n), anchor=(0.0, y, 1.0), stiffness=10.0, unstretched_length=0.9)
                  for n, y in ((ids[0], 0.0), (ids[-1], 1.0)))
    return model, fg.Configuration("hung", suspension=cords, gravity=gravity)


def test_a_plausible_suspension_has_no_caution():
    with warnings.catch_warnings():
        warnings.simplefilter("error", FlexGVTWarning)
        state = fg.solve_static(*_hung(1.0))
    assert state.cautions == () and "warning" not in state.summary()
    assert 0.2 < state.cord_length[0] / 0.9 - 1 < 0.4  # about 0.1 m of sag


def test_cords_stretched_far_and_a_structure_hanging_far_below_are_reported():
    with pytest.warns(FlexGVTWarning) as record:
        state = fg.solve_static(*_hung(30.0))
    text = [str(w.message) for w in record if issubclass(w.category, FlexGVTWarning)]
    assert any("2 cord(s) stretched beyond their design length by more than 100% of their unstretched" in t
               for t in text)
    assert any("more than twice the structure's own size (1 m," in t for t in text)
    assert len(state.cautions) == 2
    assert state.summary().count("\n  warning: ") == 2
    strain = state.cord_length / 0.9 - 1
    assert strain.min() > 5.0 and np.linalg.norm(state.displacements[:, :3], axis=1).max() > 5.0


def test_the_cord_allowance_is_a_setting():
    settings = fg.StaticSettings(cord_strain_limit=10.0)
    with pytest.warns(FlexGVTWarning) as record:
        state = fg.solve_static(*_hung(30.0), settings=settings)
    assert len(state.cautions) == 1 and "structure's own size" in state.cautions[0]
    assert not any("cord(s) stretched" in str(w.message) for w in record)


def test_a_displacement_beyond_the_structure_size_on_a_soft_spring_is_reported():
    model, ids = straight_beam(4, length=0.5)
    spring = fg.Spring.make(int(ids[0]), None, stiffness=[0.5, 0.5, 0.5, 1e3, 1e3, 1e3])  # 0.2 kg sags 4 m
    with pytest.warns(FlexGVTWarning, match=r"moves 3\.\d+ m, more than twice the structure's own size \(0\.5 m"):
        state = fg.solve_linear_static(model, fg.Configuration("soft", springs=(spring,), gravity=1.0))
    assert len(state.cautions) == 1
