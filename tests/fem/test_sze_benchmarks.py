"""The geometrically nonlinear shell benchmarks of Sze, Liu & Lo, "Popular benchmark problems for
geometric nonlinear analysis of shells", Finite Elements in Analysis and Design 40 (2004) 1551-1569,
through solve_static: whole load-deflection paths against the paper's tabulated ABAQUS S4R
reference solutions (sections 3.3-3.6).

The tables are transcribed from MBDyn's tests/plates/sze2004/sze3*/sze3*_ref.dat (GPL test data
quoting the paper, section by section) and, for the hemisphere, Elmer's
fem/tests/Shell_OpenHemisphere*/ (quoting the paper); the paper's own pages were not in reach to
check the transcriptions digit by digit. The cantilever end-shear and roll-up cases are in
test_shell_corotational and test_shell_family. bench/sze_benchmarks.py runs every case at the
paper's meshes with every tabulated level (docs/shells.md, "Nonlinear benchmarks").
"""

import numpy as np

import flexgvt as fg
from flexgvt.fem.static import StaticSettings
from flexgvt.model import Material
from flexgvt.model.configuration import NodalLoad

# Section 3.3, slit annular plate: P/Pmax, W_A (inner radius), W_B (outer radius); S4R 10 x 80.
SLIT = np.array([
    [0.025, 1.305, 1.789], [0.05, 2.455, 3.370], [0.075, 3.435, 4.720], [0.10, 4.277, 5.876],
    [0.125, 5.007, 6.872], [0.15, 5.649, 7.736], [0.20, 6.725, 9.160], [0.25, 7.602, 10.288],
    [0.30, 8.340, 11.213], [0.35, 8.974, 11.992], [0.40, 9.529, 12.661], [0.45, 10.023, 13.247],
    [0.50, 10.468, 13.768], [0.55, 10.876, 14.240], [0.60, 11.257, 14.674], [0.65, 11.620, 15.081],
    [0.70, 11.970, 15.469], [0.75, 12.310, 15.842], [0.80, 12.642, 16.202], [0.85, 12.966, 16.550],
    [0.90, 13.282, 16.886], [0.95, 13.590, 17.212], [1.00, 13.891, 17.528]])
# Section 3.4, hemisphere with an 18 deg hole: P/Pmax, outward U at the pulled point, inward at the
# pushed one; S4R 16 x 16 on a quarter.
HEMISPHERE = np.array([
    [0.05, 0.855, 0.955], [0.10, 1.499, 1.840], [0.15, 1.969, 2.604], [0.20, 2.321, 3.261],
    [0.25, 2.596, 3.833], [0.30, 2.819, 4.339], [0.35, 3.002, 4.790], [0.40, 3.158, 5.196],
    [0.45, 3.291, 5.565], [0.50, 3.406, 5.902], [0.55, 3.508, 6.212], [0.60, 3.598, 6.497],
    [0.65, 3.678, 6.761], [0.70, 3.750, 7.006], [0.75, 3.816, 7.234], [0.80, 3.875, 7.448],
    [0.85, 3.929, 7.647], [0.90, 3.979, 7.835], [0.95, 4.025, 8.011], [1.00, 4.067, 8.178]])
# Section 3.5, pull-out of an open-ended cylinder: P/Pmax, W_A (load point, outward), -U_B (mid-length
# at 90 deg, inward), -U_C (free end at 90 deg, inward); S4R 24 x 36 on an eighth.
PULLOUT = np.array([
    [0.025, 0.819, 0.864, 0.872], [0.05, 1.260, 1.471, 1.493], [0.075, 1.527, 1.901, 1.946],
    [0.10, 1.707, 2.217, 2.293], [0.15, 1.936, 2.641, 2.792], [0.20, 2.079, 2.904, 3.106],
    [0.25, 2.180, 3.087, 3.310], [0.30, 2.257, 3.227, 3.452], [0.35, 2.321, 3.342, 3.556],
    [0.40, 2.376, 3.443, 3.632], [0.45, 2.425, 3.539, 3.688], [0.50, 2.473, 3.653, 3.718],
    [0.525, 2.543, 4.061, 3.580], [0.55, 2.577, 4.171, 3.518], [0.60, 2.618, 4.274, 3.452],
    [0.65, 2.648, 4.338, 3.410], [0.70, 2.672, 4.385, 3.378], [0.75, 2.692, 4.423, 3.353],
    [0.80, 2.710, 4.455, 3.332], [0.85, 2.726, 4.483, 3.313], [0.90, 2.741, 4.508, 3.297],
    [0.95, 2.755, 4.530, 3.283], [1.00, 2.768, 4.551, 3.269]])
