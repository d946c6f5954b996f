"""Shell design variables (thickness, E, G, rho, nsm of shell groups): the partial derivatives of the
residual, tangent and mass matrix against finite differences of the assembly, and the whole-solve
Jacobian of frequencies and static deflections about a deformed state against finite
differences of whole solves."""

import dataclasses

import numpy as np
import pytest
from test_gradients import TIGHT, _check

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.errors import ModelError
from flexgvt.updating.derivatives import partial_derivatives

AL = fg.Material("Al", E=70e9, nu=0.33, rho=2700.0)


def shell_strip(nx=12, ny=2, length=1.0, width=0.1):
    """A cantilever plate strip of quads in two groups (root half 'root', outer half 'outer', 3 mm
    with 0.5 kg/m^2 NSM) plus a row of triangles at the tip ('tip'), a tip mass; self-weight and
    unloaded configurations."""
    model = fg.Model("shell strip")
    x, y = np.meshgrid(np.linspace(0, length, nx + 1), np.linspace(0, width, ny + 1))
    ids = np.arange(1, x.size + 1).reshape(x.shape)
    model.add_nodes(np.c_[x.ravel(), y.ravel(), 0.02 * x.ravel() ** 2], ids=ids.ravel())
    quads = np.array([[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]]
                      for j in range(ny) for i in range(nx - 1)])
    half = (nx - 1) // 2
    outer = quads.reshape(ny, nx - 1, 4)
    model.add_shells(outer[:, :half].reshape(-1, 4), fg.model.ShellProperty.isotropic(AL, 0.003, "p_root", 0.5),
                     name="root", mass="consistent")
    model.add_shells(outer[:, half:].reshape(-1, 4), fg.model.ShellProperty.isotropic(AL, 0.003, "p_outer", 0.5),
                     name="outer")
    tris = []
    for j in range(ny):
        a, b, c, d = ids[j, nx - 1], ids[j, nx], ids[j + 1, nx], ids[j + 1, nx - 1]
        tris += [[a, b, c], [a, c, d]]
    model.add_shells(np.array(tris), fg.model.ShellProperty.isotropic(AL, 0.003, "p_tip"), name="tip")
    model.add_mass(int(ids[0, -1]), 0.02)
    fixed = {int(i): "123456" for i in ids[:, 0]}
    return model, [fg.Configuration("self_weight", fixed=fixed, gravity=1.0),
                   fg.Configuration("unloaded", fixed=fixed)], ids


@pytest.mark.parametrize("attribute", ["thickness", "E", "G", "rho", "nsm"])
def test_partial_derivatives_against_finite_differences_of_the_assembly(attribute):
    """dR, dK, dM of a shell variable at the deformed self-weight state against central differences
    of the assembled residual, tangent and mass (steps 1e-3 and 5e-4, Richardson), each within 1e-6
    of its largest entry (the difference's own error, measured: about 1e-9), with a floor of 1e-12
    of the quantity itself where it does not change (M with E, K with rho)."""
    model, cfgs, _ = shell_strip()
    groups = "root" if attribute == "nsm" else ["root", "tip"]
    par = up.Parametrisation(model, cfgs[:1], [up.shell("v", groups, attribute)])
    work = model.copy()
    x0 = np.ones(1)
    par.apply(work, x0)
    state = fg.solve_static(work, cfgs[0], settings=TIGHT)
    dR, dK, dM = partial_derivatives(par, work, x0, state, 0)

    def assembled(xv):
        w = model.copy()
        par.apply(w, np.array([xv]))
        system = state.system.for_values(w, cfgs[0])
        ev = system.evaluate(state.positions, state.rotations, state.load_factor)
        return (ev.internal - ev.external, ev.tangent.toarray(),
                system.mass_matrix(state.positions, state.rotations).toarray())

    def central(h):
        a, b = assembled(1 + h), assembled(1 - h)
        return [(p - q) / (2 * h) for p, q in zip(a, b)]

    c1, c2 = central(1e-3), central(5e-4)
    base = list(assembled(1.0))
    base[0] = np.abs(state.system.evaluate(state.positions, state.rotations, 1.0).external)
    for got, f1, f2, whole in zip((dR, dK.toarray(), dM.toarray()), c1, c2, base):
        ref = (4 * f2 - f1) / 3
        allowed = max(1e-6 * np.abs(ref).max(), 1e-12 * np.abs(whole).max())
        assert np.abs(got - ref).max() <= allowed, attribute


