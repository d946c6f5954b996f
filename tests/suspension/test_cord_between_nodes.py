"""A cord attached between two nodes (along an element): the same as a node placed there, its
position a design variable with an exact derivative, an attachment off the structure refused."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.errors import ModelError

L, B, T = 2.0, 0.05, 0.003
ATTACH = (-0.7137, 0.6523)  # y of the two attachment points [m]: between nodes of the regular mesh


def _strip(extra_nodes: bool, n: int = 80):
    """A free aluminium strip along y on n elements; with extra_nodes, nodes at the attachment points."""
    ys = np.linspace(-L / 2, L / 2, n + 1)
    if extra_nodes:
        ys = np.sort(np.r_[ys, ATTACH])
    model = fg.Model("strip")
    ids = model.add_nodes(np.c_[np.zeros_like(ys), ys, np.zeros_like(ys)])
    model.add_beams(np.c_[ids[:-1], ids[1:]], fg.Material("Al", E=70e9, nu=0.33, rho=2700.0),
                    fg.RectangularSection(width=B, height=T), orientation=(0, 0, 1), rotary_inertia=False,
                    name="strip")
    cords = []
    weight = 2700.0 * L * B * T * 9.80665 / 2
    for y, k in zip(ATTACH, (5.0, 5.3)):
        if extra_nodes:
            where = dict(node=int(ids[np.argmin(np.abs(ys - y))]))
        else:
            j = int(np.searchsorted(ys, y)) - 1
            where = dict(node=int(ids[j]), node_b=int(ids[j + 1]), along=float(y - ys[j]))
        cords.append(fg.Cord(anchor=(0.0, y, 2.0), stiffness=k, damping=0.3, unstretched_length=2.0 - weight / k,
                             **where))
    return model, fg.Configuration("hung", suspension=cords, gravity=1.0)


def test_cord_between_nodes_equals_a_node_placed_there():
    """The attachment between nodes moves with the element's end translations interpolated
    linearly; a node placed there moves with the beam's own (cubic) shape. The two converge with
    the mesh: measured (max |dz| of the ends / sag, max frequency ratio - 1, 14 complex modes with
    the cords' dampers): 80 elements 1.2e-4, 2.4e-4; 160 elements 2.5e-5, 5.5e-5."""
    errors = {}
    for n in (80, 160):
        out = []
        for extra in (True, False):
            model, cfg = _strip(extra, n)
            state = fg.solve_static(model, cfg)
            out.append((state, fg.solve_modes(state, 14)))
        (s_node, m_node), (s_between, m_between) = out
        sag = np.ptp(s_node.positions[:, 2])
        dz = np.abs(s_between.positions[[0, -1], 2] - s_node.positions[[0, -1], 2]).max() / sag
        df = np.abs(m_between.frequencies_hz / m_node.frequencies_hz - 1).max()
        dzeta = np.abs(m_between.damping_ratio - m_node.damping_ratio).max()
        errors[n] = (dz, df, dzeta)
        assert dz < 2e-4 and df < 3e-4 and dzeta < 1e-4
    assert errors[160][0] < 0.5 * errors[80][0] and errors[160][1] < 0.5 * errors[80][1]


def test_attachment_position_derivative_matches_finite_differences():
    model, cfg = _strip(False)
    modes = fg.solve_modes(fg.solve_static(model, cfg), 12, damped=False, label=False)
    data = [up.Measured("hung", modes.frequencies_hz[modes.frequencies_hz > 0.3][:6] * 1.01)]
    variables = [up.cord("left_along", 0, "along", bounds=(-1.0, 1.0), scale=0.01),
                 up.cord("right_along", 1, "along", bounds=(-1.0, 1.0), scale=0.01)]
    problem = up.UpdatingProblem(model, [cfg], data, variables, static_settings=fg.StaticSettings(tolerance=1e-13))
    x0 = np.array([0.6, 1.3])  # inside the elements: 0.6 * 0.01 m short of / 0.3 * 0.01 m past the start
    J = problem.evaluate(x0, gradient=True).jacobian
    fd = {}
    for h in (2e-2, 1e-2):
        fd[h] = np.column_stack([(problem.evaluate(x0 + h * e).residuals - problem.evaluate(x0 - h * e).residuals)
                                 / (2 * h) for e in np.eye(2)])
    rich = (4 * fd[1e-2] - fd[2e-2]) / 3
    scale = np.abs(rich).max(axis=0)
    assert np.all(scale > 0)
    assert np.all(np.abs(J - rich) <= np.maximum(1e-4 * scale, 3 * np.abs(fd[1e-2] - fd[2e-2])))


def test_attachment_off_the_structure_is_refused():
    model, cfg = _strip(False)
    bad = cfg.suspension[0].__class__(**{**cfg.suspension[0].__dict__, "along": 0.5})
    with pytest.raises(ModelError, match="off the structure"):
        fg.solve_static(model, cfg.with_(suspension=(bad, cfg.suspension[1])))
    with pytest.raises(ModelError, match="needs node_b"):
        fg.Cord(node=1, anchor=(0, 0, 1), stiffness=1.0, unstretched_length=0.5, along=0.1)
    model, cfg = _strip(True)
    with pytest.raises(ModelError, match="hangs at a node"):
        up.Parametrisation(model, [cfg], [up.cord("a", 0, "along", bounds=(0.5, 1.5))])
