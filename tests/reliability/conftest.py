"""Fixtures of the robustness tests."""

import pytest
from project_fixtures import build_base


@pytest.fixture(scope="session")
def base(tmp_path_factory):
    """A project folder as `flexgvt init --data` writes it, plus modes already identified; built once
    per session (tests copy it before changing anything)."""
    return build_base(tmp_path_factory.mktemp("init-data"))
