"""CSV tables rounded to what their numbers support (flexgvt.workflow.outputs.round_value)."""

import pytest

from flexgvt.workflow.outputs import round_rows, round_value


def test_frequencies_follow_their_standard_deviation_or_keep_five_digits():
    row = {"measured_hz": 0.26641780752630745, "measured_std_hz": 5.0164e-05, "initial_hz": 0.27044369168862853}
    out = round_rows([row])[0]
    assert out["measured_hz"] == 0.266418  # std 5.0e-05: its 2 significant digits reach the 6th decimal
    assert out["measured_std_hz"] == 5.0e-05
    assert out["initial_hz"] == 0.27044  # no std: 5 significant digits
    assert round_value("free_hz", 10.544234) == 10.544


def test_mac_percentages_angles_and_the_rest():
    assert round_value("mac_updated", 0.9930495) == 0.993
    assert round_value("bungee_outboard_mac", 0.99876) == 0.999
    assert round_value("comac", 0.81549) == 0.815 and round_value("mpc", 0.99871) == 0.999
    assert round_value("updated_error_percent", -0.0725484551646775) == -0.07
    assert round_value("std_percent", 2434.456) == 2400.0 and round_value("damping_std_percent", 0.0035) == 0.0035
    assert round_value("mpd_deg", 12.44) == 12.4
    assert round_value("updated", 4193190053.0914497) == pytest.approx(4.19319e9, rel=1e-12)


def test_what_is_not_a_float_is_left_as_it_is():
    row = {"mode": 3, "label": "1 OOP", "paired": True, "updated_hz": None, "bounds": (0.75, 1.25),
           "nan_hz": float("nan")}
    out = round_rows([row])[0]
    assert out["mode"] == 3 and out["label"] == "1 OOP" and out["paired"] is True and out["updated_hz"] is None
    assert out["bounds"] == (0.75, 1.25) and out["nan_hz"] != out["nan_hz"]
