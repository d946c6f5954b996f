"""A bungee's own weight in the hung solution: half of it on the structure, a third of its mass
moving with the attachment (Rayleigh), so a block on a heavy cord sits and bounces as a uniform
spring's closed forms say."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.suspension import Bungee, Line

G = 9.80665


def _block(mass_block: float, line: Line):
    model = fg.Model("block")
    ids = model.add_nodes([[0.0, -0.05, 0.0], [0.0, 0.05, 0.0]])
    model.add_beams([ids], fg.Material("steel", E=2e11, nu=0.3, rho=0.0), fg.RectangularSection(0.05, 0.05),
                    orientation=(0, 0, 1))
    model.add_mass(int(ids[0]), mass_block / 2)
    model.add_mass(int(ids[1]), mass_block / 2)
    cords = [line.cord(int(n), (0.0, float(y), 20.5), (0.0, float(y), 0.0), mass_block / 2 * G)
             for n, y in zip(ids, (-0.05, 0.05))]
    return model, fg.Configuration("hung", suspension=cords, gravity=1.0), cords


def test_block_on_heavy_bungees_sits_where_sized_and_plunges_at_the_rayleigh_frequency():
    bungee = Bungee(EA=92.5, mass_per_length=0.02)
    line = Line((bungee.element(20.0),))
    M = 2.0
    model, cfg, cords = _block(M, line)
    assert cords[0].mass == pytest.approx(0.4)
    state = fg.solve_static(model, cfg)
    # Sized with the cord's weight: the block stays where the cords were sized to hold it.
    assert np.abs(state.displacements[:, 2]).max() < 1e-6
    k = 2 * cords[0].stiffness
    plunge = fg.solve_modes(state, 6, damped=False)
    f = plunge.frequencies_hz[plunge.labels.index("RB plunge")]
    rayleigh = np.sqrt(k / (M + 2 * 0.4 / 3)) / (2 * np.pi)
    assert f == pytest.approx(rayleigh, rel=1e-4)
    # The exact first mode of a mass on a uniform spring: w L/c tan(w L/c) = m_cord / M.
    from scipy.optimize import brentq
    ratio = 2 * 0.4 / M
    beta = brentq(lambda b: b * np.tan(b) - ratio, 1e-6, np.pi / 2 - 1e-9)
    exact = beta * np.sqrt(k / (2 * 0.4)) / (2 * np.pi)
    assert f == pytest.approx(exact, rel=2e-3)  # Rayleigh's third: 0.1 % high at m_cord / M = 0.4
    massless = fg.solve_modes(fg.solve_static(model, cfg.with_(suspension=tuple(
        c.__class__(**{**c.__dict__, "mass": 0.0}) for c in cords))), 6, damped=False)
    assert massless.frequencies_hz[massless.labels.index("RB plunge")] > 1.05 * f


def test_bad_suspension_input_is_named():
    from flexgvt.errors import ModelError
    from flexgvt.suspension import identify_block
    with pytest.raises(ModelError, match="mass"):
        identify_block(mass=-0.8, frequency_hz=0.4, damping_ratio=0.07)
    with pytest.raises(ModelError, match="mass=-0.1 must be >= 0"):
        fg.Cord(node=1, anchor=(0, 0, 1), stiffness=5.0, unstretched_length=0.5, mass=-0.1)
    model, cfg, cords = _block(2.0, Line((Bungee(EA=92.5).element(20.0),)))
    slack = cords[0].__class__(**{**cords[0].__dict__, "unstretched_length": 21.0})
    # Named as a warning. The block then drops on the other cord until the slack one takes up load
    # (1.3 m), and hangs tilted on both: a stable equilibrium, every mode at a real frequency.
    with pytest.warns(UserWarning, match=r"cord 0 \(node 1\) is slack at the start"):
        state = fg.solve_static(model, cfg.with_(suspension=(slack, cords[1])))
    assert np.all(state.cord_tension > 0) and state.displacements[:, 2].min() < -1.0
    f = fg.solve_modes(state, 5, damped=False).frequencies_hz
    assert np.all(f > 0.05)


def test_modes_of_a_block_with_massless_rotations_are_the_condensed_ones():
    """The block above hanging on both cords: its nodes' rotations carry no mass. The modes are
    those of the stiffness condensed onto the translations (independent reference); the general
    eigensolver used before on such small models returned a spurious negative and a spurious
    0.135 Hz mode in place of one of each repeated pair."""
    import scipy.linalg as sla
    model, cfg, cords = _block(2.0, Line((Bungee(EA=92.5).element(20.0),)))
    slack = cords[0].__class__(**{**cords[0].__dict__, "unstretched_length": 21.0})
    with pytest.warns(UserWarning):
        state = fg.solve_static(model, cfg.with_(suspension=(slack, cords[1])))
    s, x, R = state.system, state.positions, state.rotations
    M = s.mass_matrix(x, R).toarray()
    K = s.newton_matrix(s.evaluate(x, R, 1.0, assemble=False), s.mass_matrix(x, R), 0.0).toarray()
    t = np.flatnonzero(np.diag(M) > 0)
    r = np.flatnonzero(np.diag(M) == 0)
    Kc = K[np.ix_(t, t)] - K[np.ix_(t, r)] @ np.linalg.pinv(K[np.ix_(r, r)]) @ K[np.ix_(r, t)]
    lam = sla.eigh(0.5 * (Kc + Kc.T), M[np.ix_(t, t)], eigvals_only=True)
    # Both carry an error of up to eps * lambda_max in every eigenvalue (the axially stiff block:
    # lambda_max 1e10 rad^2/s^2; measured 2e-6 absolute, 4e-6 of the 0.1 Hz mode's eigenvalue, and
    # it moved by that much with the static state's last digits): ten times eps * lambda_max.
    atol = 10 * np.finfo(float).eps * lam.max()
    computed = (2 * np.pi * fg.solve_modes(state, 6, damped=False).frequencies_hz[:5]) ** 2
    assert computed == pytest.approx(lam[:5], rel=1e-9, abs=atol)
