"""The command line as a user runs it."""

import json

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
                            "cg_m", "timings_s"}
    assert abs(cfg["unloaded"]["frequencies_hz"][0] - 1.0967) < 1e-3
    assert 0.25 < cfg["self_weight"]["max_displacement_m"] < 0.35
    assert (tmp_path / "fig" / "static_shape.png").stat().st_size > 10_000


def test_unknown_case_and_configuration_give_a_clear_error():
    result = runner.invoke(app, ["solve", "no_such_case"])
    assert result.exit_code == 2 and "no built-in case 'no_such_case'" in result.output
    result = runner.invoke(app, ["solve", "hale_wing", "-c", "cruise"])
    assert result.exit_code == 2 and "no configuration ['cruise']" in result.output


def test_demo_writes_its_figures(tmp_path):
    result = runner.invoke(app, ["demo", "--out", str(tmp_path), "--json", str(tmp_path / "demo.json")])
    assert result.exit_code == 0, result.output
    for name in ("static_shape.png", "frequency_vs_load.png", "strip_366_static_shape.png"):
        assert (tmp_path / name).exists()
    data = json.loads((tmp_path / "demo.json").read_text())
    freqs = data["tracking"]["frequencies_hz"]
    ip = data["tracking"]["labels"].index("1 IP")
    assert freqs[-1][ip] < 0.65 * freqs[0][ip]


def test_solve_a_real_nastran_deck_matches_nastran_eigenvalues(tmp_path):
    """pyNastran's beam_modes deck: Simcenter Nastran's first bending pair is 456.6603 Hz and its first
    torsion mode 3554.923 Hz (with Nastran's CBAR lumped mass, which has no torsional inertia)."""
    from pathlib import Path

    deck = Path(__file__).parents[1] / "data" / "bdf" / "beam_modes" / "beam_modes.dat"
    out = tmp_path / "r.json"
    result = runner.invoke(app, ["solve", str(deck), "--units", "in-lbf-s", "--modes", "5", "--nastran-cbar-mass",
                                 "--json", str(out)])
    assert result.exit_code == 0, result.output
    f = next(iter(json.loads(out.read_text())["configurations"].values()))["frequencies_hz"]
    assert abs(f[0] / 456.6603 - 1) < 1e-5 and abs(f[4] / 3554.923 - 1) < 1e-5
