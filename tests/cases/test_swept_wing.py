"""The A3TB-WT-like swept wing: geometry and mass against the published figures, the spar's laminate
stiffness against a hand CLT computation, the modes' labels, the design variables and stages."""

import math

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.cases import swept_wing
from flexgvt.cases.swept_wing_sections import laminate_beam, naca_contour, tip_load_modulus
from flexgvt.errors import ModelError
from flexgvt.model.shells import Laminate, OrthotropicMaterial, Ply


@pytest.fixture(scope="module")
def case():
    return swept_wing(n_wing=10)


@pytest.fixture(scope="module")
def modes(case):
    return fg.solve_modes(fg.solve_static(case.model, case.configurations["shaker_table"]), 10)


def test_geometry_against_the_published_description(case):
    xyz = dict(zip(case.model.node_ids.tolist(), case.model.xyz))
    spar = np.array([xyz[n] for n in case.references["spar_node_ids"]])
    tip = spar[-1]
    assert tip[1] == pytest.approx(1.5)  # half of the 3 m span
    assert math.degrees(math.atan2(tip[0], tip[1])) == pytest.approx(22.0)  # sweep back
    # Twist: the wing's last element turned -3 deg (nose down) about the spar from the wing root's.
    wing = next(g for g in case.model.beams if g.name == "spar_wing")
    z0, z1 = wing.orientation[0], wing.orientation[-1]
    axis = (spar[-1] - spar[0]) / np.linalg.norm(spar[-1] - spar[0])
    angle = math.degrees(math.atan2(np.dot(np.cross(z0, z1), axis), np.dot(z0, z1)))
    n = len(wing.orientation)
    assert angle == pytest.approx(-3.0 * (n - 1) / n, abs=1e-6)  # element mid-points: 1/(2n) to 1 - 1/(2n)
    fin_tip = xyz[case.references["fin_tip_node"]]
    assert fin_tip[2] - tip[2] == pytest.approx(case.references["properties"]["fin_height"])
    assert {g.name for g in case.model.beams} == {"spar_body", "spar_wing", "fuselage", "frame", "skin", "fin"}
    assert [s.name for s in case.model.springs] == ["root_spring"] + [f"hinge_{k}" for k in range(1, 5)]
    # 16 uniaxial accelerometers (6 stations x 2 + one per control surface) and two triaxials
    uni = [k for k in case.sensors if not k.startswith("TRI")]
    assert len(uni) == 16 and len(case.sensors) == 16 + 6


def test_mass_against_the_published_figures(case):
    mp = fg.mass_properties(case.model)
    # Half model of an 11 kg vehicle without its motors, batteries and avionics: well under 5.5 kg.
    assert 1.0 < mp.mass < 5.5
    assert 0.3 < mp.cg[1] < 1.0  # cg outboard of the centre body, inboard of mid-span
    spar_len = 1.5 / math.cos(math.radians(22.0))
    spar_mass = sum(1471.5 * 0.02 * 0.005 * np.linalg.norm(np.diff(case.model.xyz[case.model.index_of(g.nodes)],
                                                                        axis=1), axis=-1).sum()
                    for g in case.model.beams if g.name.startswith("spar"))
    assert spar_mass == pytest.approx(1471.5 * 0.02 * 0.005 * spar_len)


def _hand_qbar(E1, E2, nu12, G12, theta):
    """Textbook transformed reduced stiffnesses (Jones, Mechanics of Composite Materials, Eq. 2.85)."""
    d = 1 - nu12**2 * E2 / E1
    Q11, Q22, Q12, Q66 = E1 / d, E2 / d, nu12 * E2 / d, G12
    c, s = math.cos(math.radians(theta)), math.sin(math.radians(theta))
    q11 = Q11 * c**4 + 2 * (Q12 + 2 * Q66) * s**2 * c**2 + Q22 * s**4
    q12 = (Q11 + Q22 - 4 * Q66) * s**2 * c**2 + Q12 * (s**4 + c**4)
    q22 = Q11 * s**4 + 2 * (Q12 + 2 * Q66) * s**2 * c**2 + Q22 * c**4
    q16 = (Q11 - Q12 - 2 * Q66) * s * c**3 + (Q12 - Q22 + 2 * Q66) * s**3 * c
    q26 = (Q11 - Q12 - 2 * Q66) * s**3 * c + (Q12 - Q22 + 2 * Q66) * s * c**3
    q66 = (Q11 + Q22 - 2 * Q12 - 2 * Q66) * s**2 * c**2 + Q66 * (s**4 + c**4)
    return np.array([[q11, q12, q16], [q12, q22, q26], [q16, q26, q66]])


