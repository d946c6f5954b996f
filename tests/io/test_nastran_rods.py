"""CROD/PROD and CONROD: mapping, the same frequencies as the model built in Python, round trips."""

import warnings
from pathlib import Path

import numpy as np
import pytest
from nastran_helpers import assert_close, model_data, rebuild

import flexgvt as fg
from flexgvt.workflow import solve_deck

DATA = Path(__file__).parents[1] / "data" / "bdf"
STEEL = fg.Material("MAT1_1", E=2.1e11, nu=0.3, rho=7850.0)


def read(path, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fg.io.read_bdf(path, **kw)


def python_twin():
    """tests/data/bdf/rods.bdf built with flexgvt calls (lumped mass, NSM as end masses)."""
    model = fg.Model("twin")
    x = np.arange(11) * 0.2
    ids = model.add_nodes(np.c_[x, 0 * x, 0 * x], ids=range(1, 12))
    model.add_rods(np.c_[ids[:-1], ids[1:]], STEEL, area=1e-6, torsion_constant=2e-13)
    ends = np.zeros(12)
    for a, b in zip(ids[:-1], ids[1:]):
        ends[[a, b]] += 0.5 * 0.002 * 0.2
    for n in ids:
        model.add_mass(int(n), float(ends[n]))
    fixed = {int(n): "456" for n in ids}
    fixed[1], fixed[11] = "123456", "23456"
    cfg = fg.Configuration("twin", fixed=fixed, forces=[fg.NodalLoad(11, force=(200.0, 0.0, 0.0))])
    return model, cfg


def test_rod_deck_maps_cards_and_matches_the_python_twin():
    deck = read(DATA / "rods.bdf")
    names = sorted(g.name for g in deck.model.beams)
    assert names == ["CONROD_110", "PROD_5"]
    rod = next(g for g in deck.model.beams if g.name == "PROD_5")
    assert rod.section == fg.RodSection(A=1e-6, J=2e-13) and rod.mass == "lumped"
    assert any("joined only by rods" in n for n in deck.notes)
    cfg = deck.configurations["subcase_1"]
    assert all("456" in cfg.fixed[n] or cfg.fixed[n] == "123456" for n in range(1, 12))
    got = solve_deck(deck)["subcase_1"].modes.frequencies_hz
    model, twin_cfg = python_twin()
    twin = fg.solve_modes(fg.solve_static(model, twin_cfg), n_modes=6, label=False).frequencies_hz
    np.testing.assert_allclose(got, twin, rtol=1e-9)
    # String with end masses: the fundamental is close to the continuum value sqrt(T / mu) / (2 L).
    mu = 7850.0 * 1e-6 + 0.002
    assert got[0] == pytest.approx(np.sqrt(200.0 / mu) / (2 * 2.0), rel=2e-2)


def test_rod_deck_round_trips_through_template_and_compact_writes(tmp_path):
    deck = read(DATA / "rods.bdf")
    fg.io.write_bdf(deck.model, tmp_path / "same.bdf", template=deck)
    again = read(tmp_path / "same.bdf")
    assert_close(model_data(again.model), model_data(deck.model), rtol=1e-12)
    # Updated values go into PROD and CONROD.
    stiffer = {"PROD_5": fg.RodSection(A=2e-6, J=3e-13), "CONROD_110": fg.RodSection(A=4e-6, J=0.0)}
    fg.io.write_bdf(rebuild(deck.model, section=stiffer), tmp_path / "updated.bdf", template=deck)
    updated = read(tmp_path / "updated.bdf")
    assert {g.name: g.section for g in updated.model.beams} == stiffer
    # A compact deck of a rod model built in Python: PROD + CROD, same frequencies.
    model, cfg = python_twin()
    fg.io.write_bdf(model, tmp_path / "compact.bdf", configurations=[cfg])
    compact = read(tmp_path / "compact.bdf")
    f0 = fg.solve_modes(fg.solve_static(model, cfg), n_modes=4, label=False).frequencies_hz
    f1 = solve_deck(compact)
    f1 = next(iter(f1.values())).modes.frequencies_hz[:4]
    np.testing.assert_allclose(f1, f0, rtol=1e-9)


def test_crod_on_a_missing_property_is_named(tmp_path):
    body = (DATA / "rods.bdf").read_text().replace("CROD,101,5,", "CROD,101,7,")
    (tmp_path / "bad.bdf").write_text(body)
    with pytest.raises(fg.errors.ModelError, match="CROD 101.*property 7"):
        read(tmp_path / "bad.bdf")
