"""Sensors, MAC family and pairing: closed forms, rigid arms against finite rotations, crossing
modes, end to end from identified (ema) to analytical (fem) modes."""

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.correlation import (Sensor, Sensors, auto_mac, comac, cross_orthogonality, mac, pair,
                                 subspace_mac)
from flexgvt.errors import ModelError
from flexgvt.fem.rotations import expm_so3


def test_mac_closed_forms():
    rng = np.random.default_rng(0)
    a = rng.standard_normal((3, 20))
    q, _ = np.linalg.qr(rng.standard_normal((20, 3)))
    np.testing.assert_allclose(np.diag(mac(a, a)), 1.0)
    np.testing.assert_allclose(mac(q.T, q.T), np.eye(3), atol=1e-14)  # orthogonal shapes: 0
    # Invariant to scale and (complex) phase; complex shapes use the conjugate transpose.
    c = a * (2.5 * np.exp(1j * 0.7))
    np.testing.assert_allclose(mac(a, c), mac(a, a), atol=1e-14)
    z = a + 1j * rng.standard_normal(a.shape)
    m = mac(z, z * np.exp(-1j * 1.1))
    np.testing.assert_allclose(np.diag(m), 1.0)
    # A worked value: (1, 1) against (1, 0) -> cos^2(45 deg) = 0.5.
    assert mac(np.array([[1.0, 1.0]]), np.array([[1.0, 0.0]]))[0, 0] == pytest.approx(0.5)
    np.testing.assert_allclose(auto_mac(q.T), np.eye(3), atol=1e-14)


def test_comac_and_cross_orthogonality_of_identical_sets():
    rng = np.random.default_rng(1)
    phi = rng.standard_normal((4, 12))
    np.testing.assert_allclose(comac(phi, -3.0 * phi), 1.0)
    # A perturbed row (sensor) shows a lower COMAC than the others.
    bad = phi.copy()
    bad[:, 5] += rng.standard_normal(4)
    c = comac(phi, bad)
    assert np.argmin(c) == 5 and c[5] < 0.9 and np.delete(c, 5).min() > 0.9
    # SEREP cross-orthogonality of a set with itself: the identity.
    np.testing.assert_allclose(np.abs(cross_orthogonality(phi, phi)), np.eye(4), atol=1e-10)
    M = np.diag(rng.uniform(1, 2, 12))
    np.testing.assert_allclose(np.abs(cross_orthogonality(phi, phi, mass=M)).diagonal(), 1.0)
    assert subspace_mac(phi[:2], phi) == pytest.approx(1.0)


def _state(rotation_vector):
    R = expm_so3(np.asarray(rotation_vector, float)[None, :])
    return SimpleNamespace(rotations=R, node_ids=np.array([7]))


def test_an_offset_sensor_reads_the_rigid_arm_through_the_nodes_rotation():
    """Reading = d . (u + theta x r) with r and d turned by the node's rotation: against the exact
    motion of the sensor point under a finite rotation increment (central difference)."""
    r0, d0 = np.array([0.10, 0.02, -0.03]), np.array([0.3, 0.4, 0.866])
    s = Sensors([Sensor(7, d0, r0)])
    state = _state([0.2, -0.5, 0.4])
    R = state.rotations[0]
    S = s.matrix(np.array([7]), state).toarray()[0]
    du, dth = np.array([1e-3, -2e-3, 0.5e-3]), np.array([0.3, -0.1, 0.2])
    h = 1e-5
    d = R @ (d0 / np.linalg.norm(d0))

    def point(t):  # sensor position after a spin t * dth and a translation t * du
        return t * du + expm_so3((t * dth)[None, :])[0] @ R @ r0

    exact = d @ (point(h) - point(-h)) / (2 * h)
    assert S @ np.r_[du, dth] == pytest.approx(exact, rel=1e-9)
    # Not following the structure: the undeformed arm and direction.
    S0 = s.matrix(np.array([7]), state, follow=False).toarray()[0]
    d_u = d0 / np.linalg.norm(d0)
    assert S0 @ np.r_[du, dth] == pytest.approx(d_u @ (du + np.cross(dth, r0)))


