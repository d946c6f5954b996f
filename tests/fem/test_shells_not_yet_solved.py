"""A model with shells is read (io.nastran's plate cards) but cannot be solved yet: it says so at
once, instead of solving the rest of the structure without its skins (issue 30)."""

from pathlib import Path

import pytest

import flexgvt as fg
from flexgvt.errors import ModelError

GOLAND = Path(__file__).resolve().parents[1] / "data" / "bdf" / "pynastran" / "goland" / "goland_final_test.bdf"


def test_the_real_goland_wing_box_with_its_skins_is_refused_clearly():
    deck = fg.io.read_bdf(GOLAND)
    assert deck.model.n_shells == 92
    config = next(iter(deck.configurations.values())) if isinstance(deck.configurations, dict) \
        else deck.configurations[0]
    for call in (lambda: fg.solve_static(deck.model, config), lambda: fg.mass_properties(deck.model)):
        with pytest.raises(ModelError, match=r"92 shell elements .* are read but not yet solved"):
            call()
