"""A load path that buckles without an unstable equilibrium on it (fem.knee): the simply supported
plate of test_buckling under in-plane compression with a small lateral load across it (the
imperfection). Its path stays stable through the bifurcation, so no tangent eigenvalue turns
negative; solve_static reports the knee of its load-work curve instead. The reference is the same
plate without the lateral load, whose flat path loses stability at a bifurcation that fem.stability
locates (+0.44 % of the closed form k = 4 on this 16 x 16 mesh)."""

import dataclasses

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import InstabilityError
from flexgvt.fem.knee import _candidate, _Point
from flexgvt.fem.stability import negative_eigenvalues
from flexgvt.fem.static import StaticSettings

from test_buckling import _plate

OVER = 1.3  # the compression: 1.3 x the closed-form critical Nx


def _imperfect(over: float, share: float = 1e-2):
    """_plate(16, over) with a uniform lateral load of ``share`` x Nx_cr x t spread over its nodes
    (out-of-plane, -z): a deflection of about t / 30 at half the critical load."""
    model, config, n_cr = _plate(16, over)
    q = share * n_cr * 0.005 / len(model.node_ids)
    lateral = tuple(fg.NodalLoad(int(n), force=(0.0, 0.0, -q)) for n in model.node_ids)
    return model, dataclasses.replace(config, forces=tuple(config.forces) + lateral)


def test_an_imperfect_plate_reports_the_knee_of_its_stable_path():
    """The onset within 2 % of the perfect plate's bifurcation on the same mesh (measured -1.4 %: the
    two-tangent construction of an imperfect path lies a little below the bifurcation, more so the
    larger the imperfection), found from the path ('path': no equilibrium unstable, the final one
    neither), its compliance grown by half past it (measured 1.53: the buckled plate's middle strip
    sheds its load to the edges), and the departure from the flat path largest at the centre (one
    half-wave each way)."""
    model, config = _imperfect(OVER)
    with pytest.warns(fg.errors.FlexGVTWarning, match="knee of the load path"):
        state = fg.solve_static(model, config)
    event = state.instability
    assert event.found_by == "path" and event.recovered and event.kind == "bifurcation"
    assert negative_eigenvalues(state.system, state.positions, state.rotations, 1.0) == 0
    perfect_model, perfect_config, _ = _plate(16, OVER)
    with pytest.warns(fg.errors.FlexGVTWarning, match="loses stability"):
        perfect = fg.solve_static(perfect_model, perfect_config).instability
    assert perfect.found_by == "tangent"
    assert event.load_factor == pytest.approx(perfect.load_factor, rel=0.02)
    assert event.bracket[0] <= event.load_factor <= event.bracket[1]
    assert event.bracket[1] - event.bracket[0] < 0.01 * event.load_factor
    assert 1.3 < event.softening < 2.0
    w = np.abs(event.shape[:, 2]).reshape(17, 17)
    assert w[8, 8] == pytest.approx(1.0, abs=0.05)
    assert "shell quad" in event.where


def test_below_its_buckling_load_an_imperfect_plate_has_no_knee():
    """At 0.8 x Nx_cr the lateral deflection grows faster than the load (the amplification 1 / (1 -
    N / N_cr)), smoothly: no knee, no instability, no warning."""
    model, config = _imperfect(0.8)
    state = fg.solve_static(model, config)
    assert state.instability is None
    assert abs(state.displacements[:, 2]).max() > 0.0


def test_stop_at_a_knee_returns_the_state_before_it():
    """buckling='stop' raises with the last equilibrium below the knee's bracket and the event."""
    model, config = _imperfect(OVER)
    with pytest.raises(InstabilityError) as info:
        fg.solve_static(model, config, settings=StaticSettings(buckling="stop"))
    event = info.value.instability
    assert event.found_by == "path"
    assert info.value.state.load_factor <= event.bracket[0]


def _path(lam, compliance) -> list:
    work = np.concatenate([[0.0], np.cumsum(np.diff(lam) * compliance)])
    return [_Point(float(a), None, None, float(w)) for a, w in zip(lam, work)]


def test_the_knee_candidate_is_a_jump_of_the_compliance_not_its_trend():
    """A jump of 24 % in one increment (the 0.1 m wingbox at -1 g between 0.50 and 0.72 g) is the
    candidate; a compliance that grows steadily by 3 % per increment, or stiffens, is not."""
    lam = np.array([0.0, 0.05, 0.106, 0.19, 0.316, 0.504, 0.715, 0.788, 0.869, 0.960, 1.0])
    jump = np.r_[np.ones(5), 1.24, 1.54, 1.63, 1.71, 1.77]
    assert _candidate(_path(lam, jump)) == 5
    steady = 1.03 ** np.arange(10)
    assert _candidate(_path(lam, steady)) is None
    assert _candidate(_path(lam, 1.0 / steady)) is None
    # The as-built X-HALE on two cords: its first increment 6 % stiffer than the rest, no buckling.
    hung = np.array([4.471, 4.738, 4.782, 4.741, 4.729, 4.709, 4.673, 4.602, 4.460, 4.40]) / 4.471
    assert _candidate(_path(lam, hung)) is None


def test_an_aircraft_hung_on_cords_has_no_knee():
    """The as-built X-HALE-like aircraft on its two lab cords (seed 2): the path's compliance rises 6 %
    from the first increment to the second as the cords' pendulum stiffness grows with their
    tension, then falls smoothly; nothing buckles (it was once reported as a knee at 0.05)."""
    case = fg.cases.xhale(as_built=True, seed=2)
    state = fg.solve_static(case.model, case.configurations["inboard"])
    assert state.instability is None


def test_the_default_imperfection_follows_the_buckled_skin_not_a_thin_neighbour():
    """'continue' sizes its imperfection as a tenth of the thickness most of the moved shells have: a
    5 mm plate whose last row of quads is 2 mm (a rib's edge along a skin) moved everywhere gets 0.5 mm,
    not 0.2 mm (the thinnest, as before: the 0.1 m wingbox's 8 mm skin got the ribs' 0.2 mm)."""
    from flexgvt.fem.stability import Instability
    from flexgvt.fem.static import _default_imperfection
    from flexgvt.model import Material
    model, config, _ = _plate(8, 1.0)
    thin = fg.Model("plate with a thin edge row")
    thin.add_nodes(model.xyz, ids=model.node_ids)
    ids = model.node_ids.reshape(9, 9)
    q = np.array([[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]] for j in range(8) for i in range(8)])
    al = Material("al", 70e9, 2700.0, nu=0.3)
    thin.add_shells(q[:56], material=al, thickness=0.005, name="skin")
    thin.add_shells(q[56:], material=al, thickness=0.002, name="rib_edge")
    state = fg.solve_static(thin, config, settings=StaticSettings(buckling="ignore"))
    shape = np.zeros((81, 6))
    shape[:, 2] = 1.0
    event = Instability(1.0, "bifurcation", 0.0, shape, "", (1.0, 1.0))
    assert _default_imperfection(state.system, event) == pytest.approx(0.0005)