def test_laminate_stiffness_against_a_hand_clt_computation():
    E1, E2, nu12, G12 = 130e9, 9e9, 0.3, 5e9
    mat = OrthotropicMaterial("UD", E1=E1, E2=E2, nu12=nu12, G12=G12)
    angles, t, b = (0, 45, -45, 90, 90, -45, 45, 0), 0.625e-3, 0.02
    lb = laminate_beam(Laminate("quasi", tuple(Ply(mat, t, a) for a in angles)), b)
    h = t * len(angles)
    z = -h / 2 + t * np.arange(len(angles) + 1)
    A = sum(_hand_qbar(E1, E2, nu12, G12, a) * (z[k + 1] - z[k]) for k, a in enumerate(angles))
    D = sum(_hand_qbar(E1, E2, nu12, G12, a) * (z[k + 1] ** 3 - z[k] ** 3) / 3 for k, a in enumerate(angles))
    assert lb.EA == pytest.approx(b / np.linalg.inv(A)[0, 0], rel=1e-12)
    assert lb.EI_flat == pytest.approx(b / np.linalg.inv(D)[0, 0], rel=1e-12)
    assert lb.EI_edge == pytest.approx(b**3 / 12 / np.linalg.inv(A)[0, 0], rel=1e-12)
    assert lb.G == pytest.approx(1 / (h * np.linalg.inv(A)[2, 2]), rel=1e-12)
    # Quasi-isotropic membrane: E = 8 U1 (U1 - U4) ... in closed form the invariant modulus
    Q = _hand_qbar(E1, E2, nu12, G12, 0)
    U1 = (3 * Q[0, 0] + 3 * Q[1, 1] + 2 * Q[0, 1] + 4 * Q[2, 2]) / 8
    U4 = (Q[0, 0] + Q[1, 1] + 6 * Q[0, 1] - 4 * Q[2, 2]) / 8
    assert lb.E == pytest.approx((U1**2 - U4**2) / U1, rel=1e-9)
    # An unsymmetric stack is refused (the narrow-beam reduction needs B = 0).
    with pytest.raises(ModelError, match="not symmetric"):
        laminate_beam(Laminate("unsym", (Ply(mat, t, 0), Ply(mat, t, 90))), b)


def test_case_spar_is_the_woven_laminate(case):
    """All plies woven 0/90 (E1 = E2): the beam's E is the ply modulus and G is G12, so Table 5.7's
    'E_1 or E_2' and 'G_12' variables scale the beam's E and G exactly; EI = E b h^3 / 12."""
    lb = case.references["spar_beam"]
    assert lb.E == pytest.approx(45e9, rel=1e-12) and lb.E_flat == pytest.approx(45e9, rel=1e-12)
    assert lb.G == pytest.approx(2.01e9, rel=1e-12)
    assert lb.EI_flat == pytest.approx(45e9 * 0.02 * 0.005**3 / 12, rel=1e-12)
    # Eq. 5.2 recovers the modulus from a tip-load test on the spar alone (F L^3 / (3 delta I)).
    L, F, I = 1.0, 2.0, 0.02 * 0.005**3 / 12
    assert tip_load_modulus(F, F * L**3 / (3 * lb.EI_flat), L, I) == pytest.approx(45e9)
    with pytest.raises(ModelError):
        tip_load_modulus(F, 0.0, L, I)


