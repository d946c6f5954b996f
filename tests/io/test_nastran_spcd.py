"""SPCD (and SPC with an enforced value) -> Configuration.prescribed: the cantilever whose tip is
pushed by d bends as a Timoshenko beam under the tip force P that takes it there,
w(x) = P (L x^2 / 2 - x^3 / 6) / EI + P x / (k G A) (PBARL BAR keeps shear, k = 5/6); round trip
through a compact deck."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.workflow import solve_deck

D = 2e-3  # m


def deck_text(tip_spc="1234", enforced_by="SPCD"):
    lines = ["SOL 101", "CEND", "SUBCASE 1", "  SPC = 1", "  LOAD = 2", "BEGIN BULK",
             "MAT1,1,7.+10,,0.33,2700.", "PBARL,5,1,,BAR", ",0.003,0.05"]  # 3 mm along z: a flat strip
    for i in range(21):
        lines.append(f"GRID,{i + 1},,{0.05 * i:.2f},0.,0.")
    for i in range(20):
        lines.append(f"CBAR,{101 + i},5,{i + 1},{i + 2},0.,1.,0.")  # v along y: the 3 mm DIM1 lies along z
    lines.append("SPC1,1,123456,1")
    if enforced_by == "SPCD":
        lines += [f"SPC1,1,{tip_spc},21", f"SPCD,2,21,3,{D}", "FORCE,2,11,,0.,1.,0.,0."]
    else:  # SPC's own D field
        lines += [f"SPC,1,21,3,{D}", "SPC1,1,124,21", "FORCE,2,11,,0.,1.,0.,0."]
    return "\n".join(lines + ["ENDDATA"]) + "\n"


def read(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path)


@pytest.mark.parametrize("enforced_by", ["SPCD", "SPC"])
def test_enforced_tip_displacement_from_bulk_data(tmp_path, enforced_by):
    path = tmp_path / "push.bdf"
    path.write_text(deck_text("1234", enforced_by))
    deck = read(path)
    cfg = deck.configurations["subcase_1"]
    assert cfg.prescribed == {21: {3: pytest.approx(D)}}
    state = fg.solve_linear_static(deck.model, cfg)
    x = deck.model.xyz[:, 0]
    L = x.max()
    E, nu, b, h = 7e10, 0.33, 0.05, 0.003
    EI, kGA = E * b * h**3 / 12, 5 / 6 * E / (2 * (1 + nu)) * b * h
    P = D / (L**3 / (3 * EI) + L / kGA)
    expected = P * (L * x**2 / 2 - x**3 / 6) / EI + P * x / kGA
    np.testing.assert_allclose(state.displacements[:, 2], expected, rtol=1e-6, atol=1e-12)
    # Compact deck of the same model and configuration: the enforced value survives the round trip.
    out = fg.io.write_bdf(deck.model, tmp_path / "compact.bdf", configurations=[cfg])
    again = read(out)
    cfg2 = next(iter(again.configurations.values()))
    assert cfg2.prescribed == {21: {3: pytest.approx(D)}}
    got = solve_deck(again)
    nl = next(iter(got.values())).state
    np.testing.assert_allclose(nl.displacements[-1, 2], D, rtol=1e-12)


def test_spcd_on_a_dof_the_spc_set_does_not_hold_is_an_error(tmp_path):
    path = tmp_path / "loose.bdf"
    path.write_text(deck_text("124"))  # z of node 21 is not in SPC set 1
    with pytest.raises(fg.errors.ModelError, match="SPCD on node 21 component.*3"):
        read(path)
