"""flexgvt.updating.parallel: worker processes that cannot start give a clear error."""

import pytest

from flexgvt.errors import UpdatingError
from flexgvt.updating import parallel


def test_workers_that_cannot_start_name_the_main_guard(monkeypatch):
    """A script that calls update(processes=N) at its top level, without `if __name__ ==
    "__main__":`, makes dask's spawned workers import it again and fail: dask's own message is
    "Nanny failed to start". flexgvt says what to do instead."""
    import distributed

    def failing(*args, **kwargs):
        raise RuntimeError("Nanny failed to start.")

    monkeypatch.setattr(distributed, "LocalCluster", failing)
    with pytest.raises(UpdatingError, match=r"could not start.*__name__ == \"__main__\""):
        with parallel.client_for(processes=2):
            pass