def test_uniaxial_triaxial_and_uff_outputs():
    ids = np.array([3, 5, 9])
    tri = Sensors.triaxial([9, 3]).matrix(ids).toarray()
    assert tri.shape == (6, 18)
    np.testing.assert_array_equal(tri[:3, 12:15], np.eye(3))  # node 9 is the third node
    np.testing.assert_array_equal(tri[3:, 0:3], np.eye(3))
    uni = Sensors.uniaxial([5], (1.0, 1.0, 0.0)).matrix(ids).toarray()
    np.testing.assert_allclose(uni[0, 6:9], np.array([1, 1, 0]) / np.sqrt(2))
    s = Sensors.from_outputs(np.array([[103, -3], [105, 1]]), node_map={103: 3, 105: 5})
    assert s.names == ["103-Z", "105+X"]
    m = s.matrix(ids).toarray()
    assert m[0, 2] == -1.0 and m[1, 6] == 1.0
    with pytest.raises(ModelError, match="node\\(s\\) \\[4\\]"):
        Sensors.uniaxial([4], (0, 0, 1)).matrix(ids)
    with pytest.raises(ModelError, match="not a translation"):
        Sensors.from_outputs(np.array([[3, 5]]))
    with pytest.raises(ModelError, match="NaN"):
        mac(np.array([[1.0, np.nan]]), np.array([[1.0, 0.0]]))


def _strip_modes(gravity, n=10):
    case = fg.cases.cantilever_strip(n_elements=30)
    cfg = case.configurations["unloaded"].with_(gravity=gravity)
    state = fg.solve_static(case.model, cfg)
    return fg.solve_modes(state, n), case


def test_pairing_follows_modes_that_cross_as_the_load_grows():
    """Under self-weight the first torsion mode (61.1 Hz unloaded) couples with in-plane bending and
    rises past the fifth bending mode (62.3 Hz): pairing load step to load step by MAC follows it
    through the crossing, where the sorted index would jump to the bending mode."""
    ids = fg.cases.cantilever_strip(n_elements=30).model.node_ids
    sensors = Sensors(list(Sensors.uniaxial(np.repeat(ids[3::3], 2), (0, 0, 1),
                                            np.tile([[-0.02, 0, 0], [0.02, 0, 0]], (10, 1))))
                      + list(Sensors.uniaxial(ids[3::3], (1, 0, 0))))
    sets = [_strip_modes(g)[0] for g in np.linspace(0.0, 1.0, 11)]
    torsion = sets[0].labels.index("1 T")
    chain, crossings = torsion, 0
    for prev, nxt in zip(sets, sets[1:]):
        meas = SimpleNamespace(frequencies_hz=prev.frequencies_hz,
                               shapes=np.asarray(sensors.matrix(prev.node_ids, prev.state) @ prev.matrix()).T)
        p = pair(meas, nxt, sensors=sensors, mac_floor=0.8)
        assert not p.unpaired and p.mac.min() > 0.8
        crossings += int(np.any(p.analytical != p.measured))
        chain = int(p.analytical[list(p.measured).index(chain)])
    assert crossings >= 1
    last = sets[-1]
    assert chain == torsion + 1 and "T" in last.labels[chain]
    assert "OOP" in last.labels[torsion]  # what the sorted index would have paired it with
    assert last.frequencies_hz[chain] > sets[0].frequencies_hz[torsion + 1]


def test_a_measured_mode_the_model_lacks_is_left_unpaired():
    modes, case = _strip_modes(0.0, 6)
    sensors = Sensors.triaxial(case.model.node_ids[5::5])
    shapes = np.asarray(sensors.matrix(modes.node_ids, modes.state) @ modes.matrix()).T
    alien = np.zeros(shapes.shape[1])
    alien[1::3] = 1.0  # the strip stretching along its span: no mode below 100 Hz does that
    meas = SimpleNamespace(frequencies_hz=np.r_[modes.frequencies_hz[:3], 40.0], shapes=np.vstack([shapes[:3], alien]))
    p = pair(meas, modes, sensors=sensors)
    assert p.unpaired == (3,) and "left unpaired" in p.report()
    assert [r["analytical_mode"] for r in p.table()] == [1, 2, 3, None]