# Section 3.6, pinched cylinder on rigid diaphragms: P/Pmax, -W_A (load point, inward), U_B (mid-length
# at 90 deg, radial); S4R 48 x 48 on an eighth. The snap-through lies between 0.15 and 0.175.
PINCHED = np.array([
    [0.05, 9.561, -0.233], [0.075, 15.648, -0.922], [0.10, 23.164, -2.391], [0.125, 29.375, -3.872],
    [0.15, 36.208, -2.154], [0.175, 51.499, 6.792], [0.20, 56.373, 10.448], [0.25, 61.877, 14.905],
    [0.30, 65.498, 17.979], [0.35, 68.229, 20.365], [0.40, 70.424, 22.321], [0.45, 72.204, 23.916],
    [0.50, 73.790, 25.381], [0.55, 75.139, 26.631], [0.60, 76.331, 27.735], [0.65, 77.472, 28.843],
    [0.70, 78.451, 29.772], [0.75, 79.339, 30.604], [0.80, 80.218, 31.471], [0.85, 81.045, 32.299],
    [0.90, 81.766, 32.989], [0.95, 82.435, 33.619], [1.00, 83.102, 34.272]])


def _grid_model(name: str, xyz: np.ndarray, ids: np.ndarray, quads: np.ndarray, E: float, nu: float,
                t: float) -> fg.Model:
    model = fg.Model(name)
    model.add_nodes(xyz, ids=ids.ravel())
    model.add_shells(quads, material=Material("m", E, 0.0, nu=nu), thickness=t)
    return model


def _fixed(pairs) -> dict[int, str]:
    """Merge (node ids, DOFs) pairs into a fixed= mapping (a corner on two symmetry planes gets both)."""
    out: dict[int, str] = {}
    for nodes, dofs in pairs:
        for n in np.atleast_1d(nodes):
            out[int(n)] = "".join(sorted(set(out.get(int(n), "") + dofs)))
    return out


