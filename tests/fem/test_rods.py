"""Rods (axial E A + torsion G J, no bending; Nastran CROD): consistent tangent, truss statics and
the transverse frequencies of a pre-tensioned string against closed form."""

import numpy as np
import pytest
from scipy.optimize import brentq

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.system import System

STEEL = fg.Material("steel", E=210e9, nu=0.3, rho=7850.0)


def _residual(system, x, R, lam):
    ev = system.evaluate(x, R, lam, tangent=False)
    return ev.internal - ev.external


def test_rod_tangent_matches_finite_differences():
    model = fg.Model("rod net")
    ids = model.add_nodes([[0, 0, 0], [1.0, 0.1, 0.0], [2.0, -0.2, 0.3], [1.2, 1.0, 0.4]])
    model.add_rods([[ids[0], ids[1]], [ids[1], ids[2]], [ids[1], ids[3]], [ids[2], ids[3]]], STEEL,
                   area=1e-4, torsion_constant=2e-9)
    cfg = fg.Configuration("check", fixed={int(ids[0]): "123456"}, gravity=1.0)
    system = System(model, cfg)
    rng = np.random.default_rng(7)
    x, R = system.undeformed
    x, R = system.update(x, R, 0.01 * rng.standard_normal(system.n_free))  # stretched, rotated, off equilibrium
    K = system.evaluate(x, R, 1.0).tangent.toarray()
    h = 1e-7
    FD = np.empty_like(K)
    for j in range(system.n_free):
        e = np.zeros(system.n_free)
        e[j] = h
        FD[:, j] = (_residual(system, *system.update(x, R, e), 1.0)
                    - _residual(system, *system.update(x, R, -e), 1.0)) / (2 * h)
    assert np.abs(FD - K).max() / np.abs(K).max() < 1e-6
    # Nodal rotations alone strain no rod (a beam's shallow-arch term would: ~EA theta^2 / 30 = 0.7 N here).
    x0, R0 = system.undeformed
    turned = system.update(x0, R0, np.where(system.rotation_mask, 1e-3, 0.0) * rng.standard_normal(system.n_free))
    assert np.abs(system.evaluate(*turned, 0.0, tangent=False).axial_forces).max() < 1e-9 * STEEL.E * 1e-4


def test_two_bar_truss_against_closed_form():
    """Symmetric V truss, apex load F: bar force F / (2 sin a), apex drop F L / (2 E A sin^2 a)."""
    a, L, A, F = np.radians(40.0), 1.5, 2e-4, 5e3
    model = fg.Model("truss")
    ids = model.add_nodes([[-L * np.cos(a), 0, L * np.sin(a)], [L * np.cos(a), 0, L * np.sin(a)], [0, 0, 0]])
    model.add_rods([[ids[0], ids[2]], [ids[1], ids[2]]], STEEL, area=A)
    cfg = fg.Configuration("load", fixed={int(ids[0]): "123456", int(ids[1]): "123456", int(ids[2]): "2456"},
                           forces=[fg.NodalLoad(int(ids[2]), force=(0.0, 0.0, -F))])
    lin = fg.solve_linear_static(model, cfg)
    drop = -lin.displacements[2, 2]
    assert drop == pytest.approx(F * L / (2 * STEEL.E * A * np.sin(a) ** 2), rel=1e-9)
    # Large-displacement equilibrium of the same truss, exact: 2 N(d) (L sin a + d) / l(d) = F.
    EA = STEEL.E * A

    def unbalance(d):
        length = np.hypot(L * np.cos(a), L * np.sin(a) + d)
        return 2 * EA * (length - L) / L * (L * np.sin(a) + d) / length - F

    d = brentq(unbalance, 0.0, 0.1 * L, xtol=1e-15)
    nl = fg.solve_static(model, cfg)
    assert -nl.displacements[2, 2] == pytest.approx(d, rel=1e-8)
    assert nl.axial_forces == pytest.approx(np.full(2, EA * (np.hypot(L * np.cos(a), L * np.sin(a) + d) - L) / L),
                                            rel=1e-6)  # the bars hang: tension


@pytest.mark.parametrize("mass", ["lumped", "consistent"])
def test_pretensioned_string_frequencies(mass):
    """A rod chain pulled by T: transverse modes f_n = n / (2 L) sqrt(T / (rho A)) (continuum), and the
    lumped chain's exact discrete values 2 sqrt(T / (m h)) sin(n pi / 2N) / (2 pi)."""
    n_el, L, A, T = 100, 2.0, 1e-6, 200.0
    model = fg.Model("string")
    x = np.linspace(0, L, n_el + 1)
    ids = model.add_nodes(np.c_[x, 0 * x, 0 * x])
    model.add_rods(np.c_[ids[:-1], ids[1:]], STEEL, area=A, mass=mass)
    fixed = {int(i): "456" for i in ids}
    fixed[int(ids[0])] = "123456"
    fixed[int(ids[-1])] = "23456"  # free to slide along the string
    cfg = fg.Configuration("tension", fixed=fixed, forces=[fg.NodalLoad(int(ids[-1]), force=(T, 0.0, 0.0))])
    state = fg.solve_static(model, cfg)
    assert state.axial_forces == pytest.approx(np.full(n_el, T), rel=1e-9)
    modes = fg.solve_modes(state, n_modes=8, label=False)
    f = np.sort(modes.frequencies_hz)[::2][:3]  # each transverse mode twice (y and z)
    m_lin = STEEL.rho * A
    length = L * (1 + T / (STEEL.E * A))
    n = np.arange(1, 4)
    continuum = n / (2 * length) * np.sqrt(T / (m_lin * L / length))
    assert f == pytest.approx(continuum, rel=1e-3)
    if mass == "lumped":
        h = length / n_el
        discrete = 2 * np.sqrt(T / (m_lin * L / n_el * h)) * np.sin(n * np.pi / (2 * n_el)) / (2 * np.pi)
        assert f == pytest.approx(discrete, rel=1e-8)


def test_rod_bad_input():
    model = fg.Model("bad")
    ids = model.add_nodes([[0, 0, 0], [1, 0, 0]])
    with pytest.raises(ModelError, match="A="):
        model.add_rods([[ids[0], ids[1]]], STEEL, area=0.0)
    with pytest.raises(ModelError, match="J="):
        model.add_rods([[ids[0], ids[1]]], STEEL, area=1e-4, torsion_constant=-1.0)
    with pytest.raises(ModelError, match="zero length"):
        model.add_rods([[ids[0], ids[0]]], STEEL, area=1e-4)
