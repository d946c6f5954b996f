"""Tapered beams (TaperedSection): the element against closed-form integrals, a fine stepped mesh of
uniform elements, its own flexibility, finite differences (tangent, parameter derivatives) and
exact mass integrals."""

import numpy as np
import pytest
from fem_builders import AL, perturbed_state, tangent_error
from scipy.integrate import quad
from sensitivity_reference import beam_parameter_derivative, frequency_derivatives

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.beam import (
    GAUSS3_POINTS,
    GAUSS3_WEIGHTS,
    element_coefficients,
    local_mass_matrices,
)
from flexgvt.fem.system import System, compile_model

L = 2.0
A0, IY0, IZ0, J0 = 8e-4, 6.7e-9, 4.3e-7, 2.5e-8
TAPER = 0.6  # every property falls linearly to 1 - TAPER of its root value at the tip


def linear_section(s, shear=True, scale=1.0):
    """A, Iy, Iz, J, Ip (and shear areas 5/6 A) all linear in s: the continuum of the tests."""
    c = scale * (1 - TAPER * s)
    kw = dict(Ay=5 / 6 * A0 * c, Az=5 / 6 * A0 * c) if shear else {}
    return fg.GeneralSection(A=A0 * c, Iy=IY0 * c, Iz=IZ0 * c, J=J0 * c, Ip=(IY0 + IZ0) * c, **kw)


def cantilever(n, tapered=True, mass="consistent", shear=True, material=AL):
    """n elements along x, clamped at x = 0: tapered elements, or uniform ones with the section of
    each element's midpoint (the stepped reference)."""
    model = fg.Model("tapered cantilever")
    s = np.linspace(0, 1, n + 1)
    ids = model.add_nodes(np.c_[s * L, 0 * s, 0 * s])
    for k in range(n):
        if tapered:
            sec = fg.TaperedSection(linear_section(s[k], shear), linear_section(s[k + 1], shear))
        else:
            sec = linear_section(0.5 * (s[k] + s[k + 1]), shear)
        model.add_beams([[ids[k], ids[k + 1]]], material, sec, mass=mass, rotary_inertia=False, name="beam")
    return model, ids


def clamped(ids, **kw):
    return fg.Configuration("clamped", fixed={int(ids[0]): "123456"}, gravity=0.0, **kw)


def tip_displacement(n, force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0), shear=False):
    model, ids = cantilever(n, shear=shear)
    cfg = clamped(ids, forces=[fg.NodalLoad(int(ids[-1]), force=force, moment=moment)])
    state = fg.solve_linear_static(model, cfg)
    return state.displacements[-1]


def test_uniform_ends_give_the_uniform_element():
    sec = fg.RectangularSection(width=0.05, height=0.01, shear=True)
    p = sec.properties()
    lengths = np.array([0.1, 0.7])
    uniform = element_coefficients(AL.E, AL.shear_modulus, p, p, lengths)
    as_tapered = element_coefficients(AL.E, AL.shear_modulus, p, dict(p), lengths)  # another dict: the Gauss path
    np.testing.assert_allclose(as_tapered, uniform, rtol=1e-13, atol=1e-13 * np.abs(uniform).max())
    for mass in ("consistent", "lumped", "consistent-bending"):
        models = []
        for section in (sec, fg.TaperedSection(sec, sec)):
            m = fg.Model()
            ids = m.add_nodes([[0, 0, 0], [0.3, 0.4, 0.0]])
            m.add_beams([ids], AL, section, orientation=(0, 0, 1), mass=mass)
            models.append(compile_model(m))
        np.testing.assert_array_equal(local_mass_matrices(models[0].beams), local_mass_matrices(models[1].beams))


