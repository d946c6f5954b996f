"""What the per-family bulk data writers share: id numbering of a compact deck, value comparison."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Numbering:
    """The next free element, property and coordinate system ids of a compact deck being written."""

    eid: int
    pid: int
    cid: int = 1


def same(a, b, rtol=1e-9) -> bool:
    """Equal values within rtol (arrays or scalars)."""
    return np.allclose(np.asarray(a, float), np.asarray(b, float), rtol=rtol, atol=0.0)
