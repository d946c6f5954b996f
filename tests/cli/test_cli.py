"""The command line as a user runs it."""

import json
from pathlib import Path

from typer.testing import CliRunner

from flexgvt.cli.main import app

runner = CliRunner()


def test_solve_builtin_case_writes_documented_json(tmp_path):
    out = tmp_path / "r.json"
    result = runner.invoke(app, ["solve", "cantilever_strip", "-c", "unloaded", "-c", "self_weight", "--modes", "4",
                                 "--json", str(out), "--out", str(tmp_path / "fig")])
    assert result.exit_code == 0, result.output
    data = json.loads(out.read_text())
    assert data["case"] == "cantilever_strip"
    cfg = data["configurations"]
    assert set(cfg) == {"unloaded", "self_weight"}
    for rec in cfg.values():
        assert set(rec) == {"load_factor", "max_displacement_m", "frequencies_hz", "damping_ratio", "labels", "mass_kg",
                            "cg_m", "timings_s", "cautions"}
        assert rec["cautions"] == []  # the built-in strip is sound
    assert abs(cfg["unloaded"]["frequencies_hz"][0] - 1.0967) < 1e-3
    assert 0.25 < cfg["self_weight"]["max_displacement_m"] < 0.35
    assert (tmp_path / "fig" / "static_shape.png").stat().st_size > 10_000


def test_unknown_case_and_configuration_give_a_clear_error():
    result = runner.invoke(app, ["solve", "no_such_case"])
    assert result.exit_code == 2 and "no built-in case 'no_such_case'" in result.output
    result = runner.invoke(app, ["solve", "hale_wing", "-c", "cruise"])
    assert result.exit_code == 2 and "no configuration ['cruise']" in result.output


def test_demo_predicts_the_as_built_aircraft_and_its_report_renders(tmp_path):
    """`make demo`: synthetic GVT of the as-built X-HALE-like airframe in two layouts -> PolyMAX ->
    30-variable updating on both -> suspension removed. The first 7 free-free elastic modes of the
    as-built truth are predicted within 2 %, the updated model beats the initial one in every
    configuration, the updated deck reads back, the report renders in Chromium."""
    import flexgvt as fg
    from flexgvt.report.browser import check_page, chromium

    result = runner.invoke(app, ["demo", "--out", str(tmp_path / "demo"), "--json", str(tmp_path / "demo.json")])
    assert result.exit_code == 0, result.output
    data = json.loads((tmp_path / "demo.json").read_text())
    rows = data["free_free"]["updated"]
    # A mode of a close cluster (the 3 OOP / 1 T pair, 0.9 % apart) is judged by the span of its
    # cluster's predicted modes, an isolated one by its own MAC.
    assert len(rows) == 7 and all(abs(r["error_percent"]) < 2.0 for r in rows)
    assert all((r["mac"] if r["subspace_mac"] is None else r["subspace_mac"]) > 0.95 for r in rows)
    assert sum(r["subspace_mac"] is not None for r in rows) == 2
    assert data["max_abs_error_percent"]["updated"] < data["max_abs_error_percent"]["initial"]
    for name, c in data["configurations"].items():
        assert c["updated_rms_error_percent"] < c["initial_rms_error_percent"], name
    for name, by_model in data["bungees"].items():
        assert all(abs(r["error_percent"]) < 2.0 for r in by_model["updated"]), name
    assert "free-free prediction of the updated model" in result.output
    # The updated deck gives the updated model's free-free frequencies.
    deck = fg.io.read_bdf(data["files"]["bdf"])
    modes = fg.solve_modes(fg.solve_static(deck.model, next(iter(deck.configurations.values()))), 16)
    predicted = [r["predicted_hz"] for r in rows]
    elastic = modes.frequencies_hz[modes.frequencies_hz > 0]
    assert all(min(abs(elastic / f - 1)) < 1e-4 for f in predicted)
    if chromium() is not None:
        check = check_page(Path(data["files"]["report"]), tmp_path / "chromium")
        assert check.errors == [] and check.undrawn == [] and len(check.plots) >= 10


