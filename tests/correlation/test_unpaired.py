"""Unpaired measured modes carry their reason; labels keep a measured OOP mode off an FE IP mode."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.correlation import Sensors, label_families, labels_compatible, pair, pair_by_frequency
from flexgvt.modal import ModalSet


@pytest.fixture(scope="module")
def strip():
    case = fg.cases.cantilever_strip(n_elements=30)
    state = fg.solve_static(case.model, case.configurations["unloaded"])
    modes = fg.solve_modes(state, 8)
    return case, state, modes


def _measured(state, modes, sensors, keep):
    shapes = np.asarray(sensors.matrix(state.node_ids, state) @ modes.matrix()).T[keep]
    return ModalSet(modes.frequencies_hz[keep], shapes=shapes)


def test_label_families():
    assert label_families("5 OOP") == {"OOP"} and label_families("2 IP") == {"IP"}
    assert label_families("1 T/OOP") == {"T", "OOP"} and label_families("RB plunge") == {"RB"}
    assert label_families("torsion 2") == {"T"} and label_families("mode 3") == frozenset()
    assert not labels_compatible("5 OOP", "2 IP") and labels_compatible("1 T", "1 OOP/T")
    assert labels_compatible("mode 3", "2 IP")  # a label naming no family constrains nothing
    # A distributed cord's own modes (fem.labels) are a family of their own.
    assert label_families("3 bungee surge") == label_families("1 bungee string") == {"CORD"}
    assert not labels_compatible("1 OOP", "1 bungee string")


def test_a_measured_mode_never_pairs_a_closer_mode_of_a_heavy_cord():
    """Frequency-only data on a structure hung by distributed cords: the cords' own surge and string
    modes lie among the structure's and must not take a measured bending mode's place."""
    fm = [0.99, 2.74]
    fa = [1.004, 2.70, 2.75, 3.1]
    labels_a = ("1 OOP", "2 OOP", "1 bungee string", "1 bungee surge")
    assert pair_by_frequency(fm, fa).analytical.tolist() == [0, 2]  # blind: the string mode, 0.4 % away
    got = pair_by_frequency(fm, fa, measured_labels=("1 OOP", "2 OOP"), analytical_labels=labels_a)
    assert got.analytical.tolist() == [0, 1] and not got.unpaired


def test_a_measured_oop_mode_never_pairs_a_closer_fe_ip_mode():
    """The case seen: a measured '5 OOP' with an FE '2 IP' 0.4 % away and the FE '5 OOP' 3 % away."""
    fm = [1.0, 6.3, 17.6, 34.5, 57.0]
    labels_m = ("1 OOP", "2 OOP", "3 OOP", "4 OOP", "5 OOP")
    fa = [1.03, 6.49, 18.1, 35.5, 57.23, 58.7, 70.0]
    labels_a = ("1 OOP", "2 OOP", "3 OOP", "4 OOP", "2 IP", "5 OOP", "1 T")
    blind = pair_by_frequency(fm, fa)
    assert blind.analytical[4] == 4  # without labels: the IP mode, 0.4 % away
    got = pair_by_frequency(fm, fa, measured_labels=labels_m, analytical_labels=labels_a)
    assert got.analytical.tolist() == [0, 1, 2, 3, 5] and not got.unpaired
    # With no FE mode of its family in range it stays unpaired, and says so.
    got = pair_by_frequency(fm, fa[:5], measured_labels=labels_m, analytical_labels=labels_a[:5],
                            max_frequency_ratio=1.2)
    (u,) = got.reasons
    assert (u.mode, u.reason, u.best_label) == (5, "label_mismatch", "2 IP")
    assert "family (OOP)" in u.text and "2 IP" in u.text
    # Its family's modes all taken by other measured modes: 'taken'.
    got = pair_by_frequency(fm, fa[:5], measured_labels=labels_m, analytical_labels=labels_a[:5])
    assert [(u.mode, u.reason) for u in got.reasons] == [(5, "taken")]


def test_no_fe_mode_within_the_frequency_ratio(strip):
    case, state, modes = strip
    sensors = Sensors.triaxial(case.model.node_ids[5::5])
    meas = _measured(state, modes, sensors, slice(0, 4))
    far = ModalSet(np.r_[meas.frequencies_hz[:3], 900.0], shapes=meas.shapes)
    got = pair(far, modes, sensors)
    (u,) = got.reasons
    assert (u.mode, u.reason) == (4, "no_mode_in_range")
    assert "within a factor 2" in u.text and u.best_mode == len(modes.frequencies_hz)  # the nearest: the highest
    row = got.table()[3]
    assert row["analytical_mode"] is None and row["reason"] == u.text


def test_mac_below_the_floor_names_the_best_mode(strip):
    """Test points mapped to the wrong FE nodes (the span reversed): the MACs collapse."""
    case, state, modes = strip
    nodes = case.model.node_ids[5::5]
    meas = _measured(state, modes, Sensors.triaxial(nodes), slice(0, 5))
    got = pair(meas, modes, Sensors.triaxial(nodes[::-1]))
    assert len(got.unpaired) >= 3
    for u in got.reasons:
        assert u.reason in ("mac_below_floor", "taken")
        if u.reason == "mac_below_floor":
            assert u.best_mac < 0.5 and u.best_mode is not None and f"best MAC {u.best_mac:.2f}" in u.text


def test_sensors_that_see_nothing(strip):
    """Every test point mapped onto the clamped root node: no FE mode moves there."""
    case, state, modes = strip
    meas = _measured(state, modes, Sensors.triaxial(case.model.node_ids[5::5]), slice(0, 3))
    root = Sensors.triaxial([case.references["root_node"]] * 6)
    got = pair(meas, modes, root)
    assert len(got.reasons) == 3 and all(u.reason == "not_seen" for u in got.reasons)
    assert "sensors see none" in got.reasons[0].text and "mapping" in got.reasons[0].text
    zero = ModalSet(meas.frequencies_hz, shapes=np.vstack([meas.shapes[:2], 0 * meas.shapes[2]]))
    got = pair(zero, modes, Sensors.triaxial(case.model.node_ids[5::5]))
    (u,) = got.reasons
    assert (u.mode, u.reason) == (3, "not_seen") and "measured shape is zero" in u.text