def test_one_element_is_the_inverse_of_its_three_point_flexibility():
    """Tip deflection and rotation of a one-element cantilever under a tip force and moment: the
    3-point Gauss sums of int (L - x)^2 / EI, int (L - x) / EI, int 1 / EI plus int 1 / (G As)
    (Nastran's CBEAM rule), exactly."""
    P, Mo = 10.0, 3.0
    u = tip_displacement(1, force=(0.0, 0.0, P), moment=(0.0, -Mo, 0.0), shear=True)  # bending about y
    x = GAUSS3_POINTS * L
    w = GAUSS3_WEIGHTS * L
    EI = AL.E * IY0 * (1 - TAPER * GAUSS3_POINTS)
    GAs = AL.shear_modulus * 5 / 6 * A0 * (1 - TAPER * GAUSS3_POINTS)
    w_tip = P * (np.sum(w * (L - x) ** 2 / EI) + np.sum(w / GAs)) + Mo * np.sum(w * (L - x) / EI)
    rot = -(P * np.sum(w * (L - x) / EI) + Mo * np.sum(w / EI))  # ry = -dw/dx
    assert u[2] == pytest.approx(w_tip, rel=1e-12)
    assert u[4] == pytest.approx(rot, rel=1e-12)
    EA = AL.E * A0 * (1 - TAPER * GAUSS3_POINTS)
    GJ = AL.shear_modulus * J0 * (1 - TAPER * GAUSS3_POINTS)
    u = tip_displacement(1, force=(P, 0.0, 0.0), moment=(Mo, 0.0, 0.0))
    assert u[0] == pytest.approx(P * np.sum(w / EA), rel=1e-12)
    assert u[3] == pytest.approx(Mo * np.sum(w / GJ), rel=1e-12)


def test_tip_deflection_converges_to_the_closed_form_integral():
    """A cantilever with I linear along it under a unit tip load: w = int (L - x)^2 / EI(x) dx in
    closed form. One element is Nastran's 3-point rule (3.1e-4 off for this 2.5:1 taper); refined,
    the error falls as h^6 (7e-11 at 16 elements)."""
    b, c = TAPER / L, 1 - TAPER
    # u = 1 - b x: int_0^L (L - x)^2 / (1 - b x) dx = b^-3 int_c^1 (u - c)^2 / u du
    exact = ((1 - c**2) / 2 - 2 * c * (1 - c) + c**2 * np.log(1 / c)) / (b**3 * AL.E * IY0)
    numeric = quad(lambda x: (L - x) ** 2 / (AL.E * IY0 * (1 - b * x)), 0, L, epsabs=0, epsrel=1e-13)[0]
    assert exact == pytest.approx(numeric, rel=1e-12)
    errors = [tip_displacement(n, force=(0.0, 0.0, 1.0))[2] / exact - 1 for n in (1, 2, 4, 8, 16)]
    assert errors[0] == pytest.approx(-3.14e-4, rel=0.01)
    assert abs(errors[-1]) < 1e-10
    rates = np.log2(np.abs(np.array(errors[:-1]) / np.array(errors[1:])))  # measured 4.8, 5.5, 5.8, 6.0
    assert np.all(rates > 4.5) and rates[-1] > 5.8


@pytest.fixture(scope="module")
def stepped_reference():
    """First 8 frequencies of the linear taper (Timoshenko, consistent mass) from 500 and 1,000
    uniform stepped elements, Richardson-extrapolated (the stepping error is O(h^2); the
    extrapolation moved them by at most 4e-7)."""
    f = [fg.solve_modes(fg.solve_linear_static(model, clamped(ids)), 8).frequencies_hz
         for model, ids in (cantilever(n, tapered=False) for n in (500, 1000))]
    return (4 * f[1] - f[0]) / 3


def frequencies(n, mass):
    model, ids = cantilever(n, mass=mass)
    return fg.solve_modes(fg.solve_linear_static(model, clamped(ids)), 8).frequencies_hz


