"""Honest updating (issue 32): unpaired measured modes reported with their reasons, refusal when
too few pair, labels in the pairing by frequency, variables the data cannot see held at their
initial value with the reason in their rows."""

import json

import numpy as np
import pytest

import flexgvt as fg
from flexgvt import updating as up
from flexgvt.correlation import Sensors
from flexgvt.errors import FlexGVTWarning, UpdatingError
from flexgvt.workflow.schema import ProjectFile


def _shapes(case, cfg, sensors_at, n):
    state = fg.solve_static(case.model, cfg)
    modes = fg.solve_modes(state, n)
    sensors = Sensors.triaxial(sensors_at)
    return modes, np.asarray(sensors.matrix(state.node_ids, state) @ modes.matrix()).T


def test_unpaired_modes_are_reported_with_their_reasons_and_too_few_refuse_the_update():
    case = fg.cases.cantilever_strip(n_elements=30)
    unloaded, loaded = case.configurations["unloaded"], case.configurations["self_weight"]
    at = case.model.node_ids[5::5]
    modes, shapes = _shapes(case, unloaded, at, 6)
    alien = np.zeros(shapes.shape[1])
    alien[1::3] = np.linspace(1, -1, len(alien[1::3]))  # motion along the span: no FE mode looks like it
    f = np.r_[modes.frequencies_hz[:4], 30.0, 900.0]  # the last: no FE mode within a factor 2
    good = up.Measured(unloaded.name, f, np.vstack([shapes[:4], alien, shapes[0]]), Sensors.triaxial(at))
    modes2, shapes2 = _shapes(case, loaded, at, 3)
    # The test points of this configuration mapped onto the clamped root: the sensors see nothing.
    blind = up.Measured(loaded.name, modes2.frequencies_hz, shapes2,
                        Sensors.triaxial([case.references["root_node"]] * len(at)))
    variables = [up.beam("E", "*", "E")]
    with pytest.raises(UpdatingError) as err:
        up.update(case.model, [unloaded, loaded], [good, blind], variables)
    text = str(err.value)
    assert "configuration 'self_weight': 0 of 3 measured modes pair" in text and "unloaded" not in text
    assert "sensors see none" in text and "min_paired_fraction = 0" in text and "min_paired_fraction=0" in text
    with pytest.warns(FlexGVTWarning, match="measured mode\\(s\\) do not pair") as seen:
        result = up.update(case.model, [unloaded, loaded], [good, blind], variables, min_paired_fraction=0.0,
                           max_iterations=5)
    assert any("'unloaded', mode 5" in str(w.message) for w in seen)
    why = result.unpaired["initial"]
    assert [(r["mode"], r["reason"]) for r in why["unloaded"]] == [(5, "mac_below_floor"), (6, "no_mode_in_range")]
    assert why["unloaded"][0]["best_mac"] < 0.5 and why["unloaded"][0]["best_mode"] is not None
    assert [r["reason"] for r in why["self_weight"]] == ["not_seen"] * 3
    rows = result.tables["unloaded"]
    assert rows[4]["unpaired_reason"].startswith("best MAC") and rows[0]["unpaired_reason"] is None
    out = json.loads(json.dumps(result.to_dict()))  # results.json of a project run holds the same
    assert out["unpaired"]["updated"]["unloaded"][1]["reason"] == "no_mode_in_range"
    assert any("do not pair" in w for w in out["warnings"])
    assert "measured mode 6 unpaired: no FE mode within a factor 2" in result.summary()
    # The project key of the override.
    spec = ProjectFile.model_validate({"model": {"case": "xhale"}, "configurations": [{"name": "a"}],
                                       "optimiser": {"min_paired_fraction": 0}})
    assert spec.optimiser.min_paired_fraction == 0.0


def _oop_ip_strip():
    """A strip whose first in-plane mode sits 2.5 % below its third out-of-plane one (the truth),
    and an initial model 6.09 % too stiff: its '1 IP' lands 0.4 % from the measured '3 OOP',
    its own '3 OOP' 3 % away."""
    case = fg.cases.cantilever_strip(n_elements=30)
    cfg = case.configurations["unloaded"]
    modes = fg.solve_modes(fg.solve_static(case.model, cfg), 8)
    lab = list(modes.labels)
    width = 0.975 * modes.frequencies_hz[lab.index("3 OOP")] / modes.frequencies_hz[lab.index("1 IP")]
    truth = case.model.copy("truth")
    up.Parametrisation(truth, [cfg], [up.beam("w", "*", "width")]).apply(truth, np.array([width]))
    m = fg.solve_modes(fg.solve_static(truth, cfg), 8)
    oop = [i for i, name in enumerate(m.labels) if name.endswith("OOP")][:4]
    initial = truth.copy("initial")
    up.Parametrisation(initial, [cfg], [up.beam("E", "*", "E")]).apply(initial, np.array([1.0609]))
    return initial, cfg, m.frequencies_hz[oop], tuple(m.labels[i] for i in oop)


