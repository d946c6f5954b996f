"""Interpolation links (RBE3): the reference follows the weighted best-fit rigid motion of its nodes.

* the fit reproduces any rigid motion of the nodes exactly (large rotation);
* a load at the reference reaches the nodes as Nastran's RBE3 distributes it: F w_i / W plus
  the moment (X_ref - C) x F spread as w_i (J^-1 M) x r_i, J = sum w_i (|r_i|^2 I - r_i r_i^T);
* a mass on the reference of four sprung corner nodes: heave 4k/m, yaw 8 k a^2 / I_zz and the
  coupled sway/pitch pair of the fitted rigid motion, to 1e-9;
* with a stiff rib at a cantilever's tip, a large tip load through an RBE3 reference bends the
  beam as through a rigid link (RBE2) to the same reference.
"""

import numpy as np
import pytest
import scipy.linalg as sla

import flexgvt as fg
from flexgvt.errors import ModelError
from flexgvt.fem.interpolation import fit
from flexgvt.fem.rotations import expm_so3

from fem_builders import AL


def test_fit_follows_any_rigid_motion():
    rng = np.random.default_rng(7)
    X = rng.standard_normal((5, 3))
    w = rng.random(5)
    w /= w.sum()
    C = w @ X
    X_ref = np.array([0.4, -1.0, 2.0])
    Q0 = expm_so3(np.array([1.2, -2.0, 0.7]))  # 2.5 rad
    t = np.array([3.0, -1.0, 0.5])
    x_ref, Q, _ = fit(X @ Q0.T + t, w, X - C, X_ref - C)
    np.testing.assert_allclose(x_ref, Q0 @ X_ref + t, atol=1e-12)
    np.testing.assert_allclose(Q, Q0, atol=1e-12)


def corner_platform(k=2.0e4, a=0.3, h=0.2, weights=(1.0, 1.0, 1.0, 1.0)):
    model = fg.Model("platform")
    corners = model.add_nodes([[a, a, 0], [-a, a, 0], [-a, -a, 0], [a, -a, 0]])
    (ref,) = model.add_nodes([[0.0, 0.0, h]])
    for c in corners:
        model.add_spring(int(c), None, stiffness=[k, k, k, 0, 0, 0])
    model.add_interpolation(int(ref), [int(c) for c in corners], weights=weights)
    cfg = fg.Configuration("sprung", fixed={int(c): "456" for c in corners})
    return model, cfg, corners, ref


def test_reference_load_is_distributed_as_nastran_rbe3():
    weights = np.array([1.0, 2.0, 3.0, 4.0])
    model, cfg, corners, ref = corner_platform(weights=weights)
    F = np.array([10.0, -20.0, 30.0])
    state = fg.solve_linear_static(model, cfg.with_(forces=(fg.NodalLoad(int(ref), force=tuple(F)),)))
    k = 2.0e4
    got = k * state.displacements[model.index_of([int(c) for c in corners]), :3]  # spring forces on the corners
    X = model.xyz[model.index_of([int(c) for c in corners])]
    w = weights / weights.sum()
    C = w @ X
    r = X - C
    J = sum(wi * (ri @ ri * np.eye(3) - np.outer(ri, ri)) for wi, ri in zip(w, r))
    M = np.cross(model.xyz[model.index_of([int(ref)])[0]] - C, F)
    theta = np.linalg.solve(J, M)
    expected = w[:, None] * F[None, :] + w[:, None] * np.cross(theta, r)
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-9 * np.abs(F).max())


def test_mass_on_the_reference_of_four_sprung_corners():
    k, a, h, m = 2.0e4, 0.3, 0.2, 5.0
    I = np.array([0.04, 0.05, 0.06])
    model, cfg, corners, ref = corner_platform(k, a, h)
    model.add_mass(int(ref), m, inertia=np.diag(I))
    f = np.sort(fg.solve_modes(fg.solve_static(model, cfg), 6).frequencies_hz)
    heave = np.sqrt(4 * k / m)
    yaw = np.sqrt(8 * k * a**2 / I[2])
    # sway x / pitch about y about the centroid: K = diag(4k, 4k a^2), the mass sits h above it
    Kp = np.diag([4 * k, 4 * k * a**2])
    pair = []
    for Ir in (I[1], I[0]):
        Mp = np.array([[m, m * h], [m * h, m * h**2 + Ir]])
        pair += list(np.sqrt(sla.eigh(Kp, Mp, eigvals_only=True)))
    expected = np.sort(np.r_[heave, yaw, pair]) / (2 * np.pi)
    np.testing.assert_allclose(f, expected, rtol=1e-9)


