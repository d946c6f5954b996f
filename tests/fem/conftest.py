"""Fixtures shared by the solver tests."""

import pytest

import flexgvt as fg


@pytest.fixture
def strip_props():
    sec = fg.RectangularSection(width=0.05, height=0.003, shear=False)
    return sec, sec.properties()
