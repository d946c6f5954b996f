"""Mass about the deformed state (default, physical) against the undeformed one (Nastran SOL 400,
OpenSees), on the cantilever strip under self-weight (issue 23)."""

import json
from pathlib import Path

import numpy as np
import pytest

import flexgvt as fg

REF = json.loads((Path(__file__).parents[1] / "data" / "mass_frame" / "strip_ratios.json").read_text())


@pytest.fixture(scope="module")
def strip():
    case = fg.cases.cantilever_strip()
    loaded = fg.solve_static(case.model, case.configurations["self_weight"])
    unloaded = fg.solve_static(case.model, case.configurations["unloaded"])
    return loaded, unloaded


def test_undeformed_mass_reproduces_nastran_sol400(strip):
    loaded, _ = strip
    f = fg.solve_modes(loaded, 15, mass_frame="undeformed").frequencies_hz
    for mode, ref in REF["nastran_sol400_minus_1g_hz"].items():
        assert f[int(mode) - 1] == pytest.approx(ref, rel=3e-3), mode  # measured: within 0.1 %


def test_default_ratios_follow_the_continuum(strip):
    """f(-1 g) / f(unloaded) of the modes growing from 1 T and 2 IP, within 1 % of CalculiX shells;
    the undeformed-mass convention misses them by 1.7-2.2 %."""
    loaded, unloaded = strip
    f0 = fg.solve_modes(unloaded, 15)
    deformed = fg.solve_modes(loaded, 15)
    undeformed = fg.solve_modes(loaded, 15, mass_frame="undeformed")
    for mode, origin, key in ((7, "1 T", "7 (from 1 T)"), (9, "2 IP", "9 (from 2 IP)")):
        base = f0.frequencies_hz[f0.labels.index(origin)]
        ref = REF["calculix_s8r_ratio"][key]
        assert deformed.frequencies_hz[mode - 1] / base == pytest.approx(ref, rel=0.01)
        assert abs(undeformed.frequencies_hz[mode - 1] / base / ref - 1) > 0.015


def test_both_frames_agree_without_deformation(strip):
    _, unloaded = strip
    a = fg.solve_modes(unloaded, 10).frequencies_hz
    b = fg.solve_modes(unloaded, 10, mass_frame="undeformed").frequencies_hz
    np.testing.assert_allclose(a, b, rtol=1e-9)  # the same matrices; ARPACK round-off
    with pytest.raises(fg.errors.ModelError, match="mass_frame"):
        fg.solve_modes(unloaded, 4, mass_frame="initial")


def test_the_command_line_takes_the_mass_frame(tmp_path):
    from typer.testing import CliRunner
    from flexgvt.cli.main import app
    out = tmp_path / "r.json"
    r = CliRunner().invoke(app, ["solve", "cantilever_strip", "-c", "self_weight", "--modes", "9", "--mass-frame",
                                 "undeformed", "--json", str(out)])
    assert r.exit_code == 0, r.output
    f = json.loads(out.read_text())["configurations"]["self_weight"]["frequencies_hz"]
    assert f[8] == pytest.approx(120.22, rel=3e-3)


def test_calculix_shells_give_the_same_ratios_where_ccx_is_installed():
    """The continuum reference rebuilt live (bench/calculix_strip.py, coarse S8R 2 x 50): its ratios
    of modes 7 and 9 within 1 % of the converged ones in tests/data and of flexgvt's default."""
    import shutil
    import sys
    if shutil.which("ccx") is None:
        pytest.skip("CalculiX (ccx) is not installed (Debian: apt-get install calculix-ccx); the stored reference "
                    "ratios are still checked by test_default_ratios_follow_the_continuum")
    sys.path.insert(0, str(Path(__file__).parents[2] / "bench"))
    from calculix_strip import run
    shells = run(2, 50, 15)["ratios"]
    case = fg.cases.cantilever_strip()
    f0 = fg.solve_modes(fg.solve_static(case.model, case.configurations["unloaded"]), 15)
    f1 = fg.solve_modes(fg.solve_static(case.model, case.configurations["self_weight"]), 15)
    for mode, origin, key in ((7, "1 T", "7 (from 1 T)"), (9, "2 IP", "9 (from 2 IP)")):
        live = shells[mode]["ratio"]
        assert live == pytest.approx(REF["calculix_s8r_ratio"][key], rel=0.01)
        assert f1.frequencies_hz[mode - 1] / f0.frequencies_hz[f0.labels.index(origin)] == pytest.approx(live, rel=0.01)


def test_a_plate_strip_section_brackets_mode_3():
    """Flatwise stiffness E I / (1 - nu^2) (the plate-strip limit of a section stiffening with
    curvature): the continuum's coupled mode 3 lies between the beam and plate-strip ratios, while
    mode 13 moves away from it (so no such section fits both; docs/solver.md)."""
    case = fg.cases.cantilever_strip()
    p = case.model.beams[0].section.properties()
    out = {}
    for name, factor in (("beam", 1.0), ("plate", 1 / (1 - 0.33**2))):
        m = fg.Model(name)
        ids = m.add_nodes(np.c_[np.zeros(151), np.linspace(0, 1.5, 151), np.zeros(151)])
        m.add_beams(np.c_[ids[:-1], ids[1:]], fg.Material("Al", E=70e9, nu=0.33, rho=2700),
                    fg.GeneralSection(A=p["A"], Iy=p["Iy"] * factor, Iz=p["Iz"], J=p["J"], Ip=p["Ip"], Ay=p["Ay"],
                                      Az=p["Az"]), orientation=(0, 0, 1), rotary_inertia=False)
        clamp = fg.Configuration("unloaded", fixed={int(ids[0]): "123456"})
        f0 = fg.solve_modes(fg.solve_static(m, clamp), 15)
        f1 = fg.solve_modes(fg.solve_static(m, clamp.with_(gravity=1.0)), 13)
        out[name] = {mode: f1.frequencies_hz[mode - 1] / f0.frequencies_hz[f0.labels.index(origin)]
                     for mode, origin in ((3, "1 IP"), (13, "2 T"))}
    ref3, ref13 = REF["calculix_s8r_ratio"]["3 (from 1 IP)"], REF["calculix_s8r_ratio"]["13 (from 2 T)"]
    assert out["beam"][3] < ref3 < out["plate"][3]
    assert abs(out["plate"][13] / ref13 - 1) > 3 * abs(out["beam"][13] / ref13 - 1)
