"""Force-deflection tables of nonlinear springs (model.Spring's ``tables``): Nastran's PBUSHT KN /
PELAST TKNID / PBUSH1D SPRING TABLE, a TABLED1 of deflection against force.

A table maps the deflection d of one spring component [m or rad] (in the spring's axes, node b
relative to node a) to its force f(d) [N or N m], interpolated piecewise linearly (Nastran's
TABLED1 LINEAR/LINEAR) or, with ``smooth=True``, by the monotone cubic (PCHIP, Fritsch-Carlson)
through the same points, whose slope is continuous. Outside the table the force goes on along the
end slope (the last segment's, or the cubic's slope at the end point): no clamp, no jump. The
consistent tangent is the slope df/dd at the current deflection (at a breakpoint of the piecewise
linear table: the slope of the segment on the larger-deflection side).

f(0) must be 0: the undeformed state carries no spring force (a preloaded spring is not modelled).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError


@dataclass(frozen=True, eq=False)
class SpringTable:
    """Force [N or N m] against deflection [m or rad] of one spring component; see the module.

    x: deflections, strictly increasing, at least two; f: forces there; smooth: monotone cubic
    instead of straight segments. Build with SpringTable.make (it checks the data)."""

    x: np.ndarray
    f: np.ndarray
    smooth: bool = False
    name: str = ""

    @staticmethod
    def make(x: ArrayLike, f: ArrayLike, smooth: bool = False, name: str = "") -> "SpringTable":
        where = f"spring table {name!r}" if name else "spring table"
        try:
            xs = np.array(x, dtype=float).reshape(-1)
            fs = np.array(f, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ModelError(f"{where}: deflections and forces must be numbers, got {x!r} and {f!r}") from None
        if xs.shape != fs.shape:
            raise ModelError(f"{where}: {len(xs)} deflections but {len(fs)} forces; give one force per deflection")
        if len(xs) < 2:
            raise ModelError(f"{where}: {len(xs)} point(s); a force-deflection table needs at least two")
        if not (np.all(np.isfinite(xs)) and np.all(np.isfinite(fs))):
            raise ModelError(f"{where}: NaN or infinity in the table (x={xs}, f={fs}); give finite values")
        step = np.diff(xs)
        if np.any(step <= 0):
            k = int(np.flatnonzero(step <= 0)[0])
            raise ModelError(f"{where}: deflections must increase strictly; x[{k}]={xs[k]:g} is followed by "
                             f"x[{k + 1}]={xs[k + 1]:g}. Sort the table and merge repeated deflections")
        xs.setflags(write=False)
        fs.setflags(write=False)
        table = SpringTable(xs, fs, bool(smooth), str(name))
        f0 = float(table.evaluate(np.zeros(1))[0][0])
        if abs(f0) > 1e-9 * max(np.max(np.abs(fs)), 1e-300):
            raise ModelError(f"{where}: the force at zero deflection is {f0:g}, not 0: a preloaded spring is not "
                             "modelled. Shift the table so that it passes through (0, 0) and apply the preload as "
                             "a load")
        if table.nominal_stiffness <= 0:
            raise ModelError(f"{where}: the table is flat (every slope 0); give a table with some stiffness")
        return table

    @property
    def slopes(self) -> np.ndarray:
        """(n - 1,) slopes of the straight segments."""
        return np.diff(self.f) / np.diff(self.x)

    @property
    def nominal_stiffness(self) -> float:
        """The stiffness a scale of 1 stands for: the slope at zero deflection, or where that is 0
        (a gap or a one-sided spring) the largest slope magnitude of the segments [N/m, N m/rad]."""
        k0 = float(self.evaluate(np.zeros(1))[1][0])
        return k0 if k0 > 0 else float(np.max(np.abs(self.slopes)))

    def knot_slopes(self) -> np.ndarray:
        """(n,) slopes of the smooth table at its points: Fritsch-Carlson's weighted harmonic mean
        inside (0 where the data turn), the shape-preserving three-point rule at the ends (as
        scipy.interpolate.PchipInterpolator)."""
        h, s = np.diff(self.x), self.slopes
        if len(s) == 1:
            return np.array([s[0], s[0]])
        d = np.zeros(len(self.x))
        w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
        same = (np.sign(s[1:]) == np.sign(s[:-1])) & (s[1:] != 0) & (s[:-1] != 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            d[1:-1] = np.where(same, (w1 + w2) / (w1 / np.where(same, s[:-1], 1) + w2 / np.where(same, s[1:], 1)), 0)
        for end, (h0, h1, s0, s1) in ((0, (h[0], h[1], s[0], s[1])), (-1, (h[-1], h[-2], s[-1], s[-2]))):
            e = ((2 * h0 + h1) * s0 - h0 * s1) / (h0 + h1)
            if np.sign(e) != np.sign(s0):
                e = 0.0
            elif np.sign(s0) != np.sign(s1) and abs(e) > abs(3 * s0):
                e = 3 * s0
            d[end] = e
        return d

    def evaluate(self, d: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """(force, slope) at deflections d (any shape) [N or N m, N/m or N m/rad]."""
        d = np.asarray(d, float)
        x, f = self.x, self.f
        k = np.clip(np.searchsorted(x, d, side="right") - 1, 0, len(x) - 2)  # segment, the right one at a knot
        h = x[k + 1] - x[k]
        if not self.smooth:
            slope = self.slopes[k]
            inside = f[k] + slope * (d - x[k])
            return inside, slope
        m = self.knot_slopes()
        t = (d - x[k]) / h
        h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
        force = h00 * f[k] + h10 * h * m[k] + h01 * f[k + 1] + h11 * h * m[k + 1]
        slope = ((6 * t**2 - 6 * t) * f[k] + (3 * t**2 - 4 * t + 1) * h * m[k] + (-6 * t**2 + 6 * t) * f[k + 1]
                 + (3 * t**2 - 2 * t) * h * m[k + 1]) / h
        below, above = d < x[0], d > x[-1]
        force = np.where(below, f[0] + m[0] * (d - x[0]), np.where(above, f[-1] + m[-1] * (d - x[-1]), force))
        slope = np.where(below, m[0], np.where(above, m[-1], slope))
        return force, slope