def test_solve_a_real_nastran_deck_matches_nastran_eigenvalues(tmp_path):
    """pyNastran's beam_modes deck: Simcenter Nastran's first bending pair is 456.6603 Hz and its first
    torsion mode 3554.923 Hz (with Nastran's CBAR lumped mass, which has no torsional inertia)."""
    from pathlib import Path

    deck = Path(__file__).parents[1] / "data" / "bdf" / "beam_modes" / "beam_modes.dat"
    out = tmp_path / "r.json"
    result = runner.invoke(app, ["solve", str(deck), "--units", "in-lbf-s", "--modes", "5",
                                 "--json", str(out)])
    assert result.exit_code == 0, result.output
    f = next(iter(json.loads(out.read_text())["configurations"].values()))["frequencies_hz"]
    assert abs(f[0] / 456.6603 - 1) < 1e-5 and abs(f[4] / 3554.923 - 1) < 1e-5


def test_solve_a_deck_honours_its_eigr_method(tmp_path):
    """pt145's EIGR (GIV, ND = 6, NORM = MAX): six modes, Nastran's first one (39.9615 Hz), shapes with
    largest component 1, without --modes."""
    from pathlib import Path

    deck = Path(__file__).parents[1] / "data" / "bdf" / "pynastran" / "pt145.bdf"
    out = tmp_path / "r.json"
    result = runner.invoke(app, ["solve", str(deck), "--json", str(out)])
    assert result.exit_code == 0, result.output
    f = next(iter(json.loads(out.read_text())["configurations"].values()))["frequencies_hz"]
    assert len(f) == 6 and abs(f[0] / 39.9615 - 1) < 1e-5


def test_solve_reads_a_deck_in_units_by_their_usual_names(tmp_path):
    deck = tmp_path / "beam.bdf"
    deck.write_text("SOL 103\nCEND\nSPC = 1\nBEGIN BULK\nGRID,1,,0.,0.,0.\nGRID,2,,1000.,0.,0.\n"
                    "CBAR,10,1,1,2,0.,0.,1.\nPBAR,1,1,100.,1.e4,2.e4,1.e4\nMAT1,1,7.e4,,0.3,2.7e-9\n"
                    "CONM2,20,2,,1.e-3\nSPC1,1,123456,1\nENDDATA\n")
    found = {}
    for units in ("mm-N-t-s", "mm-t-s"):
        result = runner.invoke(app, ["solve", str(deck), "--units", units, "--modes", "2",
                                     "--json", str(tmp_path / f"{units}.json")])
        assert result.exit_code == 0, result.output
        found[units] = json.loads((tmp_path / f"{units}.json").read_text())
    a, b = found["mm-t-s"]["configurations"], found["mm-N-t-s"]["configurations"]
    assert a.keys() == b.keys() and all(a[k]["frequencies_hz"] == b[k]["frequencies_hz"] for k in a)
    assert all(f > 0 for k in a for f in a[k]["frequencies_hz"])
    result = runner.invoke(app, ["solve", str(deck), "--units", "mm-kg-fortnight"])
    assert result.exit_code == 2 and "--units" in result.output and "mm-t-s" in result.output


def test_solve_takes_the_buckling_setting(tmp_path):
    """`flexgvt solve --buckling`: an unknown choice is refused with the choices named; 'stop' reaches
    the static solve (a case that does not lose stability solves as before)."""
    bad = runner.invoke(app, ["solve", "cantilever_strip", "-c", "unloaded", "--buckling", "sideways"])
    assert bad.exit_code != 0 and "must be one of" in bad.output and "continue" in bad.output
    out = tmp_path / "r.json"
    ok = runner.invoke(app, ["solve", "cantilever_strip", "--buckling", "stop", "--modes", "3", "--json", str(out)])
    assert ok.exit_code == 0, ok.output
    assert all(len(c["frequencies_hz"]) == 3 for c in json.loads(out.read_text())["configurations"].values())
