"""Linear constraints on translations (Nastran MPC): sum a_j u_j = 0, u = x - X.

Two equal parallel cantilevers of tip stiffness k = 3 E I / L^3 whose tip deflections are tied
by w_B = 2 w_A: a tip force P on A gives w_A = P / (5 k) (energy k w^2 / 2 + k (2 w)^2 / 2).
Under a large load the relation holds exactly in the total translations."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.rotations import logm_so3

from fem_builders import AL

L, N = 1.0, 10
SECTION = fg.RectangularSection(width=0.04, height=0.006, shear=False)


def lever_pair(ratio=2.0):
    model = fg.Model("lever pair")
    x = np.linspace(0, L, N + 1)
    a = model.add_nodes(np.c_[x, np.zeros_like(x), np.zeros_like(x)])
    b = model.add_nodes(np.c_[x, np.full_like(x, 0.2), np.zeros_like(x)])
    for ids in (a, b):
        model.add_beams(np.c_[ids[:-1], ids[1:]], AL, SECTION, orientation=(0, 0, 1))
    model.add_constraint([(int(b[-1]), 3, 1.0), (int(a[-1]), 3, -ratio)])
    cfg = fg.Configuration("clamped", fixed={int(a[0]): "123456", int(b[0]): "123456"})
    return model, cfg, a, b


def test_lever_constraint_against_the_energy_solution():
    model, cfg, a, b = lever_pair()
    P = 3.0
    state = fg.solve_linear_static(model, cfg.with_(forces=(fg.NodalLoad(int(a[-1]), force=(0, 0, -P)),)))
    k = 3 * AL.E * SECTION.properties()["Iy"] / L**3
    wa, wb = state.displacements[model.index_of([int(a[-1]), int(b[-1])]), 2]
    assert wa == pytest.approx(-P / (5 * k), rel=1e-9)
    assert wb == pytest.approx(2 * wa, rel=1e-12)


def test_constraint_holds_exactly_under_large_displacement():
    model, cfg, a, b = lever_pair(ratio=0.5)
    state = fg.solve_static(model, cfg.with_(forces=(fg.NodalLoad(int(a[-1]), force=(0, 0, -60.0)),)))
    ia, ib = model.index_of([int(a[-1]), int(b[-1])])
    u = state.displacements
    assert abs(u[ia, 2]) > 0.2 * L
    assert u[ib, 2] == pytest.approx(0.5 * u[ia, 2], rel=1e-12)


def test_rotation_constraint_shares_a_torque():
    """Tip twists tied (theta_x,B = theta_x,A): a torque T on A twists both by T L / (2 G J)."""
    model, cfg, a, b = lever_pair()
    model.add_constraint([(int(b[-2]), 4, 1.0), (int(a[-2]), 4, -1.0)])
    T = 0.5
    state = fg.solve_linear_static(model, cfg.with_(forces=(fg.NodalLoad(int(a[-2]), moment=(T, 0, 0)),)))
    GJ = AL.shear_modulus * SECTION.properties()["J"]
    L_twist = L * (N - 1) / N
    ta, tb = logm_so3(state.rotations[model.index_of([int(a[-2]), int(b[-2])])])[:, 0]
    assert ta == pytest.approx(T * L_twist / (2 * GJ), rel=1e-9) and tb == pytest.approx(ta, rel=1e-12)


def test_bad_constraints_are_refused():
    model, cfg, a, b = lever_pair()
    with pytest.raises(ModelError, match="must be 1-6"):
        model.add_constraint([(int(a[3]), 7, 1.0), (int(b[3]), 5, -1.0)])
    with pytest.raises(ModelError, match="already the dependent DOF"):
        model.add_constraint([(int(b[-1]), 3, 1.0), (int(a[4]), 3, -1.0)])
    model.add_constraint([(int(a[5]), 1, 1.0), (int(b[-1]), 3, -1.0)])  # depends on a dependent DOF
    with pytest.raises(ModelError, match="chains are not supported"):
        fg.solve_static(model, cfg)
