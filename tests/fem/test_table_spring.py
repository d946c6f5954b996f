"""The table spring (model.Spring.tables): its table, its exact tangent (finite differences), closed
forms (a mass hung on a hardening or softening spring; a rigid bar on a nonlinear rotational root
spring under a tip load), a peer (OpenSeesPy, numbers stored), and its design variable."""

import json

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.errors import ModelError
from flexgvt.fem.rotations import expm_so3
from flexgvt.fem.system import System
from flexgvt.model import SpringTable

import table_spring_peer as peer
from fem_builders import perturbed_state, tangent_error

G0 = fg.model.STANDARD_GRAVITY


# ---------------------------------------------------------------- the table
@pytest.mark.parametrize("x, f, message", [
    ([0.0, 0.2, 0.1], [0.0, 1.0, 2.0], "increase strictly"),
    ([0.0, 0.1, 0.1], [0.0, 1.0, 2.0], "increase strictly"),
    ([0.0], [0.0], "at least two"),
    ([0.0, np.nan], [0.0, 1.0], "NaN"),
    ([0.0, 1.0], [0.0, np.inf], "NaN"),
    ([0.0, 1.0, 2.0], [0.0, 1.0], "one force per deflection"),
    ([-1.0, 1.0], [1.0, 3.0], "preload"),
    ([-1.0, 0.0, 1.0], [0.0, 0.0, 0.0], "flat"),
    (["a", 1.0], [0.0, 1.0], "numbers"),
])
def test_malformed_tables_are_refused(x, f, message):
    with pytest.raises(ModelError, match=message):
        SpringTable.make(x, f, name="t1")


def test_piecewise_linear_table_and_end_slopes():
    t = SpringTable.make([-0.2, 0.0, 0.1, 0.3], [-10.0, 0.0, 2.0, 12.0])
    force, slope = t.evaluate([-0.3, -0.1, 0.0, 0.05, 0.1, 0.2, 0.5])
    np.testing.assert_allclose(force, [-15.0, -5.0, 0.0, 1.0, 2.0, 7.0, 22.0])  # ends: the end slopes
    np.testing.assert_allclose(slope, [50.0, 50.0, 20.0, 20.0, 50.0, 50.0, 50.0])  # at a knot: the right segment
    assert t.nominal_stiffness == 20.0
    gap = SpringTable.make([-0.1, 0.0, 0.1], [-5.0, 0.0, 0.0])  # compression only: 0 slope at 0
    assert gap.nominal_stiffness == 50.0


def test_smooth_table_is_scipys_pchip_with_linear_ends():
    x = np.array([-0.3, -0.1, 0.0, 0.05, 0.2, 0.4])
    f = np.array([-40.0, -6.0, 0.0, 1.5, 9.0, 40.0])
    t = SpringTable.make(x, f, smooth=True)
    ref = PchipInterpolator(x, f)
    d = np.linspace(-0.3, 0.4, 301)
    force, slope = t.evaluate(d)
    np.testing.assert_allclose(force, ref(d), atol=1e-12 * 40)
    np.testing.assert_allclose(slope, ref.derivative()(d), atol=1e-10 * 300)
    out_f, out_k = t.evaluate([-0.5, 0.6])
    ends = ref.derivative()(x[[0, -1]])
    np.testing.assert_allclose(out_k, ends)
    np.testing.assert_allclose(out_f, f[[0, -1]] + ends * [-0.2, 0.2])


def test_spring_scale_and_table_arguments():
    t = SpringTable.make([-0.1, 0.0, 0.1], [-30.0, 0.0, 20.0])
    s = fg.Spring.make(1, None, stiffness=[1e3, 0, 0, 0, 0, 0], tables={2: t})
    assert s.stiffness[1] == 200.0 and s.nonlinear and s.table_scale[1] == 1.0  # 0 given: the nominal
    s2 = fg.Spring.make(1, None, stiffness=[0, 400.0, 0, 0, 0, 0], tables={2: t})
    assert s2.table_scale[1] == 2.0
    model = fg.Model("m")
    model.add_nodes([[0, 0, 0]], ids=[1])
    model.add_spring(1, None, stiffness=[1e3] * 6, tables={2: t}, name="s")
    model.set_spring(0, stiffness=np.r_[1e3, 300.0, [1e3] * 4])
    assert model.springs[0].tables[1] is t and model.springs[0].table_scale[1] == 1.5
    for bad in ({7: t}, {"y": t}, [t] * 5, {2: ([0, 1], [0, 1])}):
        with pytest.raises(ModelError, match="table"):
            fg.Spring.make(1, None, tables=bad)


