"""Shells in the solver (the shell family in System): what the element tests showed for the kernels
holds through solve_static, solve_modes and mass_properties, and the built-up results match
references nobody here wrote (Leissa, CalculiX S8R, the elastica)."""

import json
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.fem._shell_elements import assemble, shell_matrices
from flexgvt.fem._shell_model import kernel_frames
from flexgvt.fem._shell_section import Ply as KernelPly
from flexgvt.fem._shell_section import mat1, mat8, pcomp, pshell, section_arrays
from flexgvt.fem.system import System
from flexgvt.model import Material
from flexgvt.model.configuration import NodalLoad
from flexgvt.model.shells import Laminate, OrthotropicMaterial, Ply

DATA = Path(__file__).resolve().parents[1] / "data"
AL = Material("al", 70e9, 2700.0, nu=0.3)


def shell_grid(nx, ny, a=1.0, b=1.0, tri=False, z=None):
    """Nodes (ids from 1) of an a x b grid in the x-y plane (z(x, y) to warp it) and its quads (or
    two triangles each): (model with the nodes, element node ids, id grid (ny+1, nx+1))."""
    x, y = np.meshgrid(np.linspace(0, a, nx + 1), np.linspace(0, b, ny + 1))
    zz = np.zeros_like(x) if z is None else z(x, y)
    model = fg.Model("grid")
    ids = np.arange(1, x.size + 1).reshape(x.shape)
    model.add_nodes(np.c_[x.ravel(), y.ravel(), zz.ravel()], ids=ids.ravel())
    q = np.array([[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]] for j in range(ny) for i in range(nx)])
    return model, (np.vstack([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]) if tri else q), ids


@pytest.mark.parametrize("tri", [False, True], ids=["quads", "triangles"])
def test_cantilever_plate_modes_against_leissa(tri):
    """Square cantilever plate (CFFF), 16 x 16, through solve_modes: lambda = omega a^2 sqrt(rho t / D)
    against Leissa's 3.4917, 8.5246, 21.429, 27.331, 31.111 (Ritz upper bounds; the kernels converge
    to 3.4716 for mode 1, docs/shells.md). Measured: quads -0.53, -0.14, +0.17, +0.07, +0.19 %;
    triangles (DKMT) -0.62, -0.12, -0.32, -0.08, +0.01 % (DKT: -0.60, -0.10, -0.27, -0.04, +0.06 %)."""
    t, nu, rho, E = 0.01, 0.3, 2700.0, 70e9
    model, elements, ids = shell_grid(16, 16, tri=tri)
    model.add_shells(elements, material=AL, thickness=t, mass="consistent", name="plate")
    config = fg.Configuration("cfff", fixed={int(i): "123456" for i in ids[:, 0]})
    modes = fg.solve_modes(fg.solve_static(model, config), 5)
    D = E * t**3 / (12 * (1 - nu**2))
    lam = 2 * np.pi * modes.frequencies_hz * np.sqrt(rho * t / D)
    np.testing.assert_allclose(lam, [3.4917, 8.5246, 21.429, 27.331, 31.111], rtol=0.007)


def _kernel_matrices(model, elements, C, mass, lumped):
    idx = model.index_of(elements.reshape(-1)).reshape(elements.shape)
    r = shell_matrices(model.xyz[idx], C, mass, lumped)
    return assemble(idx, r.K, model.n_nodes).toarray(), assemble(idx, r.M, model.n_nodes).toarray()


