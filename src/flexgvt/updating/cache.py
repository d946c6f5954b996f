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
        self._held: tuple[bytes, Point] | None = None  # a point that is the answer if its solves repeat

    def hold(self, key: bytes, point: Point) -> None:
        """``point`` is the answer at ``key`` if solving it again returns its very equilibria (the
        problem checks): held until it is asked for or the cache is cleared."""
        self._held = (key, point)

    def held(self, key: bytes) -> Point | None:
        """The point held at ``key`` (released), or None."""
        held, self._held = self._held, None
        return held[1] if held is not None and held[0] == key else None

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
        self._held = None

    def __len__(self) -> int:
        return len(self._points)
