"""Mass properties of undeformed and deformed structures."""

import numpy as np
import pytest

import flexgvt as fg

from fem_builders import AL, straight_beam

SEC = fg.RectangularSection(width=0.05, height=0.003)
L = 1.5


def test_strip_with_offset_mass_closed_form():
    model, ids = straight_beam(30, L, SEC)
    m_tip, off = 0.2, np.array([0.03, 0.0, 0.01])
    model.add_mass(int(ids[-1]), m_tip, offset=off, inertia=[1e-4, 2e-4, 3e-4])
    mp = fg.mass_properties(model)
    p = SEC.properties()
    m_strip = AL.rho * p["A"] * L
    assert mp.mass == pytest.approx(m_strip + m_tip, rel=1e-12)
    tip = np.array([0, L, 0]) + off
    cg = (m_strip * np.array([0, L / 2, 0]) + m_tip * tip) / (m_strip + m_tip)
    np.testing.assert_allclose(mp.cg, cg, atol=1e-12)
    # Strip: rod inertia m L^2 / 12 about x and z through its centre, rho*Ip*L about its axis
    # (no bending rotary inertia in this model); plus the offset mass by the parallel-axis rule.
    def point(m, r):
        return m * (r @ r * np.eye(3) - np.outer(r, r))
    I = point(m_strip, np.array([0, L / 2, 0]) - cg) + np.diag([m_strip * L**2 / 12, AL.rho * p["Ip"] * L,
                                                              m_strip * L**2 / 12])
    I += point(m_tip, tip - cg) + np.diag([1e-4, 2e-4, 3e-4])
    np.testing.assert_allclose(mp.inertia, I, rtol=1e-9, atol=1e-12)


def test_cg_moves_with_the_deformed_shape():
    case = fg.cases.cantilever_strip(n_elements=30)
    undeformed = fg.mass_properties(case.model)
    state = fg.solve_static(case.model, case.configurations["self_weight"])
    deformed = fg.mass_properties(state)
    assert deformed.mass == pytest.approx(undeformed.mass, rel=1e-12)
    assert deformed.cg[2] < -0.02 and abs(undeformed.cg[2]) < 1e-12
    assert deformed.cg[1] < undeformed.cg[1]  # the tip swings inwards as it droops