def test_labels_keep_a_measured_oop_mode_off_a_closer_fe_ip_mode():
    initial, cfg, f, labels = _oop_ip_strip()
    assert labels == ("1 OOP", "2 OOP", "3 OOP", "4 OOP")
    v = [up.beam("E", "*", "E")]
    blind = up.update(initial, [cfg], [up.Measured(cfg.name, f)], v, unidentifiable="free")
    told = up.update(initial, [cfg], [up.Measured(cfg.name, f, labels=labels)], v)
    paired = told.initial.configurations[cfg.name].paired
    assert told.initial.configurations[cfg.name].labels[paired[2]] == "3 OOP"
    assert blind.initial.configurations[cfg.name].labels[blind.initial.configurations[cfg.name].paired[2]] == "1 IP"
    assert told.x[0] == pytest.approx(1 / 1.0609, rel=1e-6)  # E recovered exactly
    assert abs(blind.x[0] * 1.0609 - 1) > 5e-3  # without the labels: biased by more than 0.5 %


def test_an_unidentifiable_variable_stays_at_its_initial_value_and_the_others_reach_the_truth():
    """Out-of-plane frequencies (0.2 % scatter) of a strip whose three regions' E are off: G barely
    moves them (std far above 50 %), a mass on the clamped root does not at all; E1-E3 are found."""
    case = fg.cases.cantilever_strip(n_elements=30)
    cfg = case.configurations["unloaded"]
    case.model.add_mass(case.references["root_node"], 0.05, name="root_clip")
    ev = [up.beam(f"E{r}", f"region{r}", "E") for r in (1, 2, 3)]
    x_e = np.array([1.04, 0.97, 1.03])
    modes = fg.solve_modes(fg.solve_static(case.model, cfg), 8)
    oop = [i for i, name in enumerate(modes.labels) if name.endswith("OOP")][:5]
    f = modes.frequencies_hz[oop]
    initial = case.model.copy("initial")
    up.Parametrisation(initial, [cfg], ev).apply(initial, x_e)
    data = [up.Measured(cfg.name, f, frequency_std_hz=0.002 * f)]
    variables = ev + [up.beam("G", "*", "G"), up.mass("clip", "root_clip")]
    with pytest.warns(FlexGVTWarning, match="held at their initial value"):
        result = up.update(initial, [cfg], data, variables)
    row = {r["name"]: r for r in result.variables}
    for name in ("G", "clip"):
        assert row[name]["fixed"] and not row[name]["identifiable"]
        assert row[name]["final"] == row[name]["initial"] and row[name]["change_percent"] == 0.0
    assert row["G"]["reason"].startswith("std +-")
    assert "the data do not constrain it (limit +-50 %)" in row["G"]["reason"]
    assert row["G"]["std_percent"] > 50
    assert row["clip"]["reason"].startswith("no sensitivity")
    np.testing.assert_allclose(result.x[:3], 1 / x_e, rtol=1e-5)
    np.testing.assert_array_equal(result.x[3:], [1.0, 1.0])
    for r in result.variables[:3]:
        assert r["identifiable"] and r["reason"] == "" and r["std_percent"] <= 50
    assert result.model.masses[0].mass == 0.05 and len(result.stages) == 2
    assert result.identifiability["unidentifiable"] == ["G", "clip"]
    # Left free on request: the flags and reasons are the same, the values are not held.
    free = up.update(initial, [cfg], data, variables, unidentifiable="free", max_iterations=20)
    flags = {r["name"]: (r["identifiable"], r["fixed"]) for r in free.variables}
    assert flags["G"] == (False, False) and flags["E1"] == (True, False) and not free.stages


def test_judge_steps_on_a_made_up_sensitivity_matrix():
    """No sensitivity, two columns the data see only together (the later one goes), a column with
    a 1e4 times smaller effect (std far above 50 % at sigma 1e-3), and an unknown sigma."""
    from flexgvt.updating.result import judge
    rng = np.random.default_rng(3)
    J = rng.normal(size=(8, 5))
    J[:, 0] = 0.0
    J[:, 2] = J[:, 1]
    J[:, 4] *= 1e-4
    names = ["zero", "a", "a_twin", "b", "weak"]
    v = judge(J, 1e-6, names, 0.5)
    assert v["identifiable"].tolist() == [False, True, False, True, False]
    assert v["reasons"][0].startswith("no sensitivity")
    assert v["reasons"][2].startswith("seen only together with 'a'")
    assert v["reasons"][4].startswith("std +-") and v["std"][4] > 0.5
    assert np.all(v["std"][[1, 3]] <= 0.5) and np.isinf(v["std"][[0, 2]]).all()
    unknown = judge(J, float("nan"), names, 0.5)  # no redundancy, no measured scatter: steps 1-2 only
    assert unknown["identifiable"].tolist() == [False, True, False, True, True]
    assert np.isnan(unknown["std"][[1, 3, 4]]).all()


def test_a_residual_with_too_few_degrees_of_freedom_does_not_estimate_sigma():
    """With one or two residuals beyond the variables (no measured scatter), s^2 = |r|^2 / (m - n)
    follows chance (1 degree of freedom: a factor 5000 between its 2.5 and 97.5 % points), so the
    stds are unknown rather than a reason to hold variables; from three on the residual serves."""
    from types import SimpleNamespace

    from flexgvt.updating.result import MIN_RESIDUAL_DOF, _residual_variance
    problem = SimpleNamespace(measured={"a": SimpleNamespace(frequency_std_hz=None)})
    point = SimpleNamespace(data_residuals=np.full(6, 0.01))
    assert MIN_RESIDUAL_DOF == 3
    for n in (5, 4):
        sigma2, source = _residual_variance(problem, point, 6, n)
        assert np.isnan(sigma2) and f"{6 - n} degree(s) of freedom" in source
    sigma2, source = _residual_variance(problem, point, 6, 3)
    assert sigma2 == pytest.approx(6e-4 / 3) and source.startswith("residual")