def test_jacobian_with_shell_variables_matches_finite_differences():
    """Frequencies of both configurations and the self-weight tip deflection, differentiated through
    the deformed state (its dependence on the variables included), against whole solves."""
    model, cfgs, ids = shell_strip()
    data = []
    for c in cfgs:
        modes = fg.solve_modes(fg.solve_static(model, c), 6, label=False)
        static = {(int(ids[0, -1]), 3): -0.02} if c.gravity else {}
        data.append(up.Measured(c.name, modes.frequencies_hz[:5] * 1.02, static=static))
    variables = [up.shell("t_root", "root", "thickness"), up.shell("E_all", "*", "E"),
                 up.shell("rho_outer", "outer", "rho"), up.shell("G_tip", "tip", "G")]
    problem = up.UpdatingProblem(model, cfgs, data, variables, objective=up.Objective(static=1.0),
                                 static_settings=TIGHT)
    _check(problem, np.array([1.03, 0.98, 1.01, 1.02]))


def test_shell_variables_are_refused_where_they_cannot_scale():
    model, cfgs, _ = shell_strip()
    with pytest.raises(ModelError, match="no shell group named"):
        up.Parametrisation(model, cfgs, [up.shell("t", "spar", "thickness")])
    with pytest.raises(ModelError, match="nsm of shell group 'tip' is 0.0"):
        up.Parametrisation(model, cfgs, [up.shell("m", "tip", "nsm")])
    with pytest.raises(ModelError, match="must be one of"):
        up.Parametrisation(model, cfgs, [up.shell("w", "tip", "width")])


def test_one_design_change_serves_configurations_with_different_imperfections():
    """A variable's ValueChange is computed once per design point for every configuration; a
    configuration's imperfection moves its shells' stress-free geometry, so the change's cached
    element constants must be those of that geometry (they were the first configuration's: the
    wingbox's post-buckled configurations had their E and skin-thickness slopes 1.6 % off)."""
    from flexgvt.updating.derivatives import value_change
    model, cfgs, ids = shell_strip()
    bumped = dataclasses.replace(cfgs[0], name="imperfect",
                                 imperfection={int(i): (0.0, 0.0, 0.002) for i in ids[:, 6]})
    par = up.Parametrisation(model, [cfgs[0], bumped], [up.shell("t", ["root", "outer"], "thickness")])
    work = model.copy()
    x0 = np.ones(1)
    par.apply(work, x0)
    perfect, imperfect = (fg.solve_static(work, c, settings=TIGHT) for c in (cfgs[0], bumped))
    shared = value_change(par, work, x0, 0, "")
    partial_derivatives(par, work, x0, perfect, 0, shared)  # fills the change's cache first
    got = partial_derivatives(par, work, x0, imperfect, 0, shared)
    fresh = partial_derivatives(par, work, x0, imperfect, 0)
    for a, b in zip(got, fresh):
        a, b = (m.toarray() if hasattr(m, "toarray") else m for m in (a, b))
        np.testing.assert_array_equal(a, b)


def test_thick_triangle_plate_frequency_derivatives_match_finite_differences():
    """A square cantilever plate of DKMT triangles, L/t = 10 (shear flexibility lowers its bending
    modes by 0.8, 2.6, 4.1 % against the same plate without MID3, i.e. DKT): the first four
    frequencies differentiated with respect to the thickness and G of its group against whole
    solves (measured: within 1e-9 relative; the triangle's constants are not linear in the
    section: the four-point rule runs on whole kernel passes)."""
    model = fg.Model("thick triangles")
    n, a = 6, 0.5
    x, y = np.meshgrid(np.linspace(0, a, n + 1), np.linspace(0, a, n + 1))
    ids = np.arange(1, x.size + 1).reshape(x.shape)
    model.add_nodes(np.c_[x.ravel(), y.ravel(), 0 * x.ravel()], ids=ids.ravel())
    tris = []
    for j in range(n):
        for i in range(n):
            p, q, r, s = ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]
            tris += [[p, q, r], [p, r, s]]
    model.add_shells(np.array(tris), fg.model.ShellProperty.isotropic(AL, a / 10, "thick"), name="plate",
                     mass="consistent")
    cfg = fg.Configuration("unloaded", fixed={int(i): "123456" for i in ids[:, 0]})
    f0 = fg.solve_modes(fg.solve_static(model, cfg), 4, label=False).frequencies_hz
    problem = up.UpdatingProblem(model, [cfg], [up.Measured(cfg.name, f0 * 1.02)],
                                 [up.shell("t", "plate", "thickness"), up.shell("G", "plate", "G")],
                                 static_settings=TIGHT)
    J = _check(problem, np.array([1.02, 0.97]))[0]
    assert np.abs(J[:, 1]).max() > 0.05 * np.abs(J[:, 0]).max()  # G matters (shear and nu)