# ---------------------------------------------------------------- the exact tangent
def _springs_only(smooth: bool):
    """Three nodes on grounded and node-to-node table springs with turned axes, every component of
    some spring tabulated (translations and rotations), no beams: the springs are the whole tangent."""
    model = fg.Model("table springs")
    ids = [int(i) for i in model.add_nodes([[0, 0, 0], [0.3, 0.1, 0], [0.3, 0.1, 0.0]])]
    for i in ids:
        model.add_mass(i, 1.0, inertia=np.eye(3) * 1e-2)
    tt = SpringTable.make([-0.05, -0.02, 0, 0.013, 0.04], [-900, -150, 0, 100, 500], smooth=smooth)
    tr = SpringTable.make([-0.5, -0.1, 0, 0.1, 0.3], [-90, -12, 0, 10, 70], smooth=smooth)
    Q = expm_so3(np.array([0.3, -0.2, 0.5]))
    model.add_spring(ids[0], None, stiffness=[1e4, 2e4, 0, 0, 50, 60], tables={3: tt, 4: tr}, frame=Q)
    model.add_spring(ids[1], None, stiffness=[1e4, 2e4, 3e4, 40, 50, 60], frame=Q)
    model.add_spring(ids[1], ids[2], stiffness=[0, 2e3, 3e3, 4, 0, 6], tables={1: tt, 5: tr, 6: tt}, frame=Q.T)
    model.add_spring(ids[0], ids[1], stiffness=[0, 2e3, 3e3, 0, 0, 6], tables={1: tt, 4: tr, 5: tr}, frame=Q.T)
    return System(model, fg.Configuration("c", gravity=1.0))


@pytest.mark.parametrize("smooth", [False, True])
def test_tangent_is_exact_by_finite_differences(smooth):
    """Random states with deflections of ~2 cm and rotations of ~0.2 rad (across the tables' knots
    and beyond their ends). The finite difference's round-off is eps |residual| / h relative to
    |K| (~1e-12 at h = 1e-5); piecewise-linear tables are exact to it (no state sits within h of a
    knot). The cubic's truncation h^2 f''' / 6 dominates at h = 1e-5 (measured 5e-10 to 3e-8); the
    error falls by 100 (h^2) at h / 10, which only an exact tangent does."""
    system = _springs_only(smooth)
    for seed in (1, 2, 3):
        x, R = perturbed_state(system, seed)
        err, K = tangent_error(system, x, R, lam=0.7, h=1e-5)
        res = system.evaluate(x, R, 0.7, tangent=False)
        noise = 1e-16 * np.abs(res.internal - res.external).max() / 1e-5 / np.abs(K).max()
        assert np.abs(K - K.T).max() / np.abs(K).max() > 1e-4  # rotation terms: not a symmetric triviality
        if not smooth:
            assert err < 100 * noise + 1e-11, (seed, err, noise)
        else:
            err10, _ = tangent_error(system, x, R, lam=0.7, h=1e-6)
            assert err < 1e-7 and (err10 < 100 * noise + 1e-11 or err10 < err / 50), (seed, err, err10, noise)


# ---------------------------------------------------------------- closed forms
def _hung(table: SpringTable, mass: float, g: float):
    model = fg.Model("hung mass")
    (n,) = model.add_nodes([[0.0, 0.0, 0.0]])
    model.add_mass(int(n), mass, inertia=np.eye(3) * 1e-3)
    model.add_spring(int(n), None, stiffness=[1e4, 1e4, 0, 10, 10, 10], tables={3: table})
    state = fg.solve_static(model, fg.Configuration("g", gravity=g), settings=fg.StaticSettings(tolerance=1e-13))
    return state.displacements[0, 2], fg.solve_modes(state, 6, label=False).frequencies_hz


