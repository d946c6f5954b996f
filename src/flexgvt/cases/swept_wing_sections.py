"""Section properties of the swept wing's parts (see flexgvt.cases.swept_wing): the carbon spar's
beam stiffness from classical lamination theory, and thin-walled NACA 00xx contours (film skin,
3D-printed body and fin walls). SI units.

The spar is a narrow laminated strip (20 mm wide, 5 mm thick). Its beam properties come from the
laminate's ABD matrix by the narrow-beam reduction (the other in-plane resultants free):
EA = b / a11, EI flatwise = b / d11, EI edgewise = b^3 / (12 a11), GJ from the rectangle's
Saint-Venant constant with the laminate's in-plane shear modulus 1 / (h a66); a, d: the inverses of
A and D (symmetric laminates, B = 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..model.section import rectangle_torsion_constant
from ..model.shells import Laminate, OrthotropicMaterial


def ply_stiffness(material: OrthotropicMaterial, theta_deg: float) -> np.ndarray:
    """Reduced plane-stress stiffness Qbar (3x3, Voigt [11, 22, 12], engineering shear) of an
    orthotropic ply turned by theta [deg] from the laminate's x axis [Pa]."""
    E1, E2, nu12, G12 = material.E1, material.E2, material.nu12, material.G12
    nu21 = nu12 * E2 / E1
    d = 1.0 - nu12 * nu21
    Q = np.array([[E1 / d, nu12 * E2 / d, 0.0], [nu12 * E2 / d, E2 / d, 0.0], [0.0, 0.0, G12]])
    c, s = math.cos(math.radians(theta_deg)), math.sin(math.radians(theta_deg))
    # Stress transformation T (Voigt, tensor shear) and Reuter's matrix R for engineering strain.
    T = np.array([[c * c, s * s, 2 * c * s], [s * s, c * c, -2 * c * s], [-c * s, c * s, c * c - s * s]])
    R = np.diag([1.0, 1.0, 2.0])
    Ti = np.linalg.inv(T)
    return Ti @ Q @ R @ T @ np.linalg.inv(R)


def abd(laminate: Laminate) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The laminate's A [N/m], B [N], D [N m] (3x3 each), plies bottom up about the mid-plane."""
    plies = list(laminate.plies)
    if laminate.lam == "SYM":
        plies = plies + plies[::-1]
    h = sum(p.thickness for p in plies)
    z = -h / 2
    A, B, D = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3))
    for p in plies:
        if not isinstance(p.material, OrthotropicMaterial):
            raise ModelError(f"laminate '{laminate.name}': the spar's plies must be OrthotropicMaterial (MAT8)")
        Q = ply_stiffness(p.material, p.theta)
        z1 = z + p.thickness
        A += Q * (z1 - z)
        B += Q * (z1**2 - z**2) / 2
        D += Q * (z1**3 - z**3) / 3
        z = z1
    return A, B, D


@dataclass(frozen=True)
class LaminateBeam:
    """Beam stiffness of a laminated strip of width b [m]: EA [N], EI_flat, EI_edge, GJ [N m^2], the
    equivalent moduli E (membrane, 1 / (h a11)) and G (1 / (h a66)) [Pa], and the flatwise bending
    modulus E_flat (12 / (h^3 d11)) [Pa] (what a tip-load test measures, Eq. 5.2)."""

    width: float
    thickness: float
    EA: float
    EI_flat: float
    EI_edge: float
    GJ: float
    E: float
    G: float
    E_flat: float


def laminate_beam(laminate: Laminate, width: float) -> LaminateBeam:
    """Beam properties of a symmetric laminate cut to a strip ``width`` [m] wide (module docstring)."""
    A, B, D = abd(laminate)
    h = laminate.thickness
    if np.abs(B).max() > 1e-9 * np.abs(A).max() * h:
        raise ModelError(f"laminate '{laminate.name}' is not symmetric (B != 0); the narrow-beam reduction "
                         "used for the spar needs a symmetric layup")
    a, d = np.linalg.inv(A), np.linalg.inv(D)
    b = float(width)
    E, G, E_flat = 1.0 / (h * a[0, 0]), 1.0 / (h * a[2, 2]), 12.0 / (h**3 * d[0, 0])
    J = rectangle_torsion_constant(b, h)
    return LaminateBeam(b, h, EA=b / a[0, 0], EI_flat=b / d[0, 0], EI_edge=b**3 / (12 * a[0, 0]), GJ=G * J,
                        E=E, G=G, E_flat=E_flat)