def slit_annular_plate(n_r: int, n_theta: int, top: float = 1.0):
    """Section 3.3: annulus R 6 to 10, t 0.03, E 21e6, nu 0, slit along theta = 0; clamped on one side
    of the slit, a lifting line force of top x 0.8 per length on the other (consistent nodal shares).
    Returns (model, configuration, {point: node id}): A at the inner radius, B at the outer."""
    r, th = np.linspace(6.0, 10.0, n_r + 1), np.linspace(0.0, 2 * np.pi, n_theta + 1)
    R, T = np.meshgrid(r, th)
    ids = np.arange(1, R.size + 1).reshape(R.shape)
    quads = np.array([[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]]
                      for j in range(n_theta) for i in range(n_r)])
    model = _grid_model("slit annular plate", np.c_[(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel(),
                                                    np.zeros(R.size)], ids, quads, 21e6, 0.0, 0.03)
    share = np.full(n_r + 1, 4.0 / n_r)
    share[[0, -1]] *= 0.5
    forces = tuple(NodalLoad(int(ids[-1, i]), force=(0.0, 0.0, 0.8 * top * share[i])) for i in range(n_r + 1))
    config = fg.Configuration("lifting line force", fixed=_fixed([(ids[0], "123456")]), forces=forces)
    return model, config, {"A": int(ids[-1, 0]), "B": int(ids[-1, -1])}


def hemisphere(n: int, top: float = 1.0):
    """Section 3.4: R 10, t 0.04, E 6.825e7, nu 0.3, open 18 deg about the pole; a quarter (symmetry
    on x = 0 and y = 0, one node held along z) with radial forces of top x 400 on the full shell,
    alternating: out along x at A, in along y at B (a half on each symmetry plane's node)."""
    th, la = np.linspace(0, np.pi / 2, n + 1), np.linspace(0, np.radians(72.0), n + 1)
    TH, LA = np.meshgrid(th, la)
    ids = np.arange(1, TH.size + 1).reshape(TH.shape)
    quads = np.array([[ids[j, i], ids[j, i + 1], ids[j + 1, i + 1], ids[j + 1, i]] for j in range(n) for i in range(n)])
    xyz = 10.0 * np.c_[(np.cos(LA) * np.cos(TH)).ravel(), (np.cos(LA) * np.sin(TH)).ravel(), np.sin(LA).ravel()]
    model = _grid_model("hemisphere", xyz, ids, quads, 6.825e7, 0.3, 0.04)
    A, B = int(ids[0, 0]), int(ids[0, -1])
    fixed = _fixed([(ids[:, 0], "246"), (ids[:, -1], "156"), (ids[-1, 0], "3")])
    forces = (NodalLoad(A, force=(200.0 * top, 0.0, 0.0)), NodalLoad(B, force=(0.0, -200.0 * top, 0.0)))
    return model, fg.Configuration("alternating forces", fixed=fixed, forces=forces), {"A": A, "B": B}


def _cylinder_eighth(name: str, n_y: int, n_c: int, R: float, L: float, E: float, nu: float, t: float):
    """An eighth of a cylinder (axis y, 0 <= y <= L/2, 0 <= theta <= 90 deg from x towards z) with
    the symmetry conditions of the planes z = 0, x = 0 and y = L/2; returns (model, ids grid, fixed
    pairs)."""
    y, th = np.linspace(0, L / 2, n_y + 1), np.linspace(0, np.pi / 2, n_c + 1)
    TH, Y = np.meshgrid(th, y)
    ids = np.arange(1, TH.size + 1).reshape(TH.shape)
    quads = np.array([[ids[j, i], ids[j + 1, i], ids[j + 1, i + 1], ids[j, i + 1]]
                      for j in range(n_y) for i in range(n_c)])
    model = _grid_model(name, np.c_[(R * np.cos(TH)).ravel(), Y.ravel(), (R * np.sin(TH)).ravel()], ids, quads,
                        E, nu, t)
    return model, ids, [(ids[:, 0], "345"), (ids[:, -1], "156"), (ids[-1], "246")]


def pullout(n_y: int, n_c: int, top: float = 1.0):
    """Section 3.5: R 4.953, L 10.35, t 0.094, E 10.5e6, nu 0.3125, open ends; two opposite radial
    forces of top x 40,000 pull at mid-length (a quarter of one on the eighth). A: the load point,
    B: mid-length at 90 deg, C: the free end at 90 deg."""
    model, ids, sym = _cylinder_eighth("pull-out", n_y, n_c, 4.953, 10.35, 10.5e6, 0.3125, 0.094)
    A = int(ids[-1, -1])
    config = fg.Configuration("pull-out", fixed=_fixed(sym), forces=(NodalLoad(A, force=(0, 0, 1e4 * top)),))
    return model, config, {"A": A, "B": int(ids[-1, 0]), "C": int(ids[0, 0])}


def pinched_cylinder(n_y: int, n_c: int, top: float = 1.0):
    """Section 3.6: R 100, L 200, t 1, E 30e3, nu 0.3 on rigid diaphragms (ends held radially and
    tangentially); two opposite radial forces of top x 12,000 pinch at mid-length (a quarter of one
    on the eighth). A: the load point, B: mid-length at 90 deg."""
    model, ids, sym = _cylinder_eighth("pinched cylinder", n_y, n_c, 100.0, 200.0, 30e3, 0.3, 1.0)
    A = int(ids[-1, -1])
    config = fg.Configuration("pinched", fixed=_fixed(sym + [(ids[0], "13")]),
                              forces=(NodalLoad(A, force=(0, 0, -3e3 * top)),))
    return model, config, {"A": A, "B": int(ids[-1, 0])}


def measured(case: str, state, points: dict[str, int]) -> np.ndarray:
    """The tabulated quantities at each of state.steps: (n_levels, n_columns) in the table's order."""
    out = []
    for s in state.steps:
        p = {k: s.positions[state.model.index_of([v])[0]] for k, v in points.items()}
        if case == "slit":
            out.append([p["A"][2], p["B"][2]])
        elif case == "hemisphere":
            out.append([p["A"][0] - 10.0, 10.0 - p["B"][1]])
        elif case == "pullout":
            out.append([p["A"][2] - 4.953, 4.953 - p["B"][0], 4.953 - p["C"][0]])
        else:
            out.append([100.0 - p["A"][2], p["B"][0] - 100.0])
    return np.array(out)


def _errors(table: np.ndarray, got: np.ndarray) -> np.ndarray:
    """Relative errors of each column against the table (the columns' own scale for signed ones)."""
    ref = table[:, 1:]
    return (got - ref) / np.maximum(np.abs(ref), 0.02 * np.abs(ref).max(axis=0))


def _solve(model, config, levels, control="load"):
    return fg.solve_static(model, config, load_factors=levels,
                           settings=StaticSettings(buckling="ignore", control=control))


def test_slit_annular_plate_path():
    """Section 3.3 on 8 x 48 quads (the paper's 10 x 80 in bench/; 6 x 30 is 3.4 % too flexible):
    W_A and W_B at all 23 tabulated levels within 1 % (the issue asks 2 %). Measured: largest
    -0.33 % (W_A at 0.05 and 0.075); 10 x 80: -0.45 %."""
    model, config, points = slit_annular_plate(8, 48)
    state = _solve(model, config, SLIT[:, 0])
    err = _errors(SLIT, measured("slit", state, points))
    assert len(state.steps) == len(SLIT)
    assert np.abs(err).max() < 0.01, np.abs(err).max(axis=0)


def test_pullout_of_an_open_cylinder_path():
    """Section 3.5 on 16 x 24 quads (the paper's 24 x 36 in bench/): W_A, -U_B and -U_C at all 23
    tabulated levels within 2 %, except the one just past the snap between 0.5 and 0.525, where
    -U_B grows four times faster than on either side and the value depends on where exactly the
    snap falls: -U_B there within 4 %. Measured: largest -1.59 % (W_A at full load) away from the
    snap; at 0.525 W_A -1.98 %, -U_B -3.37 %, -U_C +1.92 % (24 x 36: -1.29, -2.06, +1.40 %, and
    -1.18 % at most elsewhere)."""
    model, config, points = pullout(16, 24)
    state = _solve(model, config, PULLOUT[:, 0])
    err = np.abs(_errors(PULLOUT, measured("pullout", state, points)))
    snap = np.flatnonzero(np.isclose(PULLOUT[:, 0], 0.525))
    assert np.delete(err, snap, axis=0).max() < 0.02, err.max(axis=0)
    assert err[snap].max() < 0.04, err[snap]


def test_hemisphere_path():
    """Section 3.4 on a 24 x 24 quarter (finer than the paper's 16 x 16), at every second tabulated
    level: the outward (pulled) and inward (pushed) displacements within 2 %. Measured at all 20
    levels: -0.27/-0.70 % at 0.05, +0.44/+0.39 % at 0.5, +0.84/+1.66 % at full load (12.6 s CPU).
    On the paper's 16 x 16 flexgvt's quarter is softer (+1.5/+1.3 % at 0.2, +3.7/+6.1 % at 0.45)
    and reaches a limit point near 0.49 that the S4R path does not have (docs/shells.md)."""
    levels = HEMISPHERE[1::2]
    model, config, points = hemisphere(24)
    state = _solve(model, config, levels[:, 0])
    err = _errors(levels, measured("hemisphere", state, points))
    assert np.abs(err).max() < 0.02, err


def test_pinched_cylinder_snaps_through_under_arc_length():
    """Section 3.6 on a coarse 12 x 12 eighth, to 0.3 of the paper's load, by arc-length: the path
    passes a limit point (measured at 0.240 of the load; the table rises steeply between 0.15 and
    0.175, and this coarse mesh is 9-23 % stiffer before that; on the paper's 48 x 48, in bench/,
    -W_A is within 1.5 % over the whole path and U_B within 2.3 % after the snap) and ends on the far
    side of the snap (-W_A 50.7 at 0.3, the table 65.5), and below the limit the arc-length levels
    are load stepping's equilibria (1e-6 of the deflection)."""
    model, config, points = pinched_cylinder(12, 12, 0.3)
    state = _solve(model, config, np.array([0.1, 0.3]) / 0.3, control="arc-length")
    assert state.instability is not None and state.instability.kind == "limit point"
    assert 0.15 < 0.3 * state.instability.load_factor < 0.3
    got = measured("pinched", state, points)
    assert got[1, 0] > 40.0  # snapped: the table's own value before the snap is 36.2 at 0.15
    before = _solve(*pinched_cylinder(12, 12, 0.1)[:2], np.array([1.0]))
    np.testing.assert_allclose(measured("pinched", before, points)[0], got[0], rtol=1e-6)