@pytest.mark.parametrize("smooth", [False, True])
@pytest.mark.parametrize("kind", ["hardening", "softening"])
def test_mass_hung_on_a_table_spring(kind, smooth):
    """Static deflection d with f(-d) = -m g (the table's inverse), and the vertical frequency
    sqrt(k_t / m) / 2 pi with k_t the table's slope there (the consistent tangent in the modes)."""
    d = np.linspace(-0.03, 0.03, 13)
    f = 2e4 * d * (1 + 3e3 * d**2) if kind == "hardening" else 2e4 * d / (1 + 40 * np.abs(d))
    table = SpringTable.make(d, f, smooth=smooth)
    m = 10.0
    for g in (0.5, 1.5, 3.0):  # the last beyond the softening table's end (294 N against 273 N there)
        z, freqs = _hung(table, m, g)
        weight = m * g * G0
        expected = brentq(lambda u: table.evaluate(u)[0] + weight, -0.1, 0.0)
        assert z == pytest.approx(expected, rel=1e-10, abs=1e-14)
        k_t = float(table.evaluate(z)[1])
        vertical = freqs[np.argmin(np.abs(freqs - np.sqrt(k_t / m) / (2 * np.pi)))]
        assert vertical == pytest.approx(np.sqrt(k_t / m) / (2 * np.pi), rel=1e-9)
    k0 = table.nominal_stiffness
    assert (k_t > 1.5 * k0) if kind == "hardening" else (k_t < 0.7 * k0)  # the modes follow the load


def test_rigid_bar_on_a_nonlinear_rotational_root_spring():
    """A rigid bar of length L with a tip mass m on a root spring M(theta) (hardening table about y),
    a fixed-direction tip load P: equilibrium M(theta) = P L cos(theta), tip (-L(1 - cos), -L sin);
    the pendulum frequency about that state sqrt((M'(theta) + P L sin(theta)) / (m L^2)) / 2 pi (the
    dead load's stiffness included)."""
    L, m = 0.8, 1.5
    th = np.array([-0.6, -0.3, -0.1, 0.0, 0.1, 0.3, 0.6])
    table = SpringTable.make(th, 40 * th + 300 * th**3)
    model = fg.Model("bar")
    r, tip = (int(i) for i in model.add_nodes([[0, 0, 0], [L, 0, 0]]))
    model.add_mass(tip, m)
    model.add_rigid_link(r, [tip])
    model.add_spring(r, None, tables={5: table})
    for P in (5.0, 20.0, 40.0):
        cfg = fg.Configuration("P", fixed={r: "12346"}, forces=[fg.NodalLoad(tip, force=(0, 0, -P))])
        state = fg.solve_static(model, cfg)
        theta = brentq(lambda a: table.evaluate(a)[0] - P * L * np.cos(a), 0.0, 1.0)
        np.testing.assert_allclose(state.displacements[1, [0, 2, 4]],
                                   [-L * (1 - np.cos(theta)), -L * np.sin(theta), theta], rtol=1e-9)
        k = table.evaluate(theta)[1] + P * L * np.sin(theta)
        f1 = fg.solve_modes(state, 1, label=False).frequencies_hz[0]
        assert f1 == pytest.approx(np.sqrt(k / (m * L**2)) / (2 * np.pi), rel=1e-9)


def test_straight_table_is_the_linear_spring():
    """A table of constant slope k gives the linear spring's statics and loaded modes (to round-off)."""
    results = []
    for tabled in (False, True):
        case = fg.cases.cantilever_strip(n_elements=12)
        model = case.model
        root = int(model.node_ids[0])
        k = np.array([1e5, 1e5, 1e5, 40.0, 20.0, 300.0])
        tables = {c + 1: SpringTable.make([-1.0, 1.0], [-k[c], k[c]]) for c in range(6)} if tabled else None
        model.add_spring(root, None, stiffness=np.zeros(6) if tabled else k, tables=tables, name=f"root{tabled}")
        cfg = case.configurations["flatwise_2g"].with_(fixed={})
        state = fg.solve_static(model, cfg)
        results.append((state.displacements, fg.solve_modes(state, 6, label=False).frequencies_hz))
    np.testing.assert_allclose(results[1][0], results[0][0], rtol=0, atol=1e-12)
    # The modes' round-off: one model's frequencies through SuperLU and through PARDISO differ by up to
    # 1.1e-9 (the 16.4 Hz mode; measured 2026-11-27), so 1e-8.
    np.testing.assert_allclose(results[1][1], results[0][1], rtol=1e-8)


