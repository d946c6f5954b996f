"""Tapered PBEAM/PBEAML (end B different from end A): read as TaperedSection with Nastran's CBEAM
rule, checked on the glider deck fmondsp.dat against MSC Nastran's printed modes and grid point
weight generator; NSM and NSI per end; intermediate stations; both writers round-trip them."""

import contextlib
import io
import json
import warnings
from pathlib import Path

import numpy as np
import pytest
from nastran_helpers import assert_close, model_data, rebuild
from pyNastran.bdf.bdf import BDF

import flexgvt as fg
from flexgvt.fem.system import compile_model
from flexgvt.io.nastran import UnsupportedCardsError
from flexgvt.workflow import solve_deck

DATA = Path(__file__).parents[1] / "data" / "bdf" / "pynastran"
GLIDER = DATA / "fmondsp.dat"
F06 = np.array(json.loads((DATA / "eigenvalues_f06.json").read_text())["fmondsp.dat"]["cycles_hz"])


def read(path, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path, **options)


@pytest.fixture(scope="module")
def glider():
    return read(GLIDER)


def test_glider_tapered_pbeaml_give_every_printed_mode(glider):
    """12 of the 17 PBEAML (TUBE cabin and tail) taper. Every mode of the f06's table: the six rigid
    modes at exactly 0 Hz (SUPORT 1 123456, free-free), the 12 elastic ones within 1e-6 (measured
    3e-7; Nastran prints 7 digits). Linear properties with the flexibility integrated exactly
    instead of by 3-point Gauss: up to 1.1e-3 off."""
    tapered = {g.name for g in glider.model.beams if isinstance(g.section, fg.TaperedSection)}
    assert tapered == {f"PBEAML_{p}" for p in (1, 2, *range(8, 18))}
    result = next(iter(solve_deck(glider, n_modes=18).values()))
    f = result.modes.frequencies_hz
    assert np.all(f[:6] == 0.0) and np.all(F06[:6] == 0.0)
    np.testing.assert_allclose(f[6:], F06[6:], rtol=1e-6)


