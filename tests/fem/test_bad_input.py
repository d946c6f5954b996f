"""Bad input gives a clear error naming the cause and the remedy, and loses nothing computed."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ConvergenceError, ModelError, SingularModelError

from fem_builders import AL, straight_beam

SEC = fg.RectangularSection(width=0.05, height=0.003)


def test_missing_material_and_section():
    model = fg.Model()
    ids = model.add_nodes([[0, 0, 0], [1, 0, 0]])
    with pytest.raises(ModelError, match="no material"):
        model.add_beams([ids], None, SEC)
    with pytest.raises(ModelError, match="no section"):
        model.add_beams([ids], AL, None)
    with pytest.raises(ModelError, match="shear modulus G .* or Poisson"):
        fg.Material("incomplete", E=70e9, rho=2700.0)


def test_zero_length_element_and_parallel_orientation():
    model = fg.Model()
    ids = model.add_nodes([[0, 0, 0], [0, 0, 0], [1, 0, 0]])
    with pytest.raises(ModelError, match=r"nodes \[1, 2\] has zero length"):
        model.add_beams([[ids[0], ids[1]]], AL, SEC)
    with pytest.raises(ModelError, match="parallel"):
        model.add_beams([[ids[0], ids[2]]], AL, SEC, orientation=(2, 0, 0))


def test_unknown_node_references():
    model, ids = straight_beam(4)
    with pytest.raises(ModelError, match="node 99 does not exist"):
        model.add_mass(99, 1.0)
    cfg = fg.Configuration("bad", fixed={42: "123456"})
    with pytest.raises(ModelError, match="node 42 does not exist"):
        fg.solve_static(model, cfg)


@pytest.mark.parametrize("make", [
    lambda: fg.Model().add_nodes([[0.0, np.nan, 0.0]]),
    lambda: fg.Material("nan", E=np.nan, nu=0.3, rho=1.0),
    lambda: fg.RectangularSection(width=np.nan, height=0.1),
    lambda: fg.NodalLoad(1, force=(0.0, np.inf, 0.0)),
    lambda: fg.Configuration("nan gravity", gravity=np.nan),
    lambda: fg.Cord(node=1, anchor=(0, 0, np.nan), stiffness=1.0, unstretched_length=1.0),
])
def test_nan_in_input_is_refused(make):
    with pytest.raises(ModelError, match="NaN|finite"):
        make()


def test_unconstrained_model_under_load():
    model, ids = straight_beam(10)
    cfg = fg.Configuration("floating", gravity=1.0)
    with pytest.raises(SingularModelError, match="under-constrained.*translation along z"):
        fg.solve_static(model, cfg)
    with pytest.raises(SingularModelError, match="under-constrained"):
        fg.solve_linear_static(model, cfg)


def test_load_that_does_not_converge_keeps_the_last_converged_state():
    """A compressed column pushed far past its buckling load with a side imperfection (no increments
    small enough survive within the iteration budget): the error says at which load level it stopped."""
    model, ids = straight_beam(20, length=1.0)
    P = 50 * np.pi**2 * AL.E * SEC.properties()["Iy"] / 4.0
    cfg = fg.Configuration("overload", fixed={int(ids[0]): "123456"},
                           forces=[fg.NodalLoad(int(ids[-1]), force=(0.0, -P, 1e-3 * P))])
    settings = fg.StaticSettings(increments=4, max_iterations=4, min_increment=0.02)
    with pytest.raises(ConvergenceError, match=r"did not converge beyond load factor") as info:
        fg.solve_static(model, cfg, settings=settings)
    err = info.value
    assert err.state is not None and 0.0 <= err.state.load_factor < 1.0
    assert len(err.history) > 0 and np.all(np.isfinite(err.state.positions))


def test_fixing_a_rigid_link_dependent_is_refused():
    model, ids = straight_beam(4)
    model.add_rigid_link(int(ids[0]), [int(ids[1])])
    with pytest.raises(ModelError, match="tied by a rigid link"):
        fg.solve_static(model, fg.Configuration("bad", fixed={int(ids[1]): "1"}))