def tip_load_modulus(force: float, deflection: float, length: float, inertia: float) -> float:
    """Equivalent modulus of a cantilever tip-load test, E = F L^3 / (3 delta I) [Pa] (the original
    work's Eq. 5.2): force [N], tip deflection [m], length [m], second moment [m^4]."""
    if min(force, deflection, length, inertia) <= 0:
        raise ModelError("tip_load_modulus: force, deflection, length and inertia must all be > 0")
    return force * length**3 / (3.0 * deflection * inertia)


def naca_half_thickness(x: np.ndarray, thickness: float) -> np.ndarray:
    """NACA 00xx half thickness at chord fractions x (closed trailing edge), per unit chord."""
    return 5 * thickness * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)


def naca_area_centroid() -> float:
    """Chord fraction of the centroid of a NACA 00xx aerofoil's enclosed area (closed trailing
    edge; the same for every thickness ratio): the thickness polynomial's first moment over its
    integral, in closed form (about 0.418)."""
    a = (0.2969, -0.1260, -0.3516, 0.2843, -0.1036)
    powers = (0.5, 1.0, 2.0, 3.0, 4.0)
    area = sum(c / (p + 1) for c, p in zip(a, powers))
    return sum(c / (p + 2) for c, p in zip(a, powers)) / area


@dataclass(frozen=True)
class Contour:
    """A closed thin wall of thickness t [m] on a NACA 00xx contour, properties about a reference
    axis at chord fraction ``x_ref`` on the chord line: A [m^2], Iy (about the chord line), Iz
    (about the reference axis, across the chord), J (Bredt) [m^4], perimeter [m], enclosed area
    [m^2], centroid x from the reference axis [m]."""

    A: float
    Iy: float
    Iz: float
    J: float
    perimeter: float
    enclosed: float
    x_centroid: float


def naca_contour(chord: float, thickness_ratio: float, wall: float, x_ref: float, n: int = 400,
                 x_end: float = 1.0) -> Contour:
    """The thin-walled NACA 00xx (thickness_ratio, e.g. 0.12) contour of ``chord`` [m] and ``wall``
    [m], properties about the axis at chord fraction x_ref (Contour); x_end < 1: the contour from
    the nose to chord fraction x_end, closed there by a straight web of the same wall."""
    beta = np.linspace(0.0, math.pi, n + 1)
    xc = 0.5 * (1 - np.cos(beta)) * x_end  # cosine spacing: fine at the nose
    zt = naca_half_thickness(xc, thickness_ratio) * chord
    x = xc * chord
    dx, dz = np.diff(x), np.diff(zt)
    ds = np.hypot(dx, dz)
    xm, zm = 0.5 * (x[1:] + x[:-1]), 0.5 * (zt[1:] + zt[:-1])
    xr = x_ref * chord
    web = 2 * zt[-1]  # zero for a closed trailing edge
    per = 2 * ds.sum() + web
    A = wall * per
    Iy = 2 * wall * np.sum(zm**2 * ds) + wall * web**3 / 12
    Iz = 2 * wall * np.sum((xm - xr) ** 2 * ds) + wall * web * (x[-1] - xr) ** 2
    enclosed = 2 * np.sum(zm * dx)
    first = 2 * wall * np.sum((xm - xr) * ds) + wall * web * (x[-1] - xr)
    return Contour(A=A, Iy=Iy, Iz=Iz, J=4 * enclosed**2 * wall / per, perimeter=per, enclosed=enclosed,
                   x_centroid=float(first / A))