def test_contour_properties():
    """A thin NACA 0012 wall (closed trailing edge): the enclosed area is the thickness polynomial's
    integral, 10 t (0.2969 (2/3) - 0.126/2 - 0.3516/3 + 0.2843/4 - 0.1036/5) c^2; perimeter about 2.04 c."""
    c = naca_contour(1.0, 0.12, 1e-4, 0.0)
    area = 1.2 * (0.2969 * 2 / 3 - 0.126 / 2 - 0.3516 / 3 + 0.2843 / 4 - 0.1036 / 5)
    assert c.enclosed == pytest.approx(area, rel=1e-4) and c.perimeter == pytest.approx(2.04, rel=5e-3)
    assert c.J == pytest.approx(4 * c.enclosed**2 * 1e-4 / c.perimeter)


def test_modes_and_labels(case, modes):
    """The first five modes are of the published kinds: OOP 1, IP 1 (governed by the root spring's
    M_z, so flexgvt labels it RB), T 1, OOP 2, and an OOP mode near 30-35 Hz."""
    labels = list(modes.labels)
    f = modes.frequencies_hz
    assert labels[0] == "1 OOP" and 2.0 < f[0] < 3.2
    assert labels[1].startswith("RB") and modes.energy_fractions[1, 1] > 0.1  # in-plane share of its strain energy
    assert labels[2].startswith("1 T") and labels[3].startswith("2 OOP")
    assert any("OOP" in lab and 28 < fk < 40 for lab, fk in zip(labels, f))
    assert case.references["published"]["shaker_table"]["labels"] == ["OOP 1", "IP 1", "T 1", "OOP 2", "OOP 3"]
    assert case.references["published"]["wind_tunnel"]["measured_hz"] == [2.62, 7.1, 12.0, 15.1, 35.5]


def test_no_control_surface_mode_in_the_measured_band(case, modes):
    """The hinge springs (20 N m/rad) keep every control-surface mode out of the band the GVT listed
    (Table 5.2: none to 53.5 Hz, with an accelerometer on each surface): below 60 Hz the hinges hold
    less than a fifth of any mode's energy; at 5 N m/rad four modes of 39-54 Hz were mostly the
    surfaces', and the third bending and second torsion mixed with them. The third bending ('3 OOP')
    then comes below the second torsion, as in the original work's FE model (Table 5.1)."""
    idx = {n: i for i, n in enumerate(modes.node_ids.tolist())}
    hinges = [s for s in case.model.springs if s.name.startswith("hinge_")]
    assert len(hinges) == 4 and all(s.stiffness[3] == 20.0 for s in hinges)
    omega2 = (2 * np.pi * modes.frequencies_hz) ** 2
    energy = sum(0.5 * s.stiffness[3] * ((modes.shapes[:, idx[s.node_b], 3:] - modes.shapes[:, idx[s.node_a], 3:])
                                         @ s.frame[:, 0]) ** 2 for s in hinges)
    share = energy / (0.5 * omega2)  # mass-normalised shapes: the mode's potential energy is omega^2 / 2
    band = modes.frequencies_hz < 60.0
    assert band.sum() >= 6 and share[band].max() < 0.2
    labels = list(modes.labels)
    third = next(k for k, lab in enumerate(labels) if lab.startswith("3 OOP"))
    assert 30 < modes.frequencies_hz[third] < 36 and labels[third + 1].startswith("2 T")
    weak = swept_wing(n_wing=10, properties={"hinge_stiffness": 5.0})
    m5 = fg.solve_modes(fg.solve_static(weak.model, weak.configurations["shaker_table"]), 10)
    assert not any(lab.startswith("3 OOP") for lab, f in zip(m5.labels, m5.frequencies_hz) if f < 40)


def test_tip_shaker_lowers_the_modes(case, modes):
    m2 = fg.solve_modes(fg.solve_static(case.model, case.configurations["tip_shaker"]), 4)
    assert m2.frequencies_hz[0] < modes.frequencies_hz[0]


