"""flexgvt.updating.masstargets: the mass-property rows' derivatives against finite differences."""

import numpy as np

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.updating.masstargets import MassResiduals


def test_a_round_off_reference_cg_scales_the_residual_and_its_derivative_alike():
    """A reference cg of 1e-20 m (a symmetry plane's round-off) takes the target's cg_scale in the
    residual and in its derivative: the derivative divided by the round-off instead was O(1) noise
    on the wingbox and held the verification's update to a crawl."""
    case = fg.cases.cantilever_strip(n_elements=30)
    model = case.model
    tip = int(case.references["tip_node"])
    model.add_mass(tip, 0.010, offset=(0.015, 0.0, 0.002), name="tip")
    variables = [up.beam("rho2", "region2", "rho"), up.mass("tip_mass", "tip")]
    par = up.Parametrisation(model, [case.configurations["unloaded"]], variables)
    mp = fg.mass_properties(model)
    target = up.MassTarget(mass=mp.mass, cg=(1e-20, float(mp.cg[1]), 0.0), inertia=tuple(np.diag(mp.inertia)))
    work = model.copy()
    rows = MassResiduals(target, up.Objective(), par, work)
    assert rows.cg_scales().tolist() == [0.01, abs(float(mp.cg[1])), 0.01]

    def residuals(x):
        par.apply(work, x)
        return rows.vector(rows.properties())[0]

    x0 = np.array([1.02, 0.97])
    h = 1e-3
    fd = np.column_stack([(residuals(x0 + h * e) - residuals(x0 - h * e)) / (2 * h) for e in np.eye(2)])
    par.apply(work, x0)
    J = rows.derivatives(x0)
    names = rows.vector(rows.properties())[1]
    assert names[1] == "cg_x" and abs(fd[1, 1]) > 1e-3  # the tip mass moves the cg along x
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-8 * np.abs(fd).max())