def test_tip_load_through_rbe3_on_a_stiff_rib_matches_a_rigid_link():
    def build(kind):
        model = fg.Model(kind)
        y = np.linspace(0, 1.0, 21)
        ids = model.add_nodes(np.c_[np.zeros_like(y), y, np.zeros_like(y)])
        model.add_beams(np.c_[ids[:-1], ids[1:]], AL, fg.RectangularSection(width=0.05, height=0.004),
                        orientation=(0, 0, 1))
        rib = model.add_nodes([[-0.1, 1.0, 0.0], [0.1, 1.0, 0.0], [0.0, 1.0, 0.05]])
        stiff = fg.Material("stiff", E=AL.E * 1e3, nu=0.3, rho=0.0)
        for r in rib:
            model.add_beams([[int(ids[-1]), int(r)]], stiff, fg.RectangularSection(width=0.02, height=0.02),
                            orientation=(0, 1, 0) if abs(model.xyz[-1][2]) < 1 else (1, 0, 0))
        (ref,) = model.add_nodes([[0.03, 1.02, 0.06]])
        if kind == "rbe3":
            model.add_interpolation(int(ref), [int(ids[-1]), *map(int, rib)])
        else:
            model.add_rigid_link(int(ids[-1]), [int(ref)])
        cfg = fg.Configuration("tip", fixed={int(ids[0]): "123456"},
                               forces=[fg.NodalLoad(int(ref), force=(0, 0, -60.0), moment=(0.0, 2.0, 0.0))])
        state = fg.solve_static(model, cfg)
        return state.displacements[model.index_of([int(ids[-1]), int(ref)])]

    rbe3, rbe2 = build("rbe3"), build("rbe2")
    assert np.abs(rbe2[0, 2]) > 0.2  # tip drops over 20 % of the span
    np.testing.assert_allclose(rbe3, rbe2, rtol=0, atol=1e-4 * np.abs(rbe2[0, :3]).max())


def test_bad_interpolations_are_refused():
    model = fg.Model("bad")
    ids = model.add_nodes([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]])
    with pytest.raises(ModelError, match="lie on one line"):
        model.add_interpolation(int(ids[3]), [int(i) for i in ids[:3]])
    with pytest.raises(ModelError, match="weights must be positive"):
        model.add_interpolation(int(ids[0]), [int(i) for i in ids[1:]], weights=[1.0, 0.0, 1.0])
    with pytest.raises(ModelError, match="'123456' or '123'"):
        model.add_interpolation(int(ids[0]), [int(i) for i in ids[1:]], components="12")


def test_two_node_average_on_the_line():
    """An RBE3 reference between two nodes (components 123) moves as their weighted average plus
    the turn of the line: a load at it splits by the lever rule, and it stays on the turned line."""
    model = fg.Model("pair")
    a, b = model.add_nodes([[0, 0, 0], [1.0, 0, 0]])
    (ref,) = model.add_nodes([[0.25, 0, 0]])
    k = 1.0e4
    for n in (a, b):
        model.add_spring(int(n), None, stiffness=[k, k, k, 0, 0, 0])
    model.add_interpolation(int(ref), [int(a), int(b)], components="123")
    cfg = fg.Configuration("pair", fixed={int(n): "456" for n in (a, b, ref)},
                           forces=[fg.NodalLoad(int(ref), force=(0, 0, -8.0))])
    state = fg.solve_linear_static(model, cfg)
    wa, wb = k * state.displacements[model.index_of([int(a), int(b)]), 2]
    assert (wa, wb) == (pytest.approx(-6.0, rel=1e-9), pytest.approx(-2.0, rel=1e-9))  # lever rule 3:1
    big = fg.solve_static(model, cfg.with_(forces=(fg.NodalLoad(int(ref), force=(0, 0, -8000.0)),)))
    xa, xb, xr = big.positions[model.index_of([int(a), int(b), int(ref)])]
    assert np.linalg.norm(np.cross(xr - xa, xb - xa)) < 1e-12  # still on the line
    (other,) = model.add_nodes([[0.5, 0, 0]])
    with pytest.raises(ModelError, match="lie on one line"):
        model.add_interpolation(int(other), [int(a), int(b)])  # its rotation about the line is undefined
