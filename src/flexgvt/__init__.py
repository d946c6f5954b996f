"""flexgvt: ground vibration testing and FE model updating of very flexible aircraft."""

from __future__ import annotations

__version__ = "0.1.0"
