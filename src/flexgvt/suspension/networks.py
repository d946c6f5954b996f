"""Springs, bungee cords and pulleys: what a suspension line is made of (docs/method.md section 2).

Rates combine in series (1/k = sum 1/k_i) and in parallel (k = sum k_i); a bungee cord is a
spring k = EA / l with EA from a load-extension test of a short piece; each element carries an
allowed load and stretch so a plan can refuse a spring that would yield.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from ..model import Cord
from ..model.configuration import STANDARD_GRAVITY


def series(*rates: float) -> float:
    """Rate [N/m] of springs in series: 1 / sum(1 / k_i)."""
    k = np.asarray(rates, float).ravel()
    if len(k) == 0 or np.any(~np.isfinite(k)) or np.any(k <= 0):
        raise ModelError(f"series: give positive, finite rates, got {k.tolist()}")
    return float(1.0 / np.sum(1.0 / k))


def parallel(*rates: float) -> float:
    """Rate [N/m] of springs in parallel: sum(k_i)."""
    k = np.asarray(rates, float).ravel()
    if len(k) == 0 or np.any(~np.isfinite(k)) or np.any(k <= 0):
        raise ModelError(f"parallel: give positive, finite rates, got {k.tolist()}")
    return float(np.sum(k))


@dataclass(frozen=True)
class LineElement:
    """A spring or a cord piece of a suspension line: rate [N/m], unstretched length [m], allowed
    load [N] and stretch [m] (inf: not limiting), mass [kg] and a name for messages."""

    name: str
    stiffness: float
    length: float
    allowed_load: float = np.inf
    allowed_stretch: float = np.inf
    mass: float = 0.0

    def __post_init__(self) -> None:
        if not (np.isfinite(self.stiffness) and self.stiffness > 0 and np.isfinite(self.length) and self.length > 0):
            raise ModelError(f"suspension element '{self.name}': stiffness and length must be positive and finite")
        if self.mass < 0 or self.allowed_load <= 0 or self.allowed_stretch <= 0:
            raise ModelError(f"suspension element '{self.name}': mass >= 0, allowed load and stretch > 0")

    def stretch(self, load: float) -> float:
        """Static stretch [m] under ``load`` [N] at its lower end, the element's own weight included
        (load grows linearly from the bottom to the top: stretch = (W + m g / 2) / k)."""
        return (load + 0.5 * self.mass * STANDARD_GRAVITY) / self.stiffness

    def check(self, load: float) -> list[str]:
        """Problems of this element under ``load`` [N]: loaded or stretched past its allowance."""
        out = []
        top = load + self.mass * STANDARD_GRAVITY
        if top > self.allowed_load:
            out.append(f"'{self.name}' carries {top:.3g} N, above its allowed {self.allowed_load:.3g} N (it would "
                       "yield or deform plastically): use a stiffer spring or share the load")
        if self.stretch(load) > self.allowed_stretch:
            out.append(f"'{self.name}' stretches {self.stretch(load):.3g} m, above its allowed "
                       f"{self.allowed_stretch:.3g} m")
        return out


@dataclass(frozen=True)
class Bungee:
    """Bungee cord: EA [N] (stiffness per unit length times length), mass per length [kg/m],
    allowed strain [-] and load [N]."""

    EA: float
    mass_per_length: float = 0.0
    allowed_strain: float = np.inf
    allowed_load: float = np.inf
    name: str = "bungee"

    @classmethod
    def from_load_extension(cls, loads: ArrayLike, extensions: ArrayLike, test_length: float,
                            mass_per_length: float = 0.0, allowed_strain: float = np.inf, allowed_load: float = np.inf,
                            name: str = "bungee") -> "Bungee":
        """EA from a load-extension test of a piece of ``test_length`` [m]: the slope of load [N]
        against strain (extension / test_length), least squares through the points."""
        P = np.asarray(loads, float)
        e = np.asarray(extensions, float) / test_length
        if P.shape != e.shape or len(P) < 2 or not np.all(np.isfinite(np.r_[P, e])) or test_length <= 0:
            raise ModelError("Bungee.from_load_extension: give at least two (load, extension) points and a positive "
                             "test length")
        A = np.column_stack([e, np.ones_like(e)])
        (EA, _), *_ = np.linalg.lstsq(A, P, rcond=None)
        if EA <= 0:
            raise ModelError("Bungee.from_load_extension: the load does not grow with the extension")
        return cls(float(EA), mass_per_length, allowed_strain, allowed_load, name)

    def element(self, length: float, name: str | None = None) -> LineElement:
        """A piece of ``length`` [m]: k = EA / length."""
        return LineElement(name or f"{self.name} {length:g} m", self.EA / length, length, self.allowed_load,
                           self.allowed_strain * length, self.mass_per_length * length)


@dataclass(frozen=True)
class Line:
    """A suspension line from its anchor to the structure: elements in series; with a pulley the
    line turns and only the ``after_pulley`` length acts on the structure as a pendulum, while the
    whole line's stretch sets the rate; the pulley's friction adds viscous damping [N s/m]."""

    elements: tuple[LineElement, ...]
    after_pulley: float | None = None
    pulley_damping: float = 0.0

    @property
    def stiffness(self) -> float:
        return series(*[e.stiffness for e in self.elements])

    @property
    def length(self) -> float:
        """Length [m] acting on the structure (the pendulum arm)."""
        return sum(e.length for e in self.elements) if self.after_pulley is None else self.after_pulley

    def stretch(self, load: float) -> float:
        """Static stretch [m] of the whole line carrying ``load`` [N] at the structure."""
        total, below = 0.0, 0.0
        for e in self.elements:  # from the structure up: each carries the load and what hangs below it
            total += e.stretch(load + below)
            below += e.mass * STANDARD_GRAVITY
        return total

    def check(self, load: float) -> list[str]:
        out, below = [], 0.0
        for e in self.elements:
            out += e.check(load + below)
            below += e.mass * STANDARD_GRAVITY
        return out

    def cord(self, node: int, anchor: ArrayLike, attachment: ArrayLike, load: float, damping: float = 0.0,
             offset: ArrayLike = (0.0, 0.0, 0.0)) -> Cord:
        """A flexgvt Cord for this line from ``anchor`` (3,) [m] to the structure's undeformed
        attachment point ``attachment`` (3,) [m], with the line's rate and damping (plus the
        pulley's) and, without a pulley, its mass, unstretched so that it carries ``load`` [N] at
        that point with its own weight (the solver then finds the sag of the flexible structure)."""
        anchor = np.asarray(anchor, float)
        reach = float(np.linalg.norm(anchor - np.asarray(attachment, float)))
        # Without a pulley the cord is the line (its own weight included in the stretch); with one,
        # the cord stands for the segment below the pulley at the whole line's rate.
        stretch = self.stretch(load) if self.after_pulley is None else load / self.stiffness
        l0 = reach - stretch
        if l0 <= 0:
            raise ModelError(f"suspension line: it would stretch {stretch:.3g} m under {load:.3g} N, more "
                             f"than the {reach:.3g} m from anchor to attachment; raise the anchor or use a stiffer "
                             "line")
        # Without a pulley the line's weight hangs on the structure (Cord.mass); with one, the pulley
        # carries the line above it and the short segment below is left massless.
        mass = sum(e.mass for e in self.elements) if self.after_pulley is None else 0.0
        return Cord(node=int(node), anchor=tuple(anchor), stiffness=self.stiffness, unstretched_length=l0,
                    damping=float(damping + self.pulley_damping), offset=tuple(offset), mass=float(mass))
