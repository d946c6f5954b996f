"""One name per idea: progress=, to_dict(), table(), summary() -> str; the old names warn and work."""

from types import SimpleNamespace

import numpy as np
import pytest

import flexgvt.updating as up
from flexgvt.suspension import identify_block
from flexgvt.workflow import ProjectError, run


def test_as_dict_is_a_deprecated_name_of_to_dict():
    fake = SimpleNamespace(to_dict=lambda: {"a": 1})
    for cls in (up.UpdateResult, up.Verification):
        with pytest.warns(DeprecationWarning, match=f"{cls.__name__}.to_dict"):
            assert cls.as_dict(fake) == {"a": 1}
    point = identify_block(0.8, frequency_hz=0.4, damping_ratio=0.07)
    with pytest.warns(DeprecationWarning, match="to_dict"):
        assert point.as_dict() == point.to_dict()


def test_configuration_point_to_dict_and_its_old_names():
    p = up.ConfigurationPoint("a", None, np.ones(2), np.ones(2), None, np.zeros(1, int), np.ones(1), None, None,
                              np.zeros(0), _labels=("1 OOP", "2 OOP"))
    d = p.to_dict()
    assert up.ConfigurationPoint.from_dict(d).labels == ("1 OOP", "2 OOP")
    with pytest.warns(DeprecationWarning, match="to_dict"):
        assert p.summary().keys() == d.keys()
    with pytest.warns(DeprecationWarning, match="from_dict"):
        up.ConfigurationPoint.from_summary(d)


def test_run_log_is_a_deprecated_name_of_progress(tmp_path):
    with pytest.warns(DeprecationWarning, match="run\\(progress=...\\)"):
        with pytest.raises(ProjectError, match="not found"):
            run(tmp_path / "missing.toml", log=print)