def test_frequencies_converge_to_a_fine_stepped_mesh_of_uniform_elements(stepped_reference):
    """Five out-of-plane and two in-plane bending modes and the first torsion mode of the tapered
    cantilever: 40 tapered elements within 4e-5 of 1,000 stepped uniform ones (measured: bending
    2e-7 to 1.5e-5, converging as h^4; torsion 3.2e-5, as h^2 with its linear shape functions)."""
    err = {n: frequencies(n, "consistent") / stepped_reference - 1 for n in (20, 40)}
    assert np.all(np.abs(err[40]) < 4e-5), err[40]
    visible = np.abs(err[20]) > 1e-6  # above the reference's own accuracy
    assert np.all(np.abs(err[20][visible]) > 3.5 * np.abs(err[40][visible]))  # converging, not by chance


def test_lumped_mass_converges_from_below_consistent_from_above(stepped_reference):
    """Lumped mass (each node int m N_i dx) underestimates, consistent overestimates; both converge
    to the same frequencies, lumped as h^2 (40 elements: -1.5e-4 to -3e-3)."""
    lumped = {n: frequencies(n, "lumped") / stepped_reference - 1 for n in (20, 40)}
    consistent = frequencies(40, "consistent") / stepped_reference - 1
    assert np.all(lumped[40] < 0) and np.all(lumped[40] > -5e-3)
    assert np.all(consistent > -1e-6)
    np.testing.assert_allclose(lumped[20] / lumped[40], 4.0, rtol=0.1)


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_mass_properties_are_the_exact_integrals(mass):
    """Mass, centre of gravity (and for consistent mass the inertia) of a tapered beam along x with
    rho A linear: int rho A dx, int x rho A dx / m and int (x - xc)^2 rho A dx plus the torsional
    term int rho Ip dx, exactly (a single element)."""
    model, _ = cantilever(1, mass=mass, shear=False)
    mp = fg.mass_properties(model)

    def rhoA(x):
        return AL.rho * A0 * (1 - TAPER * x / L)

    m = quad(rhoA, 0, L)[0]
    xc = quad(lambda x: x * rhoA(x), 0, L)[0] / m
    assert mp.mass == pytest.approx(m, rel=1e-13)
    np.testing.assert_allclose(mp.cg, [xc, 0, 0], rtol=1e-13, atol=1e-15)
    torsion = quad(lambda x: AL.rho * (IY0 + IZ0) * (1 - TAPER * x / L), 0, L)[0]
    assert mp.inertia[0, 0] == pytest.approx(torsion, rel=1e-12)
    if mass == "consistent":
        Iyy = quad(lambda x: (x - xc) ** 2 * rhoA(x), 0, L)[0]
        assert mp.inertia[1, 1] == pytest.approx(Iyy, rel=1e-12)
        assert mp.inertia[2, 2] == pytest.approx(Iyy, rel=1e-12)


def curved_tapered_model():
    """A curved, twisted tapered beam with different tapers in the two planes and a shear area."""
    model = fg.Model("tapered tangent check")
    s = np.linspace(0, 1, 7)
    ids = model.add_nodes(np.c_[0.2 * np.sin(2 * s), s, 0.1 * s**2])
    for k in range(len(s) - 1):
        a = fg.RectangularSection(width=0.05 - 0.03 * s[k], height=0.012 - 0.004 * s[k] ** 2)
        b = fg.RectangularSection(width=0.05 - 0.03 * s[k + 1], height=0.012 - 0.004 * s[k + 1] ** 2)
        model.add_beams([[ids[k], ids[k + 1]]], AL, fg.TaperedSection(a, b), orientation=(0.3, 0, 1), name="taper")
    model.add_mass(int(ids[-1]), 0.2, offset=(0.01, 0.0, 0.02))
    cfg = fg.Configuration("check", gravity=3.0, fixed={int(ids[0]): "123456"},
                           forces=[fg.NodalLoad(int(ids[-1]), force=(1.0, 20.0, -3.0), moment=(0.1, 0.2, 0.3))])
    return model, cfg