@pytest.mark.parametrize("tri", [False, True], ids=["quads", "triangles"])
def test_the_solver_assembles_the_kernels_matrices(tri):
    """The unloaded tangent and the mass matrix of System equal the linear kernels' assembled K and M
    (a warped, tilted mesh with a material angle, an offset and consistent mass): the family adds
    nothing and loses nothing. Quads carry the initial-stress term, which vanishes unloaded."""
    model, elements, _ = shell_grid(3, 2, 0.6, 0.4, tri, z=lambda x, y: 0.05 * x * y + 0.1 * x)
    ply = OrthotropicMaterial("cfrp", 130e9, 9e9, 0.3, 5e9, rho=1600.0)
    lam = Laminate("lam", (Ply(ply, 0.001, 0.0), Ply(ply, 0.001, 45.0), Ply(ply, 0.001, -30.0)))
    model.add_shells(elements, lam, theta=20.0, zoffs=0.002, mass="consistent")
    system = System(model, fg.Configuration("free"))
    x, R = system.undeformed
    K, M = system.full_state(x, R, 0.0)[1].toarray(), system.full_mass_matrix(x, R).toarray()
    kernel_ply = mat8(ply.E1, ply.E2, ply.nu12, ply.G12, rho=ply.rho)
    sec = pcomp([KernelPly(kernel_ply, p.thickness, p.theta) for p in lam.plies]).offset(0.002)
    C, m = section_arrays([sec.rotated(np.radians(20.0))], np.zeros(len(elements), int))
    K_ref, M_ref = _kernel_matrices(model, elements, C, m, False)
    assert np.max(np.abs(K - K_ref)) < 1e-9 * np.max(np.abs(K_ref))
    assert np.max(np.abs(M - M_ref)) < 1e-12 * np.max(np.abs(M_ref))


def test_material_axis_and_kernel_frames():
    """An MCID-like material axis gives the same section as the THETA it projects to, and the frames
    the section is turned into are the kernels' own."""
    model, elements, _ = shell_grid(2, 2, 0.5, 0.5, z=lambda x, y: 0.2 * x)
    X = model.xyz[model.index_of(elements.reshape(-1)).reshape(elements.shape)]
    r = shell_matrices(X, section_arrays([pshell(0.001, mat1(70e9, nu=0.3))], np.zeros(len(X), int))[0])
    np.testing.assert_allclose(kernel_frames(X), r.frames, atol=1e-14)
    ply = OrthotropicMaterial("ply", 130e9, 9e9, 0.3, 5e9, rho=1600.0)
    lam = Laminate("l", (Ply(ply, 0.001, 0.0),))
    angle = np.radians(35.0)
    frames = kernel_frames(X)
    axis = np.cos(angle) * frames[:, :, 0] + np.sin(angle) * frames[:, :, 1] + 0.3 * frames[:, :, 2]
    by_theta, by_axis = fg.Model("a"), fg.Model("b")
    for m in (by_theta, by_axis):
        m.add_nodes(model.xyz, ids=model.node_ids)
    by_theta.add_shells(elements, lam, theta=35.0)
    by_axis.add_shells(elements, lam, material_axis=axis)
    Ka, Kb = (fg.fem.system.compile_model(m).shells[0].C for m in (by_theta, by_axis))
    np.testing.assert_allclose(Ka, Kb, atol=1e-9 * np.abs(Ka).max())


def test_weight_mass_properties_and_corner_thickness():
    """A tilted, offset plate of 0.8 x 0.5 m, 4 mm aluminium plus 1.5 kg/m^2 NSM: the weight applied
    at 1 g is m g, mass_properties give the plate's mass, centre and inertia (thin plate:
    m (b^2 + t^2) / 12 ... about its own axes, turned), and uniform corner thicknesses equal the
    property's thickness."""
    a, b, t, nsm = 0.8, 0.5, 0.004, 1.5
    model, elements, _ = shell_grid(8, 5, a, b)
    prop = fg.model.ShellProperty.isotropic(AL, t, nsm=nsm)
    model.add_shells(elements, prop, mass="consistent")
    mass = (2700.0 * t + nsm) * a * b
    props = fg.mass_properties(model)
    assert props.mass == pytest.approx(mass, rel=1e-12)
    np.testing.assert_allclose(props.cg, [a / 2, b / 2, 0.0], atol=1e-12)
    rot = 2700.0 * t**3 / 12 * a * b  # the sections' rotary inertia about x and y
    np.testing.assert_allclose(np.diag(props.inertia), [mass * b**2 / 12 + rot, mass * a**2 / 12 + rot,
                                                        mass * (a**2 + b**2) / 12], rtol=1e-10)
    system = System(model, fg.Configuration("1g", gravity=1.0))
    weight = system.applied.reshape(-1, 6)
    np.testing.assert_allclose(weight[:, :3].sum(axis=0), [0.0, 0.0, -mass * 9.80665], rtol=1e-12)
    corner = fg.Model("c")
    corner.add_nodes(model.xyz, ids=model.node_ids)
    corner.add_shells(elements, fg.model.ShellProperty.isotropic(AL, 0.001, nsm=nsm),
                      corner_thickness=np.full(elements.shape, t), mass="consistent")
    assert fg.mass_properties(corner).mass == pytest.approx(mass, rel=1e-12)


