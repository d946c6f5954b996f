"""A heavy cord distributed over tension members (fg.Cord(segments=N)) against closed forms nobody
here wrote: a uniform elastic bar fixed at one end with a tip mass (beta tan beta = m_cord / M,
its roots for the plunge and the surge modes), a taut string (f_n = n / 2L sqrt(T / mu)), a
hanging cord's stretch under its own weight and an end load, and the Rayleigh limit of the single
heavy cord (tests/suspension/test_heavy_cord.py)."""

import numpy as np
import pytest
from scipy.optimize import brentq

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.points import cord_forces, member_forces
from flexgvt.fem.rotations import expm_so3, spin

G = 9.80665
M, K, L0, MC = 5.67, 5.0, 20.0, 0.4  # block [kg], cord rate EA / L0 [N/m], unstretched [m], cord mass [kg]


def _hung(n_segments: int, clamp: str = "456", extra_stretch: float = 0.0, gravity: float = 1.0):
    """A point mass M on one cord from an anchor above it, the anchor placed by the closed-form
    stretch (M g + m g / 2) / k of a uniform cord under an end load and its own weight."""
    model = fg.Model("block")
    node = int(model.add_nodes([[0.0, 0.0, 0.0]])[0])
    model.add_mass(node, M)
    stretch = gravity * (M * G + MC * G / 2) / K + extra_stretch
    cord = fg.Cord(node=node, anchor=(0.0, 0.0, L0 + stretch), stiffness=K, unstretched_length=L0, mass=MC,
                   segments=n_segments)
    return model, fg.Configuration("hung", suspension=(cord,), gravity=gravity, fixed={node: clamp})


def _bar_roots(ratio: float, count: int) -> np.ndarray:
    """The first roots of beta tan beta = ratio (a bar fixed at one end, tip mass: ratio = m_bar / M)."""
    return np.array([brentq(lambda b: b * np.tan(b) - ratio, j * np.pi + 1e-12, (j + 0.5) * np.pi - 1e-12)
                     for j in range(count)])


def test_hanging_cord_stretches_as_the_closed_form_and_bounces_as_a_bar_with_a_tip_mass():
    model, cfg = _hung(40)
    state = fg.solve_static(model, cfg)
    # Anchor placed by the closed-form stretch: the block stays where it was put, and the cord's
    # length along its points is L0 + (M g + m g / 2) / k.
    assert abs(state.displacements[0, 2]) < 1e-8
    assert state.cord_length[0] == pytest.approx(L0 + (M * G + MC * G / 2) / K, rel=1e-9)
    # Tension of the member at the attachment: the end load plus the weight of half a member's mass.
    assert state.cord_tension[0] == pytest.approx(M * G + MC * G / 80, rel=1e-9)
    modes = fg.solve_modes(state, 14, damped=False)
    f, labels = modes.frequencies_hz, list(modes.labels)
    beta = _bar_roots(MC / M, 3)
    exact = beta * np.sqrt(K / MC) / (2 * np.pi)  # omega = beta sqrt(EA / (mu L0^2)) = beta sqrt(k / m)
    plunge = f[labels.index("RB plunge")]
    surge = [f[labels.index(f"{k} bungee surge")] for k in (1, 2)]
    assert plunge == pytest.approx(exact[0], rel=1e-4)
    # 40 lumped members: the surge modes within 0.05 % and 0.15 % (discretisation, measured 0.03 / 0.1 %).
    assert surge[0] == pytest.approx(exact[1], rel=5e-4)
    assert surge[1] == pytest.approx(exact[2], rel=1.5e-3)
    # The single heavy cord (Rayleigh's third) is the low-frequency limit the members converge to.
    single = fg.solve_modes(fg.solve_static(*_hung(0)), 4, damped=False)
    rayleigh = single.frequencies_hz[list(single.labels).index("RB plunge")]
    assert rayleigh == pytest.approx(np.sqrt(K / (M + MC / 3)) / (2 * np.pi), rel=1e-4)
    assert plunge == pytest.approx(rayleigh, rel=2e-4)


def test_surge_converges_with_the_members():
    beta = _bar_roots(MC / M, 2)[1]
    exact = beta * np.sqrt(K / MC) / (2 * np.pi)
    errors = []
    for n in (5, 10, 20):
        modes = fg.solve_modes(fg.solve_static(*_hung(n)), 6, damped=False)
        errors.append(abs(modes.frequencies_hz[list(modes.labels).index("1 bungee surge")] / exact - 1))
    # A lumped chain: second order in the member length.
    assert errors[0] > errors[1] > errors[2]
    assert errors[0] / errors[2] == pytest.approx(16, rel=0.2)