def test_tapered_tangent_matches_finite_differences():
    model, cfg = curved_tapered_model()
    assert np.abs(compile_model(model).beams.stiffness[:, 6:]).max() > 0  # the tapered terms are present
    system = System(model, cfg)
    err, _ = tangent_error(system, *perturbed_state(system, 5), lam=0.8)
    assert err < 1e-6


def _perturbed(parameter, h):
    """The curved tapered model with E, G or rho scaled by (1 + h) (G given explicitly, E kept, for G)."""
    model, cfg = curved_tapered_model()
    out = fg.Model("perturbed")
    out.add_nodes(model.xyz, ids=model.node_ids)
    for g in model.beams:
        E, rho = AL.E * (1 + h * (parameter == "E")), AL.rho * (1 + h * (parameter == "rho"))
        mat = fg.Material("Al", E=E, G=AL.shear_modulus * (1 + h), rho=rho) if parameter == "G" else \
            fg.Material("Al", E=E, nu=AL.nu, rho=rho)
        out.add_beams(g.nodes, mat, g.section, orientation=g.orientation, rotary_inertia=g.rotary_inertia, name=g.name)
    for m in model.masses:
        out.add_mass(m.node, m.mass, offset=m.offset, inertia=m.inertia)
    return out, cfg


@pytest.mark.parametrize("parameter", ["E", "G", "rho"])
def test_tapered_parameter_derivatives_match_finite_differences(parameter):
    model, cfg = curved_tapered_model()
    state = fg.solve_static(model, cfg)
    d = beam_parameter_derivative(state, "taper", parameter)
    base = {"E": AL.E, "G": AL.shear_modulus, "rho": AL.rho}[parameter]
    h = 1e-6
    out = []
    for sign in (1, -1):
        system = System(_perturbed(parameter, sign * h)[0], cfg)
        ev = system.evaluate(state.positions, state.rotations, state.load_factor)
        out.append((ev.internal - ev.external, ev.tangent.toarray(),
                    system.mass_matrix(state.positions, state.rotations).toarray()))
    fd = [(a - b) / (2 * h * base) for a, b in zip(out[0], out[1])]
    for name, exact, approx in zip(("residual", "K", "M"), (d.residual, d.stiffness.toarray(), d.mass.toarray()), fd):
        scale = max(np.abs(approx).max(), 1e-300)
        assert np.abs(exact - approx).max() < 1e-5 * scale, name
    # and the frequencies' slopes (state held fixed, unloaded)
    unloaded = fg.Configuration("free", fixed=cfg.fixed, gravity=0.0)
    modes = fg.solve_modes(fg.solve_static(model, unloaded), 4)
    df = frequency_derivatives(modes, beam_parameter_derivative(modes.state, "taper", parameter))
    hh = 1e-4
    f = [fg.solve_modes(fg.solve_static(_perturbed(parameter, s * hh)[0], unloaded), 4).frequencies_hz
         for s in (1, -1)]
    fd = (f[0] - f[1]) / (2 * hh * base)
    # atol: a frequency that barely depends on the parameter (mode 1 on G) is FD round-off
    np.testing.assert_allclose(df, fd, rtol=1e-5, atol=1e-5 * np.abs(fd).max())


def test_bad_tapered_sections_are_named():
    with pytest.raises(ModelError, match="rods do not taper"):
        fg.TaperedSection(fg.RodSection(1e-4), fg.RodSection(2e-4))
    with pytest.raises(ModelError, match="shear area Ay is given at one end only"):
        fg.TaperedSection(fg.GeneralSection(A=1e-3, Iy=1e-8, Iz=1e-8, J=1e-8, Ay=8e-4),
                          fg.GeneralSection(A=1e-3, Iy=1e-8, Iz=1e-8, J=1e-8))
    with pytest.raises(ModelError, match="end_properties"):
        fg.TaperedSection(linear_section(0), linear_section(1)).properties()
    model, _ = curved_tapered_model()
    with pytest.raises(ModelError, match="a TaperedSection cannot become a RectangularSection"):
        model.set_beam_group(0, section=fg.RectangularSection(0.05, 0.01))