def test_design_variables_and_stages(case):
    v = fg.updating.case_variables(case)
    assert len(v) == 15 and [x.name for x in v][-6:] == ["K_x", "K_y", "K_z", "M_x", "M_y", "M_z"]
    bounds = {x.name: x.bounds for x in v}
    assert bounds["E_skin"] == (0.5, 5.0) and bounds["M_x"] == (0.75, 2.0) and bounds["rho_fin"] == (0.95, 1.05)
    fg.updating.Parametrisation(case.model, list(case.configurations.values()), v)  # every variable binds
    stages = case.references["stages"]
    assert [s["name"] for s in stages] == ["component_tests", "root_spring_adjustment", "shaker_table", "wind_tunnel"]
    adjust, stage1, stage2 = stages[1:]
    # Section 5.4.2: M_z alone on Table 5.2's skin-on shaker-table first in-plane mode
    assert adjust["variables"] == ["M_z"] and adjust["measured_hz"] == [7.10] and adjust["labels"] == ["IP 1/RB"]
    assert len(stage1["variables"]) == 15 and stage2["variables"] == ["K_x", "K_y", "K_z", "M_x", "M_y", "M_z"]
    assert stage1["bounds"]["E_skin"] == (0.5, 5.0) and stage2["bounds"]["M_z"] == (0.25, 4.0)
    assert stage1["measured_hz"] == [2.49, 7.15, 11.78, 14.83, 33.03]
    # The root-spring IP mode pairs by 'IP 1/RB'; the tables print the published 'IP 1'.
    assert stage1["labels"][1] == "IP 1/RB" and stage1["printed_labels"][1] == "IP 1"
    assert fg.cases.get("swept_wing", n_wing=4).name == "swept_wing"
    with pytest.raises(ModelError, match="unknown properties"):
        swept_wing(properties={"chord_m": 0.3})


def test_hardening_root_spring_stiffens_with_the_tip_load_and_the_modes_follow():
    """The root spring's moment-rotation table (tangent doubling at 0.02 rad): at zero load the modes
    are the linear spring's; under a 30 N tip load the root's tangent is the law's at the static
    rotation and the first bending rises well above what the geometry alone gives it."""
    out = {}
    for hardening in (None, 0.02):
        case = fg.cases.swept_wing(n_wing=8, n_body=2, n_fin=2, root_hardening=hardening, tip_load=30.0)
        tracking = fg.modes_versus_load(case.model, case.configurations["tip_load"], [0.0, 1.0], n_modes=3)
        out[hardening] = (case, tracking)
    (_, linear), (case, hard) = out[None], out[0.02]
    np.testing.assert_allclose(hard.frequencies_hz[0], linear.frequencies_hz[0], rtol=1e-9)
    clamp = case.model.index_of([case.references["clamp_node"]], "test")[0]
    rx = hard.modes[-1].state.displacements[clamp, 3]
    spring = case.model.springs[[s.name for s in case.model.springs].index("root_spring")]
    tangent = spring.table_scale[3] * spring.tables[3].evaluate(rx)[1]
    assert tangent == pytest.approx(1e3 * (1 + rx**2 / 0.02**2), rel=5e-3)
    assert 0.02 < abs(rx) < 0.04
    j = hard.labels.index("1 OOP")
    rise_hard = hard.frequencies_hz[1, j] / hard.frequencies_hz[0, j] - 1
    rise_linear = linear.frequencies_hz[1, j] / linear.frequencies_hz[0, j] - 1
    assert rise_hard > 2 * rise_linear > 0


def _origin_inertia(mp):
    """Inertia tensor about the origin [kg m^2] from mass properties about the cg."""
    c = mp.cg
    return mp.inertia + mp.mass * (c @ c * np.eye(3) - np.outer(c, c))


