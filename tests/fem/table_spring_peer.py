"""The peer case for the table spring: a cantilever strip on a 6-component root spring with
force-deflection tables, loaded by a fixed-direction tip load, solved by flexgvt and by OpenSeesPy
(zeroLength with ElasticMultiLinear materials, elasticBeamColumn elements with the Corotational
transformation, lumped masses). Both sides use the same numbers below: massless Euler-Bernoulli
beams with their mass lumped at the nodes (no offsets), so the mass matrices are identical and
what is compared is the nonlinear statics and the tangent about each static state."""

import numpy as np

import flexgvt as fg
from flexgvt.model import SpringTable

L, N = 1.0, 10  # length [m], elements
E, G, RHO = 70e9, 26e9, 2700.0  # aluminium [Pa, Pa, kg/m^3]
WIDTH, HEIGHT = 0.03, 0.005  # width along local y, thickness along z [m]
TIP_MASS = 0.1  # [kg]
J_NODE = 1e-6  # rotary inertia of every lumped mass [kg m^2] (keeps the mass matrix regular)
LOADS = (0.0, 2.0, 4.0, 6.0, 8.0, 10.0)  # tip load [N], along -z
N_MODES = 4

# Root spring tables, deflection -> force (translations [m] -> [N], rotations [rad] -> [N m]):
# hardening in every component, symmetric; ry (flatwise bending at the root) the one the load works.
_U = np.array([-0.02, -0.01, -0.005, 0.0, 0.005, 0.01, 0.02])
_T = np.array([-0.4, -0.25, -0.15, -0.08, 0.0, 0.08, 0.15, 0.25, 0.4])
# "soft": torsion (rx) and in-plane (rz) root springs soft enough that the in-plane mode is the root
# spring's; "stiff": those two 1000 times stiffer, so that mode is the beam's (see docs/solver.md).
SOFT = {
    1: (_U, 2e5 * _U * (1 + 2e4 * _U**2)),
    2: (_U, 1e5 * _U * (1 + 2e4 * _U**2)),
    3: (_U, 1e5 * _U * (1 + 2e4 * _U**2)),
    4: (_T, 50 * _T * (1 + 20 * _T**2)),
    5: (_T, 20 * _T * (1 + 100 * _T**2)),
    6: (_T, 300 * _T * (1 + 20 * _T**2)),
}
STIFF = {**SOFT, 4: (_T, 5e4 * _T * (1 + 20 * _T**2)), 6: (_T, 3e5 * _T * (1 + 20 * _T**2))}
CASES = {"soft": SOFT, "stiff": STIFF}


def section_properties() -> dict:
    return fg.RectangularSection(WIDTH, HEIGHT, shear=False).properties()


def node_masses() -> np.ndarray:
    """(N + 1,) lumped masses: half of each element's at its nodes, the tip mass at the tip [kg]."""
    m = np.full(N + 1, RHO * WIDTH * HEIGHT * L / N)
    m[[0, -1]] /= 2
    m[-1] += TIP_MASS
    return m


def flexgvt_model(case: str = "soft", smooth: bool = False) -> tuple[fg.Model, int, int]:
    """(model, root node id, tip node id) of CASES[case] (smooth: the tables' monotone cubics)."""
    model = fg.Model("table-spring peer")
    ids = model.add_nodes(np.c_[np.linspace(0, L, N + 1), np.zeros(N + 1), np.zeros(N + 1)])
    massless = fg.Material("Al massless", E=E, rho=0.0, G=G)
    model.add_beams(np.c_[ids[:-1], ids[1:]], massless, fg.RectangularSection(WIDTH, HEIGHT, shear=False),
                    rotary_inertia=False)
    for i, m in zip(ids, node_masses()):
        model.add_mass(int(i), float(m), inertia=np.eye(3) * J_NODE)
    tables = {c: SpringTable.make(x, f, smooth=smooth) for c, (x, f) in CASES[case].items()}
    model.add_spring(int(ids[0]), None, tables=tables, name="root")
    return model, int(ids[0]), int(ids[-1])


def flexgvt_results(case: str = "soft") -> dict:
    """Tip displacement (x, z) [m] and the first N_MODES frequencies [Hz] at each load of LOADS."""
    model, _, tip = flexgvt_model(case)
    tip_x, tip_z, freqs = [], [], []
    for P in LOADS:
        cfg = fg.Configuration(f"P={P}", forces=[fg.NodalLoad(tip, force=(0.0, 0.0, -P))] if P else [])
        state = fg.solve_static(model, cfg, settings=fg.StaticSettings(tolerance=1e-12))
        d = state.displacements[model.index_of([tip], "peer")[0]]
        tip_x.append(float(d[0]))
        tip_z.append(float(d[2]))
        freqs.append(fg.solve_modes(state, N_MODES, label=False, mass_frame="undeformed").frequencies_hz.tolist())
    return {"tip_x": tip_x, "tip_z": tip_z, "frequencies_hz": freqs}


def opensees_results(case: str = "soft") -> dict:
    """The same with OpenSeesPy (imported here: the tests run without it)."""
    import openseespy.opensees as ops

    p = section_properties()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1000, 0.0, 0.0, 0.0)
    ops.fix(1000, 1, 1, 1, 1, 1, 1)
    for i, (x, m) in enumerate(zip(np.linspace(0, L, N + 1), node_masses())):
        ops.node(i + 1, float(x), 0.0, 0.0)
        ops.mass(i + 1, float(m), float(m), float(m), J_NODE, J_NODE, J_NODE)
    for c, (x, f) in CASES[case].items():
        ops.uniaxialMaterial("ElasticMultiLinear", c, 0.0, "-strain", *map(float, x), "-stress", *map(float, f))
    ops.element("zeroLength", 1000, 1000, 1, "-mat", 1, 2, 3, 4, 5, 6, "-dir", 1, 2, 3, 4, 5, 6)
    ops.geomTransf("Corotational", 1, 0.0, 0.0, 1.0)  # local z along global z: Iy is the flatwise one
    for i in range(N):
        ops.element("elasticBeamColumn", i + 1, i + 1, i + 2, p["A"], E, G, p["J"], p["Iy"], p["Iz"], 1)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(N + 1, 0.0, 0.0, -LOADS[-1], 0.0, 0.0, 0.0)
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-13, 100)
    ops.algorithm("Newton")
    tip_x, tip_z, freqs = [], [], []
    level = 0.0
    for P in LOADS:
        if P > level:
            steps = 20
            ops.integrator("LoadControl", (P - level) / LOADS[-1] / steps)
            ops.analysis("Static")
            if ops.analyze(steps) != 0:
                raise RuntimeError(f"OpenSees did not converge to P = {P} N")
            level = P
        tip_x.append(ops.nodeDisp(N + 1, 1))
        tip_z.append(ops.nodeDisp(N + 1, 3))
        lam = np.array(ops.eigen("-fullGenLapack", N_MODES))
        freqs.append((np.sqrt(lam) / (2 * np.pi)).tolist())
    ops.wipe()
    return {"tip_x": tip_x, "tip_z": tip_z, "frequencies_hz": freqs}
