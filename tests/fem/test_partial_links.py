"""Rigid links on a subset of components (RBE2 '123': a ball joint).

Two equal cantilevers facing each other, tips joined at a point loaded by P: joined by a ball
joint each carries P/2 as a cantilever, w = P L^3 / (6 E I); joined rigidly they form one
clamped-clamped beam of span 2L, w = P (2L)^3 / (192 E I). Under large rotation the tied
components follow the independent node exactly and the untied ones stay free."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.rotations import logm_so3

from fem_builders import AL

L, N = 1.0, 10
SECTION = fg.RectangularSection(width=0.04, height=0.006, shear=False)


def facing_cantilevers(components):
    model = fg.Model("hinged pair")
    left = model.add_nodes(np.c_[np.linspace(0, L, N + 1), np.zeros(N + 1), np.zeros(N + 1)])
    right = model.add_nodes(np.c_[np.linspace(L, 2 * L, N + 1), np.zeros(N + 1), np.zeros(N + 1)])
    for ids in (left, right):
        model.add_beams(np.c_[ids[:-1], ids[1:]], AL, SECTION, orientation=(0, 0, 1))
    model.add_rigid_link(int(left[-1]), [int(right[0])], components=components)
    return model, left, right


@pytest.mark.parametrize("components, factor", [("123", 1 / 6), ("123456", 8 / 192)])
def test_ball_joint_and_rigid_joint_against_beam_theory(components, factor):
    model, left, right = facing_cantilevers(components)
    P = 2.0
    cfg = fg.Configuration("point load", fixed={int(left[0]): "123456", int(right[-1]): "123456"},
                           forces=[fg.NodalLoad(int(left[-1]), force=(0, 0, -P))])
    state = fg.solve_linear_static(model, cfg)
    EI = AL.E * SECTION.properties()["Iy"]
    w = -state.displacements[model.index_of([int(left[-1]), int(right[0])]), 2]
    np.testing.assert_allclose(w, factor * P * L**3 / EI, rtol=1e-9)
    slopes = logm_so3(state.rotations[model.index_of([int(left[-1]), int(right[0])])])[:, 1]
    if components == "123":  # a hinge: the two sides turn oppositely (antisymmetric slopes)
        assert slopes[0] == pytest.approx(-slopes[1], rel=1e-9) and abs(slopes[0]) > 1e-3
    else:
        np.testing.assert_allclose(slopes, 0.0, atol=1e-12)


def test_ball_joint_under_large_rotation_ties_only_its_components():
    model, left, right = facing_cantilevers("123")
    cfg = fg.Configuration("big", fixed={int(left[0]): "123456", int(right[-1]): "234"},
                           forces=[fg.NodalLoad(int(left[-1]), force=(0, 0, -40.0))])
    state = fg.solve_static(model, cfg)
    i, d = model.index_of([int(left[-1]), int(right[0])])
    assert np.linalg.norm(state.displacements[i, :3]) > 0.1 * L  # genuinely large
    np.testing.assert_allclose(state.positions[d], state.positions[i], atol=1e-12)
    # The joint transmits no moment: the right beam, pinned and on a roller, stays straight.
    xr = state.positions[model.index_of(right)]
    chord = (xr[-1] - xr[0]) / np.linalg.norm(xr[-1] - xr[0])
    off_line = (xr - xr[0]) - np.outer((xr - xr[0]) @ chord, chord)
    assert np.abs(off_line).max() < 1e-9 * L
    assert not np.allclose(state.rotations[d], state.rotations[i], atol=1e-3)


def test_partial_rotation_components_are_refused():
    model, left, right = facing_cantilevers("123456")
    with pytest.raises(ModelError, match="some rotations but not all three"):
        model.add_rigid_link(int(right[3]), [int(right[4])], components="1235")
