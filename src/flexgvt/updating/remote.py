"""The updating problem's side of remote evaluation: each configuration evaluated by its worker
(flexgvt.updating.parallel.ConfigurationWorker) at once, the answers read back as points."""

from __future__ import annotations

from typing import Iterator, Sequence

import numpy as np

from ..model import Configuration
from .points import ConfigurationPoint, DesignPointFailure


def remote_points(workers: Sequence, configurations: Sequence[Configuration], x: np.ndarray,
                  gradient: bool) -> Iterator[tuple[str, ConfigurationPoint]]:
    """(name, point) of every configuration, evaluated at x by its worker (all started at once, so
    they run in parallel); DesignPointFailure at the first configuration that failed."""
    futures = [w.evaluate(x, gradient) for w in workers]
    for cfg, fut in zip(configurations, futures):
        d = fut.result()
        if "failure" in d:
            raise DesignPointFailure(d["failure"])
        yield cfg.name, ConfigurationPoint.from_dict(d)
