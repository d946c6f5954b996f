"""flexgvt.updating.masstargets: the mass-property rows' derivatives against finite differences."""

import numpy as np

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.updating.masstargets import MassResiduals


def _strip(origin):
    """A 1 m aluminium strip along y with a tip mass offset in x and z, its root at ``origin``."""
    model = fg.Model("strip")
    y = np.linspace(0.0, 1.0, 11)
    nodes = model.add_nodes(np.asarray(origin, float) + np.c_[0 * y, y, 0 * y])
    model.add_beams(np.c_[nodes[:-1], nodes[1:]], fg.Material("al", E=70e9, rho=2700.0, nu=0.33),
                    fg.RectangularSection(0.05, 0.003), name="strip")
    model.add_mass(int(nodes[-1]), 0.010, offset=(0.015, 0.0, 0.002), name="tip")
    return model


def _rows(origin, cg_error):
    model = _strip(origin)
    variables = [up.beam("rho", "strip", "rho"), up.mass("tip_mass", "tip")]
    par = up.Parametrisation(model, [fg.Configuration("free")], variables)
    mp = fg.mass_properties(model)
    target = up.MassTarget(mass=mp.mass, cg=tuple(mp.cg + cg_error), inertia=tuple(np.diag(mp.inertia)))
    work = model.copy()
    return par, work, MassResiduals(target, up.Objective(), par, work), mp


def test_a_cg_error_is_scaled_by_the_mass_spread_and_does_not_depend_on_the_origin():
    """The same strip and the same cg error (mm) in two frames, one with the cg on a symmetry plane
    (x = 0 to round-off), give the same residuals and derivatives: a cg error is divided by the
    model's rms mass spread along the axis (here L / sqrt(12) and so on), not by the coordinate."""
    error = np.array([0.001, -0.002, 0.0005])
    x0 = np.array([1.02, 0.97])
    out = []
    for origin in ((0.0, 0.0, 0.0), (-0.0002, 3.0, -1.5)):
        par, work, rows, mp = _rows(origin, error)
        par.apply(work, x0)
        out.append((rows.vector(rows.properties())[0], rows.derivatives(x0), rows.cg_scales(), mp))
    (r0, j0, s0, mp), (r1, j1, s1, _) = out
    m, d = mp.mass, np.diag(mp.inertia)
    spread = np.sqrt((d.sum() - 2 * d) / (2 * m))
    assert spread[1] > 0.25 and spread[0] > 0.01 and spread[2] < 0.01  # y: the length; z: nearly flat
    np.testing.assert_allclose(s0, np.maximum(spread, 0.01), rtol=1e-12)
    np.testing.assert_allclose(s1, s0, rtol=1e-9)
    np.testing.assert_allclose(r1, r0, rtol=0, atol=1e-9 * np.abs(r0).max())
    np.testing.assert_allclose(j1, j0, rtol=0, atol=1e-9 * np.abs(j0).max())
    assert np.abs(r0[1:4]).min() > 1e-3  # the cg rows are not zero: the comparison means something


def test_the_cg_rows_derivatives_match_finite_differences():
    par, work, rows, _ = _rows((0.0, 0.0, 0.0), np.zeros(3))

    def residuals(x):
        par.apply(work, x)
        return rows.vector(rows.properties())[0]

    x0 = np.array([1.02, 0.97])
    h = 1e-4  # central differences: truncation 3.5e-10 of the largest here, h^2 (1e-3 left 3.5e-8)
    fd = np.column_stack([(residuals(x0 + h * e) - residuals(x0 - h * e)) / (2 * h) for e in np.eye(2)])
    par.apply(work, x0)
    J = rows.derivatives(x0)
    names = rows.vector(rows.properties())[1]
    assert names[1] == "cg_x" and abs(fd[1, 1]) > 1e-3  # the tip mass moves the cg along x
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-8 * np.abs(fd).max())
