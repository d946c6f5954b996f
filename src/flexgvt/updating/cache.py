"""The updating problem's point cache: the residuals and the Jacobian of one design point are
computed once (an optimiser asks for them in separate calls)."""

from __future__ import annotations

from .points import Point


class PointCache:
    """The points of the last few design points, keyed by x's bytes; cleared whole when it grows
    beyond ``size`` (the optimisers ask about the last point or two)."""

    def __init__(self, size: int = 8):
        self.size = size
        self._points: dict[bytes, Point] = {}

    def get(self, key: bytes) -> Point | None:
        return self._points.get(key)

    def add(self, key: bytes, point: Point) -> None:
        """A new point (the cache is emptied first when it holds more than ``size``)."""
        if len(self._points) > self.size:
            self._points.clear()
        self._points[key] = point

    def replace(self, key: bytes, point: Point) -> None:
        """The point at ``key`` completed (its Jacobian added)."""
        self._points[key] = point

    def clear(self) -> None:
        self._points.clear()

    def __len__(self) -> int:
        return len(self._points)