# ---------------------------------------------------------------- the peer: OpenSeesPy
# OpenSeesPy 3.7.1.2 (pip openseespy; Debian libblas3, liblapack3), tests/fem/table_spring_peer.py's
# opensees_results(case) run on 2026-11-27: zeroLength + ElasticMultiLinear root spring, 10
# elasticBeamColumn elements with geomTransf Corotational, 20 LoadControl steps per level, Newton to
# NormDispIncr 1e-13, eigen -fullGenLapack.
OPENSEES = json.loads("""{
"soft": {"tip_x": [0.0, -0.004232522073085758, -0.012057769937584875, -0.020929721055432435,
  -0.03183265565197969, -0.04444761473839859],
 "tip_z": [0.0, -0.09092847387825337, -0.1525321708596972, -0.19967885042478453, -0.24489679559654484,
  -0.2878818934429421],
 "frequencies_hz": [[1.5796369193516315, 5.695110233384869, 15.445781714498532, 50.49634632689663],
  [1.5866242262911008, 5.607025066978266, 15.443726686561806, 50.47893606790516],
  [2.2054730439342207, 5.464081333882714, 16.969085847965037, 52.55903582718896],
  [2.224413773437191, 5.325740850512965, 16.949463490188364, 52.465818351452974],
  [2.2487974084131532, 5.1767773509925625, 16.92291096401136, 52.34366431605389],
  [2.2779474970743996, 5.027571840316045, 16.89106875236001, 52.19888523279736]]},
"stiff": {"tip_x": [0.0, -0.004232522073085758, -0.012057769937584875, -0.020929721055432435,
  -0.03183265565197969, -0.04444761473839859],
 "tip_z": [0.0, -0.09092847387825337, -0.1525321708596972, -0.19967885042478453, -0.24489679559654484,
  -0.2878818934429421],
 "frequencies_hz": [[1.5796369193516315, 15.445781714498532, 17.09956852198725, 50.49634632689663],
  [1.5866242262911008, 15.443726686561806, 17.02585983367848, 50.47893606790516],
  [2.2054730439342207, 16.818594821405675, 16.969085847965037, 52.55903582718896],
  [2.224413773437191, 16.50350154233637, 16.949463490188364, 52.465818351452974],
  [2.2487974084131532, 16.11225148518627, 16.92291096401136, 52.34366431605389],
  [2.2779474970743996, 15.67706164260245, 16.89106875236001, 52.19888523279736]]}}""")


def _against_peer(ours: dict, theirs: dict, modes) -> None:
    """Measured: tip z within 7.4e-5, tip x (axial shortening, second order) 4.5e-4, frequencies
    6.6e-4 (all growing with the load from 0: the beams' corotational formulations differ in the
    higher-order terms); unloaded frequencies equal to 1e-9."""
    np.testing.assert_allclose(ours["tip_z"], theirs["tip_z"], rtol=2e-4, atol=1e-12)
    np.testing.assert_allclose(ours["tip_x"], theirs["tip_x"], rtol=1e-3, atol=1e-12)
    f, ref = np.array(ours["frequencies_hz"]), np.array(theirs["frequencies_hz"])
    np.testing.assert_allclose(f[0], ref[0], rtol=1e-9)
    np.testing.assert_allclose(f[:, modes], ref[:, modes], rtol=1.5e-3)
    assert f[-1, 0] > 1.4 * f[0, 0]  # the root stiffens: the first mode rises 44 % by 10 N


@pytest.fixture(scope="module")
def ours():
    return {case: peer.flexgvt_results(case) for case in peer.CASES}