def test_part_offsets_move_the_mass_exactly_as_the_centroids_say(monkeypatch):
    """Each part on its own centroid line (part_offsets, the default) against the stick model on the
    spar line (part_offsets=False), untwisted so the lines are straight: the same mass to 1e-12; the
    first moment moved by each part's mass times its centroid's offset; the inertia about the origin
    changed by exactly a line mass's shift, with the torsional inertia about the spar unchanged
    (Ip about its own centroid + A d^2 = the old Ip about the spar)."""
    import sys

    module = sys.modules["flexgvt.cases.swept_wing"]
    monkeypatch.setattr(module, "TWIST_DEG", 0.0)
    kw = dict(n_wing=6, n_body=2, n_fin=2)
    old, new = swept_wing(part_offsets=False, **kw), swept_wing(**kw)
    mp_old, mp_new = fg.mass_properties(old.model), fg.mass_properties(new.model)
    assert mp_new.mass == pytest.approx(mp_old.mass, rel=1e-12)
    sweep = math.radians(22.0)
    aft = np.array([math.cos(sweep), -math.sin(sweep), 0.0])  # chordwise in the section normal to the spar
    d = new.references["part_centroids"]
    shift = {"frame": d["frame"] * aft, "skin": d["skin"] * aft, "fuselage": d["fuselage"] * aft,
             "fin": np.array([d["fin"], 0.0, 0.0])}
    moment, inertia = np.zeros(3), np.zeros((3, 3))
    for g in old.model.beams:
        if g.name not in shift:
            continue
        ends = old.model.xyz[old.model.index_of(g.nodes)]
        delta = shift[g.name]
        for p0, p1 in ends:
            m = g.material.rho * g.section.A * np.linalg.norm(p1 - p0)
            r, a = 0.5 * (p0 + p1), (p1 - p0) / np.linalg.norm(p1 - p0)
            moment += m * delta
            inertia += m * ((2 * r @ delta + delta @ delta) * np.eye(3) - np.outer(r, delta) - np.outer(delta, r)
                            - np.outer(delta, delta) - delta @ delta * np.outer(a, a))
    np.testing.assert_allclose(mp_new.mass * mp_new.cg - mp_old.mass * mp_old.cg, moment, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(_origin_inertia(mp_new) - _origin_inertia(mp_old), inertia, rtol=1e-9, atol=1e-13)
    # The centroids: the frame's (wall, rear-spar web, ribs at their plate centroid) and the film's aft of the spar.
    assert 0.02 < d["frame"] < 0.04 and 0.04 < d["skin"] < 0.07 and (mp_new.cg - mp_old.cg) @ aft > 0.01


def test_part_offsets_couple_bending_and_torsion():
    """With the parts' mass at their centroids, aft of the spar, the bending modes twist nose down
    as the wing bends up (the inertia aft of the spar lags): tip twist x chord / tip deflection goes
    from -0.040 to -0.059 in the first bending and from -1.3 to -3.0 in the second. part_offsets=False
    reproduces the stick model's modes (with the hinge springs of the time, 5 N m/rad)."""
    out = {}
    for offsets in (False, True):
        c = swept_wing(n_wing=6, n_body=2, n_fin=2, part_offsets=offsets, properties={"hinge_stiffness": 5.0})
        m = fg.solve_modes(fg.solve_static(c.model, c.configurations["shaker_table"]), 4)
        tip = m.shapes[:, list(m.node_ids).index(c.references["tip_node"])]
        axis = np.array([math.sin(math.radians(22.0)), math.cos(math.radians(22.0)), 0.0])
        out[offsets] = ((tip[:, 3:] @ axis) * 0.30 / tip[:, 2], m)
        assert list(m.labels[:4]) == ["1 OOP", "RB pitch", "1 T", "2 OOP"]
    (old, m_old), (new, _) = out[False], out[True]
    assert new[0] - old[0] < -0.01 and new[3] / old[3] > 2.0
    np.testing.assert_allclose(m_old.frequencies_hz, [2.51773405, 8.21857213, 11.12794162, 14.79376418],
                               rtol=1e-8)  # the stick model before part_offsets


def test_root_spring_axes():
    """The root spring's axes (not published): streamwise by default (x aft, y outboard, z up);
    root_axes='spar' turns x and y with the sweep (y along the spar), so M_y is then the spar's
    torsion; anything else is refused."""
    root = {}
    for axes in ("streamwise", "spar"):
        c = swept_wing(n_wing=4, n_body=2, n_fin=2, properties={"root_axes": axes})
        root[axes] = next(s for s in c.model.springs if s.name == "root_spring").frame
    np.testing.assert_allclose(root["streamwise"], np.eye(3), atol=1e-15)
    sweep = math.radians(22.0)
    np.testing.assert_allclose(root["spar"][:, 1], [math.sin(sweep), math.cos(sweep), 0.0], atol=1e-15)
    with pytest.raises(ModelError, match="root_axes"):
        swept_wing(n_wing=4, n_body=2, n_fin=2, properties={"root_axes": "chord"})
