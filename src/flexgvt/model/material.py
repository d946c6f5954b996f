"""Isotropic materials."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ModelError


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material.

    E: Young's modulus [Pa]; give either G [Pa] or nu [-]; rho: density [kg/m^3].
    """

    name: str
    E: float
    rho: float
    G: float | None = None
    nu: float | None = None

    def __post_init__(self) -> None:
        for field in ("E", "rho"):
            value = getattr(self, field)
            if value is None or not math.isfinite(value) or value < 0 or (field == "E" and value == 0):
                raise ModelError(f"material '{self.name}': {field}={value!r} must be a finite positive number")
        if self.G is None and self.nu is None:
            raise ModelError(f"material '{self.name}': give the shear modulus G [Pa] or Poisson's ratio nu")
        if self.G is not None and (not math.isfinite(self.G) or self.G <= 0):
            raise ModelError(f"material '{self.name}': G={self.G!r} must be a finite positive number")
        if self.nu is not None and not (-1.0 < self.nu < 0.5):
            raise ModelError(f"material '{self.name}': nu={self.nu!r} must lie in (-1, 0.5)")

    @property
    def shear_modulus(self) -> float:
        """G [Pa], from G or from E and nu."""
        if self.G is not None:
            return float(self.G)
        return self.E / (2.0 * (1.0 + self.nu))
