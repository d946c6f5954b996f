"""Large displacements and rotations against analytic and published solutions."""

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipeinc, ellipkinc

import flexgvt as fg

from fem_builders import AL, straight_beam

SEC = fg.RectangularSection(width=0.05, height=0.003, shear=False)
EI = AL.E * SEC.properties()["Iy"]
L = 1.5


def elastica_tip(alpha: float) -> tuple[float, float]:
    """Cantilever with a tip force perpendicular to it, alpha = P L^2 / EI (Bisshopp-Drucker).

    Returns (horizontal tip position, vertical deflection) / L from elliptic integrals.
    """
    def residual(theta0):
        k = np.sqrt((1 + np.sin(theta0)) / 2)
        phi1 = np.arcsin(1 / (np.sqrt(2) * k))
        return ellipkinc(np.pi / 2, k**2) - ellipkinc(phi1, k**2) - np.sqrt(alpha)

    theta0 = brentq(residual, 1e-9, np.pi / 2 - 1e-12)
    k = np.sqrt((1 + np.sin(theta0)) / 2)
    phi1 = np.arcsin(1 / (np.sqrt(2) * k))
    x = np.sqrt(2 * np.sin(theta0) / alpha)
    v = 1 - 2 / np.sqrt(alpha) * (ellipeinc(np.pi / 2, k**2) - ellipeinc(phi1, k**2))
    return x, v


def test_elliptic_reference_matches_mattiasson_table():
    # Mattiasson (1981) tabulates, for PL^2/EI = 1 and 10: u/L = 0.05643, 0.55500; w/L = 0.30172, 0.81061.
    for alpha, u, w in ((1.0, 0.05643, 0.30172), (10.0, 0.55500, 0.81061)):
        x, v = elastica_tip(alpha)
        assert abs((1 - x) - u) < 2e-4 and abs(v - w) < 2e-4


@pytest.mark.parametrize("alpha", [1.0, 3.0, 10.0])
def test_cantilever_tip_force_against_elastica(alpha):
    model, ids = straight_beam(40, L, SEC)
    P = alpha * EI / L**2
    cfg = fg.Configuration("tip force", fixed={int(ids[0]): "123456"},
                           forces=[fg.NodalLoad(int(ids[-1]), force=(0.0, 0.0, -P))])
    state = fg.solve_static(model, cfg)
    tip = state.positions[-1]
    x_ref, v_ref = elastica_tip(alpha)
    assert tip[1] / L == pytest.approx(x_ref, rel=5e-3, abs=5e-3 * 1)
    assert -tip[2] / L == pytest.approx(v_ref, rel=5e-3)


def test_end_moment_rolls_cantilever_into_a_full_circle():
    model, ids = straight_beam(40, L, SEC)
    M = 2 * np.pi * EI / L
    cfg = fg.Configuration("end moment", fixed={int(ids[0]): "123456"},
                           forces=[fg.NodalLoad(int(ids[-1]), moment=(M, 0.0, 0.0))])
    final = fg.solve_static(model, cfg, load_factors=[0.5])
    (half,) = final.steps
    # Full circle: the tip is back at the root (within 0.5 % of L), turned by 2 pi.
    assert np.linalg.norm(final.positions[-1] - final.positions[0]) < 5e-3 * L
    np.testing.assert_allclose(final.rotations[-1], np.eye(3), atol=5e-3)
    # Half the moment: a semicircle, tip at 2 L / pi above the root, pointing back.
    np.testing.assert_allclose(half.positions[-1], [0.0, 0.0, 2 * L / np.pi], atol=5e-3 * L)
    # Every node on the circle of radius L / (2 pi) through the root.
    centre = np.array([0.0, 0.0, L / (2 * np.pi)])
    radii = np.linalg.norm(final.positions - centre, axis=1)
    np.testing.assert_allclose(radii, L / (2 * np.pi), rtol=5e-3)


def test_bathe_bolourchi_45_degree_bend():
    """45-degree bend, radius 100, 8 elements, tip force 600 out of plane (Bathe & Bolourchi 1979).

    Published tip positions at P = 600: Bathe-Bolourchi (15.9, 47.2, 53.4); Simo & Vu-Quoc
    (15.79, 47.23, 53.37). Each component within 1 % of the tip displacement of their mean.
    """
    R = 100.0
    theta = np.linspace(0, np.pi / 4, 9)
    model = fg.Model("45-degree bend")
    # The bend starts at the origin along y and curves towards +x about the centre (100, 0, 0).
    ids = model.add_nodes(np.c_[R * (1 - np.cos(theta)), R * np.sin(theta), np.zeros(9)])
    mat = fg.Material("bend", E=1e7, G=0.5e7, rho=1.0)
    sec = fg.GeneralSection(A=1.0, Iy=1 / 12, Iz=1 / 12, J=0.1406)
    model.add_beams(np.c_[ids[:-1], ids[1:]], mat, sec, orientation=(0, 0, 1))
    cfg = fg.Configuration("P=600", fixed={int(ids[0]): "123456"},
                           forces=[fg.NodalLoad(int(ids[-1]), force=(0, 0, 600.0))])
    state = fg.solve_static(model, cfg)
    published = np.array([[15.9, 47.2, 53.4], [15.79, 47.23, 53.37]]).mean(axis=0)
    tip0 = np.array([R * (1 - np.cos(np.pi / 4)), R * np.sin(np.pi / 4), 0.0])
    scale = np.linalg.norm(published - tip0)
    assert np.all(np.abs(state.positions[-1] - published) < 0.01 * scale), state.positions[-1]
