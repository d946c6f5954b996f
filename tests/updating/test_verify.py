"""The verification protocol of docs/method.md section 4 on the cantilever strip (150 beams, 12
variables, three configurations up to 3 g), several seeds; and `flexgvt verify` as a user runs it."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.cli.main import app


@pytest.mark.parametrize("seed", [2, 3])
def test_mistuned_strip_is_recovered_in_every_configuration(seed):
    v = up.verify("cantilever", seed=seed)
    assert np.abs(v.variable_errors_percent["initial"]).max() > 2.0
    assert np.abs(v.variable_errors_percent["multi"]).max() < 0.05
    for name, rows in v.multi.tables.items():
        assert max(abs(r["initial_error_percent"]) for r in rows) > 0.5
        assert max(abs(r["updated_error_percent"]) for r in rows) < 0.01, name
        assert min(r["updated_mac"] for r in rows) > 0.9999
    # The unseen 2 g case is predicted by the multi-configuration model within 0.01 %.
    assert max(abs(e) for e in v.prediction["multi_error_percent"]) < 0.01
    assert len(v.prediction["single_error_percent"]) == len(v.prediction["reference_hz"])


def test_verify_command_writes_the_documented_json(tmp_path):
    out = tmp_path / "v.json"
    result = CliRunner().invoke(app, ["verify", "cantilever", "--seed", "1", "--json", str(out),
                                      "--out", str(tmp_path / "fig")])
    assert result.exit_code == 0, result.output
    assert "'flatwise_2g' (unseen)" in result.output
    assert "'flatwise_3g' (seen by multi only)" in result.output
    data = json.loads(out.read_text())
    assert set(data) >= {"case", "seed", "mistuning", "variable_errors_percent", "prediction", "multi", "single"}
    assert len(data["multi"]["variables"]) == 12
    # The single-configuration update's iterations too (the bench counts them).
    assert len(data["single"]["history"]) >= 2 and "objective" in data["single"]["history"][-1]
    assert set(data["multi"]["configurations"]) == {"unloaded", "self_weight", "flatwise_3g"}
    row = data["multi"]["configurations"]["flatwise_3g"][0]
    assert set(row) >= {"measured_hz", "initial_hz", "updated_hz", "initial_error_percent", "updated_error_percent",
                        "updated_mac"}
    for name in ("mac.png", "errors.png"):
        assert (tmp_path / "fig" / name).stat().st_size > 10_000
    rows = (tmp_path / "fig" / "frequencies.csv").read_text().splitlines()
    assert len(rows) == 1 + 4 * 8 and rows[-1].startswith("flatwise_2g,True,,8,")
    assert set(data["configurations"]) == {"unloaded", "self_weight", "flatwise_3g", "flatwise_2g"}
    assert data["configurations"]["self_weight"]["seen_by"] == ["multi"]
    # The static deflections (the unseen case's a prediction) and the reference's buckling onsets.
    assert "static deflections" in result.output and "buckling onset" in result.output
    (tip,) = data["prediction"]["static"]
    assert tip["component"] == 3 and abs(tip["multi_error_percent"]) < 0.01 < abs(tip["initial_error_percent"])
    static = (tmp_path / "fig" / "static.csv").read_text().splitlines()
    assert len(static) == 1 + 3 and static[-1].startswith(f"flatwise_2g,True,{tip['node']},3,")
    assert data["onsets"] == {"self_weight": None, "flatwise_3g": None, "flatwise_2g": None}
    onsets = (tmp_path / "fig" / "onsets.csv").read_text().splitlines()
    assert [r.split(",")[:2] for r in onsets[1:]] == [[n, "False"] for n in ("self_weight", "flatwise_3g",
                                                                              "flatwise_2g")]
    bad = CliRunner().invoke(app, ["verify", "fuselage"])
    assert bad.exit_code == 2 and "unknown case" in bad.output


def test_a_model_that_buckles_is_judged_on_its_post_buckled_path():
    """verify judges a model in a configuration from zero load (_predicted); where the model's path loses
    stability and the reference's did not (the wingbox whose skins all buckle at -1 g once the thin bay
    is averaged away), the primary path's unstable equilibrium must not be what is compared: the model
    is followed onto its post-buckled path, as the reference was. The narrow strip of
    tests/fem/test_buckling.py at 1.15 x its lateral-torsional critical force."""
    from flexgvt.correlation import Sensors
    from flexgvt.fem.static import StaticSettings
    from flexgvt.updating.verify import _predicted

    model = fg.Model("narrow strip")  # tests/fem/test_buckling.py's strip: P_cr 38.2 N
    ids = model.add_nodes(np.c_[np.zeros(41), np.linspace(0, 1.0, 41), np.zeros(41)])
    section = fg.RectangularSection(width=0.003, height=0.05)
    model.add_beams(np.c_[ids[:-1], ids[1:]], fg.Material("Al", E=70e9, nu=0.33, rho=2700.0), section,
                    orientation=(0, 0, 1))
    config = fg.Configuration("tip force", fixed={int(ids[0]): "123456"},
                              forces=(fg.NodalLoad(int(ids[-1]), force=(0, 0, -1.15 * 38.2)),))
    with pytest.warns(fg.errors.FlexGVTWarning, match="post-buckled path"):
        buckled = fg.solve_static(model, config, settings=StaticSettings(buckling="continue"))
    modes = fg.solve_modes(buckled, 3)
    sensors = Sensors.triaxial(list(model.node_ids[5::5]))
    shapes = np.asarray(sensors.matrix(buckled.node_ids, buckled) @ modes.matrix()).T
    meas = up.Measured("tip force", modes.frequencies_hz, shapes, sensors)
    with pytest.warns(fg.errors.FlexGVTWarning, match="post-buckled path"):
        f, _ = _predicted(model, config, meas, sensors, 3)  # config: the perfect strip, as the model has it
    assert np.all(np.isfinite(f)) and np.all(f > 0)
    np.testing.assert_allclose(f, modes.frequencies_hz, rtol=1e-6)
