"""One model, many configurations; a static state warm-starts the next solve."""

import numpy as np

import flexgvt as fg


def test_warm_start_from_a_nearby_design_matches_the_cold_solution_in_fewer_iterations():
    base = fg.cases.cantilever_strip(n_elements=30)
    stiffer = fg.cases.cantilever_strip(n_elements=30, E=73.5e9)  # a design point 5 % away
    cfg = base.configurations["flatwise_2g"]
    previous = fg.solve_static(base.model, cfg)
    cold = fg.solve_static(stiffer.model, cfg)
    warm = fg.solve_static(stiffer.model, cfg, start=previous)
    np.testing.assert_allclose(warm.positions, cold.positions, atol=1e-9)
    assert len(warm.history) < len(cold.history) / 3


def test_one_model_many_configurations_without_copying():
    case = fg.cases.cantilever_strip(n_elements=30)
    states = {name: fg.solve_static(case.model, cfg) for name, cfg in case.configurations.items()}
    tips = [s.displacements[-1, 2] for s in states.values()]
    assert tips[0] == 0.0 and tips[1] > tips[2] > tips[3]  # droop grows with the load factor (z negative)
    assert all(s.model is case.model for s in states.values())
    assert len({id(s.system.cm) for s in states.values()}) == 1  # the model's arrays are compiled once


def test_symmetric_and_superlu_paths_reach_the_same_equilibrium():
    """StaticSettings(cholmod=True): the installed symmetric factorisation (PARDISO, or CHOLMOD)."""
    import pytest

    from flexgvt.fem.linsolve import HAVE_FAST

    if not HAVE_FAST:
        pytest.skip("neither pypardiso nor scikit-sparse is installed: only the SuperLU path exists here")
    case = fg.cases.strip_366()
    cfg = case.configurations["outboard"]
    a = fg.solve_static(case.model, cfg, settings=fg.StaticSettings(cholmod=True))
    b = fg.solve_static(case.model, cfg, settings=fg.StaticSettings(cholmod=False))
    np.testing.assert_allclose(a.positions, b.positions, atol=1e-8)