@pytest.mark.parametrize("tri", [False, True], ids=["quads", "triangles"])
def test_strip_rolled_up_through_solve_static(tri):
    """Sze, Liu & Lo's strip (L 10, b 1, t 0.1, E 1.2e6, nu 0) rolled into a circle by an end moment
    2 pi EI / L through solve_static's own load stepping: the tip at L sin(theta)/theta,
    L (1 - cos theta)/theta. Measured tip error / L at 1/4, 1/2, 3/4, 1 of the moment: quads (with
    the initial-stress term) 8.3e-4, 1.1e-3, 1.5e-3, 9.5e-4; triangles 2.3e-4, 6.7e-4, 8.2e-4, 8.9e-4
    (the chords of a 20-element circle: (pi/20)^2 / 24 = 1.0e-3)."""
    L, b, t, E, nx = 10.0, 1.0, 0.1, 1.2e6, 20
    model, elements, ids = shell_grid(nx, 1, L, b, tri)
    model.add_shells(elements, material=Material("m", E, 0.0, nu=0.0), thickness=t)
    M = 2 * np.pi * E * b * t**3 / 12 / L
    tip = ids[:, -1]
    config = fg.Configuration("roll", fixed={int(i): "123456" for i in ids[:, 0]},
                              forces=tuple(NodalLoad(int(i), moment=(0.0, -M / 2, 0.0)) for i in tip))
    state = fg.solve_static(model, config, load_factors=np.array([0.25, 0.5, 0.75, 1.0]))
    errors = []
    for level in state.steps:
        theta = 2 * np.pi * level.load_factor
        at = level.positions[model.index_of(tip)].mean(axis=0)
        exact = np.array([L * np.sin(theta) / theta, 0.5 * b, L * (1 - np.cos(theta)) / theta])
        errors.append(np.linalg.norm(at - exact) / L)
    assert len(errors) == 4 and max(errors) < 2e-3


@pytest.fixture(scope="module")
def strip_s8r():
    """The 1.5 m x 50 mm x 3 mm aluminium cantilever strip (docs/method.md case 3) of 8 x 300
    lumped-mass quads, unloaded, at -1 g and at 3 g (3 x self-weight along -z), and CalculiX S8R's
    frequencies on the same layout (bench/calculix_strip.py, tests/data/mass_frame/ccx_s8r_8x300.json)."""
    model, elements, ids = shell_grid(8, 300, 0.05, 1.5)
    model.add_shells(elements, material=Material("al", 70e9, 2700.0, nu=0.33), thickness=0.003)
    fixed = {int(i): "123456" for i in ids[0]}
    out = {}
    for name, g in STRIP_CASES.items():
        state = fg.solve_static(model, fg.Configuration(name, fixed=fixed, gravity=g))
        out[name] = (state, fg.solve_modes(state, 12))
    return out, json.loads((DATA / "mass_frame" / "ccx_s8r_8x300.json").read_text()), ids


STRIP_CASES = {"unloaded": 0.0, "minus_1g": 1.0, "minus_3g": 3.0}  # gravity along -z [g]


def test_shell_strip_against_calculix_s8r(strip_s8r):
    """Unloaded and pre-stressed about the -1 g shape (tip sag 0.307 m, 20 % of the span) and the
    3 g shape (sag 0.750 m, pulled in 0.235 m): the first 12 frequencies within 1 % of CalculiX S8R.
    Measured: unloaded all bending and in-plane modes within 0.1 %, the torsion modes -0.69 % (linear
    quads against quadratic S8R across the chord: -0.04 % at 16 across); at -1 g within 0.53 %
    (1 IP, which the sag couples to torsion); at 3 g within 0.58 % (mode 2, the coupled
    lateral-torsional one; mode 9, 1 T: -0.53 %)."""
    out, ref, _ = strip_s8r
    for name in STRIP_CASES:
        f = out[name][1].frequencies_hz
        np.testing.assert_allclose(f, ref[name + "_hz"][:12], rtol=0.01, err_msg=name)


