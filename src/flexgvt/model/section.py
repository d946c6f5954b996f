"""Beam cross-sections.

Section axes: local y and z of the beam element (see ``Model.add_beams``). ``Iy`` is the second
moment of area about local y (bending in the local x-z plane), ``Iz`` about local z. A
TaperedSection holds a section for each end of the element (Nastran's tapered PBEAM/PBEAML).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError


def _check_positive(owner: str, **values: float | None) -> None:
    for name, value in values.items():
        if value is None:
            continue
        if not math.isfinite(value) or value <= 0:
            raise ModelError(f"{owner}: {name}={value!r} must be a finite positive number")


def _check_nonnegative(owner: str, **values: float) -> None:
    for name, value in values.items():
        if not math.isfinite(value) or value < 0:
            raise ModelError(f"{owner}: {name}={value!r} must be a finite number >= 0")


@dataclass(frozen=True)
class GeneralSection:
    """Section given by its properties.

    A [m^2], Iy, Iz [m^4] (about local y, z), J torsion constant [m^4], Ay, Az shear areas [m^2]
    (None: no shear deformation, Euler-Bernoulli), Ip polar moment for torsional inertia
    [m^4] (default Iy + Iz; 0: no torsional inertia, as Nastran's CBAR). Iy, Iz or J = 0 leaves that bending plane or
    torsion without
    stiffness (as Nastran allows): constraints must then hold those motions.
    """

    A: float
    Iy: float
    Iz: float
    J: float
    Ay: float | None = None
    Az: float | None = None
    Ip: float | None = None

    def __post_init__(self) -> None:
        _check_positive("GeneralSection", A=self.A, Ay=self.Ay, Az=self.Az)
        _check_nonnegative("GeneralSection", Iy=self.Iy, Iz=self.Iz, J=self.J,
                           **({} if self.Ip is None else {"Ip": self.Ip}))

    @property
    def polar(self) -> float:
        """Polar second moment about the centroid, for torsional inertia [m^4]."""
        return self.Ip if self.Ip is not None else self.Iy + self.Iz

    def properties(self) -> dict[str, float]:
        return {"A": self.A, "Iy": self.Iy, "Iz": self.Iz, "J": self.J, "Ip": self.polar,
                "Ay": self.Ay or 0.0, "Az": self.Az or 0.0}


def rectangle_torsion_constant(b: float, t: float, terms: int = 50) -> float:
    """Saint-Venant torsion constant of a solid b x t rectangle [m^4] (series solution)."""
    a, c = max(b, t), min(b, t)
    n = 2 * np.arange(terms) + 1
    series = np.sum(np.tanh(n * np.pi * a / (2 * c)) / n**5)
    return float(a * c**3 / 3.0 * (1.0 - 192.0 / np.pi**5 * c / a * series))


@dataclass(frozen=True)
class RectangularSection:
    """Solid rectangle: ``width`` along local y, ``height`` along local z [m].

    shear=True gives Timoshenko shear areas 5/6 A; False keeps Euler-Bernoulli bending.
    """

    width: float
    height: float
    shear: bool = True

    def __post_init__(self) -> None:
        _check_positive("RectangularSection", width=self.width, height=self.height)

    def properties(self) -> dict[str, float]:
        b, h = self.width, self.height
        A = b * h
        shear_area = 5.0 / 6.0 * A if self.shear else 0.0
        return {"A": A, "Iy": b * h**3 / 12.0, "Iz": h * b**3 / 12.0, "J": rectangle_torsion_constant(b, h),
                "Ip": A * (b * b + h * h) / 12.0, "Ay": shear_area, "Az": shear_area}


@dataclass(frozen=True)
class CircularTubeSection:
    """Circular tube (or solid rod with inner_radius=0) [m]."""

    outer_radius: float
    inner_radius: float = 0.0
    shear: bool = True

    def __post_init__(self) -> None:
        _check_positive("CircularTubeSection", outer_radius=self.outer_radius)
        if not (0.0 <= self.inner_radius < self.outer_radius):
            raise ModelError(f"CircularTubeSection: inner_radius={self.inner_radius!r} must be in [0, outer_radius)")

    def properties(self) -> dict[str, float]:
        ro, ri = self.outer_radius, self.inner_radius
        A = math.pi * (ro**2 - ri**2)
        I = math.pi * (ro**4 - ri**4) / 4.0
        kappa = 0.9 if ri == 0 else 0.5
        shear_area = kappa * A if self.shear else 0.0
        return {"A": A, "Iy": I, "Iz": I, "J": 2 * I, "Ip": 2 * I, "Ay": shear_area, "Az": shear_area}


@dataclass(frozen=True)
class RodSection:
    """Section of a rod (Nastran CROD/CONROD): axial stiffness E A and torsion G J only, no bending.

    A [m^2]; J torsion constant [m^4] (0: no torsional stiffness). Rods carry no rotary or
    torsional inertia (as Nastran's), so a node joined only by rods needs its rotations fixed.
    """

    A: float
    J: float = 0.0

    def __post_init__(self) -> None:
        _check_positive("RodSection", A=self.A)
        if not math.isfinite(self.J) or self.J < 0:
            raise ModelError(f"RodSection: J={self.J!r} must be a finite number >= 0")

    def properties(self) -> dict[str, float]:
        return {"A": self.A, "Iy": 0.0, "Iz": 0.0, "J": self.J, "Ip": 0.0, "Ay": 0.0, "Az": 0.0}


UniformSection = GeneralSection | RectangularSection | CircularTubeSection


@dataclass(frozen=True)
class TaperedSection:
    """Section that varies along each element, from ``end_a`` at its first node to ``end_b`` at its
    second (Nastran's tapered PBEAM/PBEAML on a CBEAM, end A at GA).

    A, Iy, Iz, J, Ip and the shear areas vary linearly between the end values. Stiffness: the
    element's flexibility (bending with shear, axial, torsion) integrated by 3-point Gauss, as
    Nastran's CBEAM; mass: the linear distributions of rho A, rho Ip (and rho I with rotary
    inertia), lumped by their centroids (each node takes int m N_i dx, N_i linear) or consistent.
    Ends: GeneralSection, RectangularSection or CircularTubeSection, both with shear areas in a
    plane or both without (Euler-Bernoulli).
    """

    end_a: UniformSection
    end_b: UniformSection

    def __post_init__(self) -> None:
        for name in ("end_a", "end_b"):
            sec = getattr(self, name)
            if not isinstance(sec, (GeneralSection, RectangularSection, CircularTubeSection)):
                raise ModelError(f"TaperedSection: {name} is a {type(sec).__name__}; give a GeneralSection, "
                                 "RectangularSection or CircularTubeSection at each end (rods do not taper)")
        pa, pb = self.end_a.properties(), self.end_b.properties()
        for area, plane in (("Ay", "x-y"), ("Az", "x-z")):
            if (pa[area] > 0) != (pb[area] > 0):
                raise ModelError(f"TaperedSection: shear area {area} is given at one end only ({pa[area]!r} at A, "
                                 f"{pb[area]!r} at B); give it at both ends (Timoshenko in the {plane} plane) or "
                                 "at neither (Euler-Bernoulli)")

    def end_properties(self) -> tuple[dict[str, float], dict[str, float]]:
        """Properties (see GeneralSection.properties) at end A and end B."""
        return self.end_a.properties(), self.end_b.properties()

    def properties(self) -> dict[str, float]:
        raise ModelError("a TaperedSection has properties at each end: use end_properties() (or "
                         "end_a.properties(), end_b.properties())")


Section = GeneralSection | RectangularSection | CircularTubeSection | RodSection | TaperedSection


def end_properties(section: Section) -> tuple[dict[str, float], dict[str, float]]:
    """Properties at the first and second node of an element: the same dict twice for a uniform section."""
    if isinstance(section, TaperedSection):
        return section.end_properties()
    p = section.properties()
    return p, p
