"""The same state gives the same modes, bit for bit: ARPACK starts from a fixed vector in both the
real and the complex (damped) eigensolvers. With ARPACK's random start, the highest damped roots of
the strip on its damped cords moved by ~3e-9 from one call to the next."""

import numpy as np

import flexgvt as fg
from flexgvt.fem.eigen import DENSE_LIMIT


def test_damped_modes_repeat_exactly():
    case = fg.cases.strip_366()
    state = fg.solve_static(case.model, case.configurations["outboard"])
    assert 6 * case.model.n_nodes > DENSE_LIMIT // 2  # the sparse (ARPACK) path of complex_modes
    first = fg.solve_modes(state, n_modes=10)
    assert first.complex_shapes is not None  # damped cords: the complex eigensolver
    for _ in range(2):
        again = fg.solve_modes(state, n_modes=10)
        assert np.array_equal(again.frequencies_hz, first.frequencies_hz)
        assert np.array_equal(again.damping_ratio, first.damping_ratio)