def test_shell_strip_frequencies_against_the_beam(strip_s8r):
    """The shell strip's first 12 frequencies against the beam model's (fg.cases.cantilever_strip,
    150 beams, rigid section) at 0, -1 g and 3 g, mode by mode. What separates the two models is the
    plate's section deforming in its own plane: where it cannot curl (at the clamp, over about a
    chord; in the higher modes, whose half-waves come down to a few chords) the plate bends with
    E I / (1 - nu^2), at most 1 / sqrt(1 - nu^2) = +5.9 % in frequency; the sag couples lateral
    bending with torsion, where the curl matters most (docs/solver.md "Mass about the deformed
    state"). So: modes without torsion within 1 % (measured +0.01 to +0.73 %, growing with the mode
    number), modes with torsion between -1 % and +5.9 % (measured: unloaded 1 T +0.33 %, 2 T +0.39 %;
    -1 g mode 3 +3.69 %, 7 +0.15 %, 9 +0.17 %; 3 g mode 2 +4.85 %, 6 +2.94 %, 9 +0.51 %)."""
    out, _, _ = strip_s8r
    case = fg.cases.cantilever_strip()
    limit = 1 / np.sqrt(1 - 0.33**2)
    for name, beam_name in zip(STRIP_CASES, ("unloaded", "self_weight", "flatwise_3g")):
        beam = fg.solve_modes(fg.solve_static(case.model, case.configurations[beam_name]), 12)
        ratio = out[name][1].frequencies_hz / beam.frequencies_hz
        torsion = np.array(["T" in label for label in beam.labels])
        assert torsion.sum() >= 2, (name, beam.labels)
        np.testing.assert_allclose(ratio[~torsion], 1.0, atol=0.01, err_msg=name)
        assert np.all((ratio[torsion] > 0.99) & (ratio[torsion] < limit)), (name, ratio)
    assert ratio[1] > 1.03  # 3 g: the coupled lateral-torsional mode, +4.85 %


def test_shell_strip_labels_and_sag_match_the_beam(strip_s8r):
    """The shell strip's modes are labelled as the beam model's (bending, in-plane, torsion by the
    cross-sections' motion), and its -1 g tip displacement is the beam model's (fg.cases.cantilever_strip)
    within 1.5 %. Measured: sag -0.56 %, pull-in -1.0 %: the clamp holds the root section flat, so
    the plate is stiffer than the beam there by up to 1/(1 - nu^2) over a length of about a chord."""
    out, _, ids = strip_s8r
    assert out["unloaded"][1].labels[:7] == ("1 OOP", "2 OOP", "1 IP", "3 OOP", "4 OOP", "1 T", "5 OOP")
    case = fg.cases.cantilever_strip()
    # At 3 g (sag 0.75 m of 1.5 m) the sections' axes turn with the strip: its flatwise modes stay
    # OOP where the beam's are (they came out IP from the curled strip's principal axes).
    beam3 = fg.solve_modes(fg.solve_static(case.model, case.configurations["flatwise_3g"]), 12).labels
    shell3 = out["minus_3g"][1].labels
    flat = [k for k, label in enumerate(beam3) if label.endswith(" OOP")]
    assert len(flat) >= 8 and [shell3[k] for k in flat] == [beam3[k] for k in flat], (shell3, beam3)
    beam = fg.solve_static(case.model, case.configurations["self_weight"])
    state = out["minus_1g"][0]
    row = state.model.index_of(ids[-1])
    moved = (state.positions[row] - state.system.cm.xyz[row]).mean(axis=0)
    k = case.model.index_of([case.references["tip_node"]])[0]
    beam_moved = beam.positions[k] - beam.system.cm.xyz[k]
    np.testing.assert_allclose(moved[1:], beam_moved[1:], rtol=0.015)
    assert moved[2] > beam_moved[2]  # the shell sags less (stiffer root)
