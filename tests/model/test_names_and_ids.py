"""Masses and springs carry an optional name and id, unique in their model, kept by set_* and copy."""

import numpy as np
import pytest

import flexgvt as fg
from flexgvt.errors import ModelError


def test_names_and_ids_are_unique_and_survive_changes():
    m = fg.Model()
    ids = m.add_nodes(np.eye(3))
    m.add_mass(int(ids[0]), 1.0, name="a", id=11)
    m.add_spring(int(ids[0]), int(ids[1]), stiffness=5.0, name="s", id=21)
    with pytest.raises(ModelError, match="name 'a' is taken"):
        m.add_mass(int(ids[1]), 1.0, name="a")
    with pytest.raises(ModelError, match="id 21 is taken"):
        m.add_spring(int(ids[1]), None, stiffness=1.0, id=21)
    m.set_mass(0, mass=2.0)
    m.set_spring(0, stiffness=7.0)
    c = m.copy()
    assert (c.masses[0].name, c.masses[0].id, c.masses[0].mass) == ("a", 11, 2.0)
    assert (c.springs[0].name, c.springs[0].id, c.springs[0].stiffness[0]) == ("s", 21, 7.0)
    assert m.find("mass", "a") == [0] and m.find("spring", 21) == [0]
    with pytest.raises(ModelError, match="no mass with id 3"):
        m.find("mass", 3)