def test_taut_weightless_string_modes():
    """No gravity, the block held: the cord pre-stretched to a uniform tension T, its string modes
    n / 2L sqrt(T / mu) with mu = m / L the stretched cord's mass per length (both planes)."""
    n = 40
    model, cfg = _hung(n, clamp="123456", extra_stretch=2.0, gravity=0.0)
    state = fg.solve_static(model, cfg)
    length = state.cord_length[0]
    T = K * (length - L0)
    assert T == pytest.approx(10.0, rel=1e-9)
    assert state.cord_tension[0] == pytest.approx(T, rel=1e-9)
    modes = fg.solve_modes(state, 8, damped=False)
    f = {lab: fr for lab, fr in zip(modes.labels, modes.frequencies_hz)}
    string = sorted(v for k, v in f.items() if "bungee string" in k)
    for k in (1, 2, 3):
        exact = k / (2 * length) * np.sqrt(T / (MC / length))
        lumped = exact * (2 * n / (k * np.pi)) * np.sin(k * np.pi / (2 * n))  # a string of n equal lumped members
        assert string[2 * k - 2] == pytest.approx(lumped, rel=1e-6)
        assert string[2 * k - 1] == pytest.approx(lumped, rel=1e-6)
        # the lumped string's error, -(k pi / 2n)^2 / 6: 0.03 % for the first mode, 0.23 % for the third
        assert string[2 * k - 2] == pytest.approx(exact, rel=(k * np.pi / (2 * n)) ** 2 / 5)
    surge = f["1 bungee surge"]
    assert surge == pytest.approx(np.sqrt(K / MC) * (2 * n / np.pi) * np.sin(np.pi / (2 * n)) / 2, rel=1e-6)


def test_member_tangent_matches_central_differences():
    """member_forces' tangent in the solver's variables (dx, spatial spin) against central
    differences of its forces, for a member between an offset attachment along an element (a, b)
    and a moving end c, and for one to a fixed anchor."""
    rng = np.random.default_rng(3)
    xa, xb, xc = rng.normal(size=(1, 3)), rng.normal(size=(1, 3)) + [1, 0, 0], rng.normal(size=(1, 3)) + [0, 0, 3]
    Ra, Rb = expm_so3(rng.normal(size=(1, 3))), expm_so3(rng.normal(size=(1, 3)))
    off, anchor = np.array([[0.1, -0.05, 0.02]]), np.array([[0.3, 0.2, 4.0]])
    k, l0, w = np.array([7.0]), np.array([1.5]), np.array([0.3])
    for s in (1.0, 0.0):
        sv = np.array([s])
        g, Kt, _, _ = member_forces(xa, Ra, xb, Rb, xc, off, anchor, sv, k, l0, w)
        fd = np.zeros((18, 18))
        h = 1e-6
        for j in range(18):
            out = []
            for sign in (1, -1):
                x = [xa.copy(), xb.copy(), xc.copy()]
                R = [Ra, Rb]
                node, comp = divmod(j, 6)
                if comp < 3:
                    x[node][0, comp] += sign * h
                elif node < 2:
                    phi = np.zeros((1, 3))
                    phi[0, comp - 3] = sign * h
                    R[node] = spin(R[node], phi)
                out.append(member_forces(x[0], R[0], x[1], R[1], x[2], off, anchor, sv, k, l0, w)[0][0])
            fd[:, j] = (out[0] - out[1]) / (2 * h)
        assert np.abs(Kt[0] - fd).max() < 1e-6 * np.abs(Kt[0]).max()
        if s == 0.0:  # to a fixed anchor it is the cord kernel
            gc, Kc, _, _ = cord_forces(xa, Ra, xb, Rb, off, anchor, k, l0, w)
            assert np.allclose(g[0, :12], gc[0]) and np.allclose(Kt[0, :12, :12], Kc[0])


def test_distributed_cord_input_is_checked():
    with pytest.raises(ModelError, match="needs the cord's mass"):
        fg.Cord(node=1, anchor=(0, 0, 1), stiffness=5.0, unstretched_length=0.5, segments=4)
    with pytest.raises(ModelError, match="whole number"):
        fg.Cord(node=1, anchor=(0, 0, 1), stiffness=5.0, unstretched_length=0.5, mass=0.1, segments=2.5)