def test_cantilever_on_a_table_root_spring_against_opensees(ours):
    """Every mode of the "stiff" case; the "soft" case's modes 1, 3, 4 (flatwise bending on the
    table's ry, axial). Its mode 2 (in-plane, on the soft rz root spring, coupled with torsion on rx
    under the load) is 0.9 % to 5.5 % above OpenSees's: the zeroLength element takes the node's
    rotations as accumulated components, flexgvt's spring the rotation vector of the relative
    rotation (a potential; the linear spring's measure), which adds the moment's terms (about
    M_y / 2 ~ 2.5 N m/rad against rx's 50) where the root has turned 0.2 rad. With rx and rz 1000
    times stiffer ("stiff") the two agree to 6.6e-4."""
    _against_peer(ours["stiff"], OPENSEES["stiff"], [0, 1, 2, 3])
    _against_peer(ours["soft"], OPENSEES["soft"], [0, 2, 3])
    soft = np.array(ours["soft"]["frequencies_hz"])[:, 1] / np.array(OPENSEES["soft"]["frequencies_hz"])[:, 1] - 1
    assert 0.005 < soft[1] < soft[-1] < 0.06  # the measure difference named above, growing with the turn


def test_opensees_rerun(ours):
    """Reruns the peer (OpenSeesPy) when it is installed; the stored numbers are what it gave."""
    pytest.importorskip("openseespy.opensees", reason="OpenSeesPy not installed (pip install openseespy; it needs "
                                                      "Debian's libblas3 and liblapack3): the stored numbers stand")
    for case in peer.CASES:
        theirs = peer.opensees_results(case)
        for key in ("tip_x", "tip_z", "frequencies_hz"):
            np.testing.assert_allclose(theirs[key], OPENSEES[case][key], rtol=1e-7, atol=1e-12)
    _against_peer(ours["stiff"], peer.opensees_results("stiff"), [0, 1, 2, 3])


# ---------------------------------------------------------------- the design variable
@pytest.mark.parametrize("attribute, smooth", [("k5", False), ("stiffness", True)])
def test_table_spring_stiffness_variable_derivative(attribute, smooth):
    """updating.spring scales a table spring (its force and slope) through its stiffness: the
    frequency and static Jacobian of two loaded configurations against central differences of the
    whole solve (Richardson, h = 2e-3), within five standard deviations of the finite difference's
    measured noise or its truncation estimate (measured: error 7e-8 (straight segments) and 5e-7
    (cubic) of the largest entry, at the noise, which does not fall with h)."""
    model, root, tip = peer.flexgvt_model("soft", smooth)  # smooth: the table's curvature in the state terms
    cfgs = [fg.Configuration(f"P{P}", forces=[fg.NodalLoad(tip, force=(0, 0, -P))]) for P in (3.0, 8.0)]
    data = [up.Measured(c.name, np.array([1.9, 5.2, 16.0]), static={(tip, 3): -0.2}) for c in cfgs]
    problem = up.UpdatingProblem(model, cfgs, data, [up.spring("k", "root", attribute)], None,
                                 up.Objective(static=1.0), static_settings=fg.StaticSettings(tolerance=1e-13))
    x0 = np.array([1.1])
    point = problem.evaluate(x0, gradient=True)
    J, r0 = point.jacobian[:, 0], point.residuals
    h = 2e-3
    r = {s: problem.evaluate(x0 + s * h).residuals for s in (1, 0.5, -0.5, -1)}
    d1, d2 = (r[1] - r[-1]) / (2 * h), (r[0.5] - r[-0.5]) / h
    fd = (4 * d2 - d1) / 3
    assert np.abs(fd).max() > 1e-3  # the variable moves the residuals
    # The residuals' own noise (the static solves' round-off), from the fourth difference of the five
    # evaluations (its h^4 truncation is far below it): the Richardson value carries 1.9 noise / h.
    noise = np.abs(r[-1] - 4 * r[-0.5] + 6 * r0 - 4 * r[0.5] + r[1]).max() / np.sqrt(70)
    allowed = max(5 * 1.9 * noise / h, 3 * np.abs(d2 - d1).max(), 1e-9 * np.abs(fd).max())
    print("Jacobian error", np.abs(J - fd).max() / np.abs(fd).max(), "allowed", allowed / np.abs(fd).max())
    assert np.abs(J - fd).max() < allowed, (J, fd, allowed)