def test_free_free_rigid_body_modes_are_not_paired_but_their_subspace_is_seen():
    case = fg.cases.strip_366(n_elements=61)
    modes = fg.solve_modes(fg.solve_static(case.model, case.configurations["free_free"]), 9)
    sensors = Sensors.triaxial(case.model.node_ids[::6], offsets=(0.02, 0.0, 0.0))  # off the axis: roll is seen
    assert np.sum(modes.frequencies_hz == 0) == 6
    p = pair(modes, modes, sensors=sensors)
    assert set(p.analytical.tolist()) == {6, 7, 8}
    rigid = SimpleNamespace(shapes=np.asarray(sensors.matrix(modes.node_ids, modes.state) @ modes.matrix()).T[:6])
    # Any rotated basis of the six rigid-body motions spans the same space.
    q, _ = np.linalg.qr(np.random.default_rng(2).standard_normal((6, 6)))
    assert subspace_mac(q @ rigid.shapes, rigid.shapes) == pytest.approx(1.0)


def test_identified_modes_against_analytical_ones_end_to_end():
    """Synthetic FRFs of the strip at 10 stations (Z) -> PolyMAX -> ModalSet, correlated with
    the fem Modes as they are (the ModalSet's outputs name the FE nodes)."""
    from flexgvt.ema import modal_model_from_modes, polymax, synthesize_frfs
    modes, case = _strip_modes(0.0, 6)
    stations = case.model.node_ids[3::3]
    model, _ = modal_model_from_modes(modes, [(n, (0, 0, 1)) for n in stations])
    model = replace(model, damping_ratio=np.full(6, 0.01))
    f = np.linspace(0.5, 45.0, 2000)
    frfs = synthesize_frfs(model, f, list(range(10)), [9], snr_db=40, seed=3)
    frfs = replace(frfs, outputs=np.column_stack([stations, np.full(10, 3)]),
                   inputs=np.array([[stations[-1], 3]]))
    measured = polymax(frfs, max_order=30, frequency_band=(0.8, 40.0)).select()
    m = mac(measured, modes)
    p = pair(measured, modes)
    bending = [k for k, lab in enumerate(modes.labels) if "OOP" in lab and modes.frequencies_hz[k] < 40]
    assert sorted(p.analytical.tolist()) == bending
    assert p.mac.min() > 0.99 and np.abs(p.frequency_error).max() < 1e-3
    assert m.shape == (len(measured.frequencies_hz), 6)


def test_a_far_mode_with_a_high_mac_is_not_paired():
    """Few sensors can see a far mode's tiny motion with a high MAC: beyond max_frequency_ratio it
    never pairs (a 16 Hz torsion mode must not pair with a 0.3 Hz pendulum mode)."""
    shape = np.array([[1.0, 0.5, -0.3, 0.2]])
    meas = SimpleNamespace(frequencies_hz=np.array([16.0]), shapes=shape)
    fe = SimpleNamespace(frequencies_hz=np.array([0.3, 12.0]),
                         shapes=np.vstack([shape, shape + [[0.0, 0.4, 0.3, 0.0]]]))
    assert pair(meas, fe, max_frequency_ratio=None).analytical.tolist() == [0]
    p = pair(meas, fe)
    assert p.analytical.tolist() == [1] and p.mac[0] < 1.0
    fe_far = SimpleNamespace(frequencies_hz=np.array([0.3, 40.0]), shapes=fe.shapes)
    assert pair(meas, fe_far).unpaired == (0,)
    with pytest.raises(ModelError, match="max_frequency_ratio"):
        pair(meas, fe, max_frequency_ratio=1.0)


def test_comac_against_a_hand_computed_case():
    """Modes a = [1, 1], [1, -1] against b = [1, 1], [1, 0] (scale factors 1 and 1): DOF 1 sees
    |1 + 1|^2 / (2 * 2) = 1, DOF 2 sees |1 * 1 - 1 * 0|^2 / (2 * 1) = 0.5; pairs pick the columns."""
    a = np.array([[1.0, 1.0], [1.0, -1.0]])
    b = np.array([[1.0, 1.0], [1.0, 0.0]])
    np.testing.assert_allclose(comac(a, b), [1.0, 0.5])
    np.testing.assert_allclose(comac(a, b[::-1], pairs=([0, 1], [1, 0])), [1.0, 0.5])
    np.testing.assert_allclose(comac(a, 2j * b), [1.0, 0.5])  # complex scale factors are taken out