def test_glider_mass_is_nastrans_grid_point_weight_generator(glider):
    """Nastran's CBEAM lumped mass splits each element at its mass centroid (int rho A N_i dx), with
    rho Ip likewise. The f06's GRDPNT output: mass 330.4377 kg, cg (0.9990629, 0, 0.03694101) m,
    I(S) diagonal (3061.074, 532.0176, 3534.565) kg m^2 and Ixz 61.04494 (its sign convention);
    within 1e-6 (measured 3.4e-7 on the mass). Half of each element at each end would put the
    cg 0.5 mm aft (5e-4)."""
    mp = fg.mass_properties(glider.model)
    assert mp.mass == pytest.approx(330.4377, rel=1e-6)
    np.testing.assert_allclose(mp.cg, [0.9990629, 0.0, 0.03694101], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(np.diag(mp.inertia), [3061.074, 532.0176, 3534.565], rtol=1e-6)
    assert -mp.inertia[0, 2] == pytest.approx(61.04494, rel=1e-6)


def beam_deck(tmp_path, prop, name="taper.bdf", coupmass=False):
    """Two CBEAMs along x (1 m each) on property ``prop(bdf)``, clamped at grid 1, MAT1 1 (SI)."""
    bdf = BDF(debug=None)
    for i in range(3):
        bdf.add_grid(i + 1, [float(i), 0.0, 0.0])
    bdf.add_cbeam(10, 1, [1, 2], [0.0, 0.0, 1.0], None)
    bdf.add_cbeam(11, 1, [2, 3], [0.0, 0.0, 1.0], None)
    bdf.add_mat1(1, 7e10, None, 0.3, rho=2700.0)
    prop(bdf)
    bdf.add_spc1(1, "123456", [1])
    bdf.add_eigrl(1, nd=6)
    if coupmass:
        bdf.add_param("COUPMASS", [1])
    from pyNastran.bdf.case_control_deck import CaseControlDeck
    bdf.case_control_deck = CaseControlDeck(["METHOD = 1", "SPC = 1", "BEGIN BULK"], bdf.log)
    bdf.sol = 103
    bdf.executive_control_lines = ["SOL 103"]
    path = tmp_path / name
    with contextlib.redirect_stdout(io.StringIO()):
        bdf.write_bdf(str(path), enddata=True)
    return path


def tapered_pbeam(bdf, stations=(0.0, 1.0), A=(2e-3, 1e-3), nsm=(0.5, 0.1), nsi=(3e-3, 1e-3)):
    n = len(stations)
    lin = lambda a, b: [a + (b - a) * x for x in stations]  # noqa: E731
    bdf.add_pbeam(1, 1, list(stations), ["YES"] * n, list(A) if len(A) == n else lin(*A), lin(4e-7, 1e-7),
                  lin(2e-7, 5e-8), [0.0] * n, lin(3e-7, 8e-8), nsm=list(nsm) if len(nsm) == n else lin(*nsm),
                  k1=0.8, k2=0.7, nsia=nsi[0], nsib=nsi[1])


def test_tapered_pbeam_ends_nsm_and_nsi(tmp_path):
    """End A and end B of a PBEAM become the TaperedSection's ends (K1, K2 times each end's A), NSIA
    and NSIB each end's extra polar mass moment, and NSM(A) != NSM(B) the point masses
    int NSM N_i dx = L (2 NSM_A + NSM_B) / 6 and L (NSM_A + 2 NSM_B) / 6."""
    deck = read(beam_deck(tmp_path, tapered_pbeam))
    (group,) = deck.model.beams
    a, b = group.section.end_properties()
    assert (a["A"], a["Iz"], a["Iy"], a["J"]) == pytest.approx((2e-3, 4e-7, 2e-7, 3e-7))
    assert (b["A"], b["Iz"], b["Iy"], b["J"]) == pytest.approx((1e-3, 1e-7, 5e-8, 8e-8))
    assert (a["Ay"], a["Az"], b["Ay"], b["Az"]) == pytest.approx((0.8 * 2e-3, 0.7 * 2e-3, 0.8e-3, 0.7e-3))
    assert a["Ip"] == pytest.approx(6e-7 + 3e-3 / 2700.0) and b["Ip"] == pytest.approx(1.5e-7 + 1e-3 / 2700.0)
    masses = {m.node: m.mass for m in deck.model.masses}
    assert masses[1] == pytest.approx((2 * 0.5 + 0.1) / 6)
    assert masses[2] == pytest.approx((0.5 + 2 * 0.1) / 6 + (2 * 0.5 + 0.1) / 6)
    assert masses[3] == pytest.approx((0.5 + 2 * 0.1) / 6)


def test_intermediate_stations_on_the_taper_are_accepted_others_refused(tmp_path):
    """flexgvt's element is linear between its ends: stations between them that lie on that line
    (blank fields, which Nastran interpolates, or consistent values) read as the two ends; any
    other is named as unsupported."""
    on_line = read(beam_deck(tmp_path, lambda bdf: tapered_pbeam(bdf, stations=(0.0, 0.3, 1.0)), "on.bdf"))
    two = read(beam_deck(tmp_path, tapered_pbeam, "two.bdf"))
    assert_close(model_data(on_line.model), model_data(two.model), rtol=1e-12)
    off = beam_deck(tmp_path, lambda bdf: tapered_pbeam(bdf, stations=(0.0, 0.3, 1.0), A=(2e-3, 1.9e-3, 1e-3)),
                    "off.bdf")
    with pytest.raises(UnsupportedCardsError, match="intermediate stations off the linear taper"):
        fg.io.read_bdf(off)
    tube = beam_deck(tmp_path, lambda bdf: bdf.add_pbeaml(1, 1, "TUBE", [0.0, 0.5, 1.0],
                                                          [[0.05, 0.04], [0.04, 0.03], [0.03, 0.02]],
                                                          so=["YES"] * 3, nsm=[0.0] * 3), "tube.bdf")
    with pytest.raises(UnsupportedCardsError, match="PBEAML .intermediate stations"):
        fg.io.read_bdf(tube)  # a tube's I is not linear in its radii


def test_pbeaml_with_two_stations_is_the_shape_at_each_end(tmp_path):
    path = beam_deck(tmp_path, lambda bdf: bdf.add_pbeaml(1, 1, "BAR", [0.0, 1.0], [[0.01, 0.05], [0.008, 0.03]],
                                                          so=["YES"] * 2, nsm=[0.2, 0.4]))
    deck = read(path)
    (group,) = deck.model.beams
    assert group.section == fg.TaperedSection(fg.RectangularSection(width=0.05, height=0.01),
                                              fg.RectangularSection(width=0.03, height=0.008))
    assert sum(m.mass for m in deck.model.masses) == pytest.approx(2 * (0.2 + 0.4) / 2)


def solve(deck, n=6):
    return next(iter(solve_deck(deck, n_modes=n).values())).modes.frequencies_hz


def test_template_writes_tapered_properties_back(tmp_path):
    """Updated values of tapered groups go back into their cards: E into the MAT1 (the PBEAML keeps its
    stations), a new TaperedSection into the PBEAM's stations; read back, the same model and modes."""
    deck = read(beam_deck(tmp_path, lambda bdf: tapered_pbeam(bdf, stations=(0.0, 0.3, 1.0)), "pbeam.bdf"))
    new = fg.TaperedSection(fg.GeneralSection(A=3e-3, Iy=3e-7, Iz=5e-7, J=4e-7, Ay=2.4e-3, Az=2.1e-3),
                            fg.GeneralSection(A=1.5e-3, Iy=9e-8, Iz=2e-7, J=1e-7, Ay=1.2e-3, Az=1.05e-3))
    updated = rebuild(deck.model, section={"PBEAM_1": new})
    again = read(fg.io.write_bdf(updated, tmp_path / "pbeam_new.bdf", template=deck))
    a, b = model_data(updated), model_data(again.model)
    for g in a["beams"] + b["beams"]:  # Ip is not a Nastran property: the deck's NSI stays
        for end in g["section"]:
            end.pop("Ip")
    assert_close(a, b, rtol=1e-10)
    glider = read(GLIDER)
    stiffer = rebuild(glider.model, material={g.name: fg.Material("al", E=7.7e10, nu=0.3, rho=2700.0)
                                              for g in glider.model.beams})
    back = read(fg.io.write_bdf(stiffer, tmp_path / "glider.bdf", template=glider))
    assert back.bdf.properties[10].type == "PBEAML" and len(back.bdf.properties[10].xxb) == 2
    np.testing.assert_allclose(solve(back, 12)[6:], np.sqrt(1.1) * F06[6:12], rtol=1e-6)


def test_compact_deck_round_trips_tapered_groups(tmp_path):
    """Tapered groups are written as CBEAM with a two-station PBEAML (both ends the same library
    shape) or PBEAM (with NSIA/NSIB for a polar mass moment other than rho (I1 + I2)), and read back
    to the same model."""
    al = fg.Material("Al", E=70e9, nu=0.33, rho=2700.0)
    model = fg.Model("tapered")
    ids = model.add_nodes(np.c_[np.linspace(0, 2, 5), np.zeros(5), np.zeros(5)])
    kw = dict(rotary_inertia=False, mass="lumped")
    model.add_beams(np.c_[ids[:2], ids[1:3]], al, fg.TaperedSection(fg.CircularTubeSection(0.05, 0.04),
                                                                    fg.CircularTubeSection(0.03, 0.025)),
                    name="tube", **kw)
    model.add_beams([[ids[2], ids[3]]], al, fg.TaperedSection(
        fg.GeneralSection(A=1e-3, Iy=2e-7, Iz=3e-7, J=1e-7, Ip=6e-7),
        fg.GeneralSection(A=5e-4, Iy=1e-7, Iz=1e-7, J=5e-8)), name="general", **kw)
    model.add_beams([[ids[3], ids[4]]], al, fg.TaperedSection(fg.RectangularSection(0.05, 0.01),
                                                              fg.RectangularSection(0.03, 0.008)),
                    orientation=(0, 1, 1), name="bar", **kw)
    cfg = fg.Configuration("clamped", fixed={1: "123456"})
    out = fg.io.write_bdf(model, tmp_path / "compact.bdf", configurations=[cfg])
    text = out.read_text()
    assert text.count("PBEAML") == 2 and text.count("PBEAM ") + text.count("PBEAM*") == 1
    again = read(out)
    assert_close(model_data(model), model_data(again.model), rtol=1e-10)
    a, b = compile_model(model).beams, compile_model(again.model).beams
    np.testing.assert_allclose(b.stiffness, a.stiffness, rtol=1e-10, atol=1e-10 * np.abs(a.stiffness).max())
    np.testing.assert_allclose(b.inertia_per_length, a.inertia_per_length, rtol=1e-10)


def test_mutated_tapered_decks_raise_only_flexgvt_errors(tmp_path):
    """The fuzzing of test_nastran_fuzz on the glider and a tapered PBEAM deck (stations, NSM, NSI)."""
    from test_nastran_fuzz import fuzz

    sources = [GLIDER, beam_deck(tmp_path, lambda bdf: tapered_pbeam(bdf, stations=(0.0, 0.3, 1.0)), "src.bdf")]
    outcomes = fuzz(sources, 150, tmp_path, seed=7)
    assert outcomes["error"] > 10 and outcomes["read"] > 10
