"""The solver's own checks (fem/checks.py): overflowing values, free parts, massless models. Each
raises a FlexGVTError naming the entities and the remedy, never a LinAlgError, NaN or empty result.
The decks are the fuzzing trial's reproducers (tests/data/reliability/fem/README.md); the Model API
cases build the same situations, so the solver's checks stay tested if the reader refuses them first."""

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg
from typer.testing import CliRunner

from flexgvt.cli.main import app
from flexgvt.errors import FlexGVTError, ModelError

from fem_builders import AL, straight_beam

DECKS = Path(__file__).parents[1] / "data" / "reliability" / "fem"
SEC = fg.RectangularSection(width=0.05, height=0.003, shear=False)


@pytest.mark.parametrize("name", ["mat1_rho_1e308.bdf", "grid_x_1e300.bdf", "prod_j_1e308.bdf",
                                  "conm2_x1_1e308.dat"])
def test_fuzzed_decks_give_a_flexgvt_error(name):
    from flexgvt.workflow.deck import solve_deck
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the reader's notes on the odd decks
        # The reader may refuse the value first (its own message); either way one clear error.
        with pytest.raises(FlexGVTError):
            solve_deck(DECKS / name)
        result = CliRunner().invoke(app, ["solve", str(DECKS / name)])
        assert result.exit_code == 2 and "error:" in result.output and "Traceback" not in result.output


def _clamped(model, ids, **kw):
    return fg.Configuration("c", fixed={int(ids[0]): "123456"}, **kw)


def test_absurd_density_names_the_group():
    model, ids = straight_beam(4, material=fg.Material("heavy", E=70e9, nu=0.3, rho=1e308))
    with pytest.raises(ModelError, match=r"beam element\(s\) 1, 2, 3, 4 \(group .*rho"):
        fg.solve_static(model, _clamped(model, ids))


def test_absurd_torsion_constant_names_the_element():
    model, ids = straight_beam(2)
    extra = model.add_nodes([[0.0, 2.0, 0.0]])
    model.add_beams([[ids[-1], extra[0]]], AL, fg.GeneralSection(A=1e-4, Iy=1e-9, Iz=1e-9, J=1e308), name="bad")
    with pytest.raises(ModelError, match=r"beam element\(s\) 3 \(group 'bad'\).*section"):
        fg.solve_static(model, _clamped(model, ids))


def test_node_far_away_is_named():
    model, ids = straight_beam(2)
    far = model.add_nodes([[1e300, 0.0, 0.0]])
    model.add_beams([[ids[-1], far[0]]], AL, SEC)
    with pytest.raises(ModelError, match=rf"model .*: node\(s\) {far[0]} lie beyond 1e\+10 m"):
        fg.solve_static(model, _clamped(model, ids))


def test_mass_offset_that_overflows_is_named():
    model, ids = straight_beam(3)
    model.add_mass(int(ids[2]), 2305.2, offset=(1e308, 0.0, 0.0))
    with pytest.raises(ModelError, match=rf"concentrated mass\(es\) at node\(s\) {ids[2]}"):
        fg.solve_static(model, _clamped(model, ids))


def test_a_nan_matrix_never_reaches_the_eigensolver():
    """A state whose matrices hold NaN (a diverged state) gives a ModelError naming nodes and DOFs."""
    model, ids = straight_beam(4)
    state = fg.solve_static(model, _clamped(model, ids))
    pos = state.positions.copy()
    pos[2, 0] = np.nan
    bad = dataclasses.replace(state, positions=pos)
    with pytest.raises(ModelError, match=r"stiffness matrix has entries that are NaN, infinite or beyond .* DOF\(s\) "
                                         rf"of 3 node\(s\) \({ids[1]} x.*beam element\(s\) 1, 2, 3"):
        fg.solve_modes(bad, 3)


def test_real_modes_refuses_non_finite_matrices():
    import scipy.sparse as sp
    from flexgvt.errors import SolverError
    K = sp.csc_matrix(np.diag([1.0, np.inf, 2.0]))
    with pytest.raises(SolverError, match="NaN or infinite"):
        fg.fem.modes.real_modes(K, sp.identity(3, format="csc"), 2)


@pytest.mark.parametrize("n_el", [4, 60])  # the dense and the sparse eigensolver paths
def test_a_massless_model_raises_instead_of_returning_no_mode(n_el):
    model, ids = straight_beam(n_el, material=fg.Material("massless", E=70e9, nu=0.3, rho=0.0))
    state = fg.solve_static(model, _clamped(model, ids))
    with pytest.raises(ModelError, match="free DOFs carry no mass.*density rho.*add_mass"):
        fg.solve_modes(state, 5)


def test_mass_only_on_fixed_dofs_raises():
    model, ids = straight_beam(4, material=fg.Material("massless", E=70e9, nu=0.3, rho=0.0))
    model.add_mass(int(ids[0]), 3.0)  # on the clamped node
    state = fg.solve_static(model, _clamped(model, ids))
    with pytest.raises(ModelError, match="no mass"):
        fg.solve_modes(state, 5)


def _two_parts():
    model, ids = straight_beam(10)
    other = model.add_nodes([[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 2.0, 0.0]])
    model.add_beams(np.c_[other[:-1], other[1:]], AL, SEC)
    return model, ids, other


def test_a_free_disconnected_part_is_named():
    """Before: Newton 'did not converge beyond load factor 0' without naming the part."""
    model, ids, other = _two_parts()
    msg = rf"falls apart into 2 parts and a part of 3 node\(s\) \(ids {other[0]}, {other[1]}, {other[2]}\) is free"
    with pytest.raises(ModelError, match=msg):
        fg.solve_static(model, _clamped(model, ids, gravity=1.0))
    with pytest.raises(ModelError, match=msg):  # without load too: its rigid modes would be spurious
        fg.solve_linear_static(model, _clamped(model, ids))


def test_disconnected_parts_that_are_each_held_or_joined_are_accepted():
    model, ids, other = _two_parts()
    cfg = fg.Configuration("c", fixed={int(ids[0]): "123456", int(other[0]): "123456"}, gravity=1.0)
    assert fg.solve_static(model, cfg).load_factor == 1.0
    model.add_spring(int(ids[-1]), int(other[-1]), stiffness=np.full(6, 1e4))
    assert fg.solve_static(model, _clamped(model, ids, gravity=1.0)).load_factor == 1.0


def test_a_loose_mass_is_a_free_part_but_an_unused_grid_is_not():
    model, ids = straight_beam(6)
    unused = model.add_nodes([[5.0, 5.0, 5.0]])  # an orientation or output grid: inert
    assert fg.solve_static(model, _clamped(model, ids, gravity=1.0)).load_factor == 1.0
    model.add_mass(int(unused[0]), 1.0)
    with pytest.raises(ModelError, match=rf"part of 1 node\(s\) \(ids {unused[0]}\) is free"):
        fg.solve_static(model, _clamped(model, ids, gravity=1.0))


def test_a_single_free_structure_is_not_refused():
    model, ids = straight_beam(6)
    modes = fg.solve_modes(fg.solve_static(model, fg.Configuration("free")), 8)
    assert np.sum(modes.frequencies_hz == 0) == 6
