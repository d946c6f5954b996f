"""Design variables address masses and springs by name or id (as beams by group name); positions
still work with a DeprecationWarning naming the new way."""

import warnings

import numpy as np
import pytest

import flexgvt as fg
import flexgvt.updating as up
from flexgvt.errors import ModelError


def _model():
    m = fg.Model("m")
    ids = m.add_nodes(np.c_[np.arange(4.0), np.zeros(4), np.zeros(4)])
    m.add_beams(np.c_[ids[:-1], ids[1:]], fg.Material("al", E=70e9, nu=0.3, rho=2700.0),
                fg.RectangularSection(width=0.05, height=0.003), name="strip")
    m.add_mass(int(ids[1]), 0.1, name="pod_L", id=101)
    m.add_mass(int(ids[2]), 0.2, name="pod_R", id=102)
    m.add_mass(int(ids[3]), 0.3, name="tip", id=7)
    m.add_spring(int(ids[0]), None, stiffness=1e4, name="root", id=9001)
    return m


def test_names_patterns_and_ids_bind_the_same_positions():
    m = _model()
    cfg = fg.Configuration("free")
    par = up.Parametrisation(m, [cfg], [up.mass("pods", "pod_*"), up.mass("tip", ids=7),
                                        up.spring("root", "root", "k1"), up.spring("root_c", ids=[9001],
                                                                                    attribute="k2")])
    assert [b.indices for b in par.bindings] == [(0, 1), (2,), (0,), (0,)]
    np.testing.assert_allclose(par.bindings[0].initial, [0.1, 0.2])
    assert m.find("mass", 102) == [1] and m.find("spring", "ro*") == [0]


def test_positions_warn_and_bind_as_before():
    m = _model()
    with pytest.warns(DeprecationWarning, match="names .* or ids="):
        v = up.mass("pods", [0, 1])
    assert up.Parametrisation(m, [fg.Configuration("free")], [v]).bindings[0].indices == (0, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        up.mass("pods", "pod_*")  # names: no warning


def test_unknown_names_and_ids_are_named():
    m = _model()
    cfg = fg.Configuration("free")
    with pytest.raises(ModelError, match="no mass named 'wing'.*'pod_L'"):
        up.Parametrisation(m, [cfg], [up.mass("w", "wing")])
    with pytest.raises(ModelError, match="no spring with id 5"):
        up.Parametrisation(m, [cfg], [up.spring("s", ids=5)])
    with pytest.raises(ModelError, match="names no mass"):
        up.Parametrisation(m, [cfg], [up.mass("nothing")])
    with pytest.raises(ModelError, match="only masses and springs"):
        up.Variable("c", "cord", "stiffness", ids=(3,))


def test_configuration_masses_by_name():
    m = _model()
    hw = fg.model.ConcentratedMass(2, 0.02, np.zeros(3), np.zeros((3, 3)), name="hook")
    cfg = fg.Configuration("hung", masses=(hw,))
    par = up.Parametrisation(m, [cfg], [up.mass("hook", "hook", configurations=["hung"])])
    assert par.bindings[0].indices == (("hung", 0),)
