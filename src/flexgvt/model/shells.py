"""Shell data: plane-stress materials (MAT2, MAT8), shell properties (PSHELL) and laminates
(PCOMP/PCOMPG), and the shell element group. Plain data, checked on construction; the section
stiffness (A, B, D, S) is computed in fem (fem/_shell_section.py). Units: SI, angles in degrees
(as Nastran's THETA).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Union

import numpy as np

from ..errors import FlexGVTWarning, ModelError
from .material import Material

LAMINATE_OPTIONS = ("", "SYM", "MEM", "BEND", "SMEAR", "SMCORE")  # Nastran PCOMP LAM


def _positive(value, what: str, allow_zero: bool = False) -> float:
    ok = value is not None and isinstance(value, (int, float, np.integer, np.floating)) and math.isfinite(value) \
        and (value >= 0 if allow_zero else value > 0)
    if not ok:
        raise ModelError(f"{what}={value!r} must be a finite {'non-negative' if allow_zero else 'positive'} number")
    return float(value)


@dataclass(frozen=True)
class AnisotropicMaterial:
    """Anisotropic plane-stress material (Nastran MAT2): the symmetric matrix
    [[G11, G12, G13], [G12, G22, G23], [G13, G23, G33]] [Pa] on [ex, ey, gxy]; rho [kg/m^3].
    Used for transverse shear (PSHELL MID3) its [[G11, G12], [G12, G22]] part applies."""

    name: str
    G11: float
    G12: float
    G13: float
    G22: float
    G23: float
    G33: float
    rho: float = 0.0

    def __post_init__(self) -> None:
        for f in ("G11", "G12", "G13", "G22", "G23", "G33"):
            v = getattr(self, f)
            if v is None or not math.isfinite(v):
                raise ModelError(f"material '{self.name}': {f}={v!r} must be a finite number")
        _positive(self.rho, f"material '{self.name}': rho", allow_zero=True)
        if self.G11 < 0 or self.G22 < 0 or self.G33 < 0 or np.linalg.eigvalsh(self.matrix)[0] < \
                -1e-12 * max(abs(self.G11), abs(self.G22), abs(self.G33), 1e-300):
            raise ModelError(f"material '{self.name}': the matrix [G11 .. G33] is not positive semi-definite; "
                             "correct the material values")

    @property
    def matrix(self) -> np.ndarray:
        """(3, 3) plane-stress matrix [Pa]."""
        return np.array([[self.G11, self.G12, self.G13], [self.G12, self.G22, self.G23],
                         [self.G13, self.G23, self.G33]], float)


@dataclass(frozen=True)
class OrthotropicMaterial:
    """Orthotropic ply material in its own axes (Nastran MAT8): E1, E2, G12 [Pa], nu12 [-],
    transverse shear moduli G1z, G2z [Pa] (None: not given, Nastran's rigid transverse shear;
    fem then uses G12), rho [kg/m^3]."""

    name: str
    E1: float
    E2: float
    nu12: float
    G12: float
    G1z: float | None = None
    G2z: float | None = None
    rho: float = 0.0

    def __post_init__(self) -> None:
        where = f"material '{self.name}'"
        for f in ("E1", "E2", "G12"):
            _positive(getattr(self, f), f"{where}: {f}")
        for f in ("G1z", "G2z"):
            if getattr(self, f) is not None:
                _positive(getattr(self, f), f"{where}: {f}")
        _positive(self.rho, f"{where}: rho", allow_zero=True)
        if self.nu12 is None or not math.isfinite(self.nu12) or 1 - self.nu12**2 * self.E2 / self.E1 <= 0:
            raise ModelError(f"{where}: nu12={self.nu12!r} with E2/E1={self.E2 / self.E1:g} gives 1 - nu12 nu21 <= 0, "
                             "not a stable ply; correct nu12")


ShellMaterial = Union[Material, AnisotropicMaterial]
PlyMaterial = Union[Material, AnisotropicMaterial, OrthotropicMaterial]


@dataclass(frozen=True)
class ShellProperty:
    """A homogeneous shell property (Nastran PSHELL).

    thickness [m] (None only when every element gives corner thicknesses); membrane, bending,
    shear, coupling: the materials of MID1, MID2, MID3, MID4 (None: that part absent; bending
    None: a membrane); bending_ratio = 12 I / T^3 (1: solid plate); shear_ratio = TS/T (5/6);
    nsm: non-structural mass [kg/m^2]; z1, z2: fibre distances for stresses [m] (None: -T/2, T/2).
    """

    name: str
    thickness: float | None
    membrane: ShellMaterial | None
    bending: ShellMaterial | None = None
    bending_ratio: float = 1.0
    shear: ShellMaterial | None = None
    shear_ratio: float = 5.0 / 6.0
    coupling: ShellMaterial | None = None
    nsm: float = 0.0
    z1: float | None = None
    z2: float | None = None

    def __post_init__(self) -> None:
        where = f"shell property '{self.name}'"
        if self.thickness is not None:
            _positive(self.thickness, f"{where}: thickness")
        if self.membrane is None and self.bending is None:
            raise ModelError(f"{where}: no membrane and no bending material; give at least one (MID1 or MID2)")
        for f in ("membrane", "bending", "shear", "coupling"):
            m = getattr(self, f)
            if m is not None and not isinstance(m, (Material, AnisotropicMaterial)):
                raise ModelError(f"{where}: the {f} material is a {type(m).__name__}; a shell property takes a "
                                 "Material (MAT1) or an AnisotropicMaterial (MAT2); plies of MAT8 go in a Laminate")
        _positive(self.bending_ratio, f"{where}: bending_ratio (12I/T^3)")
        _positive(self.shear_ratio, f"{where}: shear_ratio (TS/T)")
        _positive(self.nsm, f"{where}: nsm", allow_zero=True)
        for f in ("z1", "z2"):
            v = getattr(self, f)
            if v is not None and not math.isfinite(v):
                raise ModelError(f"{where}: {f}={v!r} must be finite")

    @classmethod
    def isotropic(cls, material: Material, thickness: float, name: str = "", nsm: float = 0.0) -> "ShellProperty":
        """A solid plate of one material: membrane, bending and shear (TS/T = 5/6) all from ``material``."""
        return cls(name or f"{getattr(material, 'name', 'shell')}_{thickness:g}", thickness, material, material,
                   shear=material, nsm=nsm)


@dataclass(frozen=True)
class Ply:
    """One ply of a laminate: material, thickness [m], theta [deg] of its axis 1 from the element
    material x axis; sout: stresses requested (Nastran SOUT); ply_id: global ply id (PCOMPG) or None."""

    material: PlyMaterial | None
    thickness: float
    theta: float = 0.0
    sout: bool = False
    ply_id: int | None = None


@dataclass(frozen=True)
class Laminate:
    """A laminated shell property (Nastran PCOMP, or PCOMPG with global ply ids), plies from the
    bottom up. z0: reference plane to the bottom surface [m] (None: -thickness/2); nsm [kg/m^2];
    lam: one of LAMINATE_OPTIONS ('SYM': the plies given are the bottom half of a symmetric stack)."""

    name: str
    plies: tuple[Ply, ...]
    z0: float | None = None
    nsm: float = 0.0
    lam: str = ""

    def __post_init__(self) -> None:
        where = f"laminate '{self.name}'"
        object.__setattr__(self, "plies", tuple(self.plies))
        object.__setattr__(self, "lam", (self.lam or "").strip().upper())
        if not self.plies:
            raise ModelError(f"{where}: has no plies; give at least one Ply(material, thickness, theta)")
        for k, p in enumerate(self.plies, start=1):
            if not isinstance(p, Ply):
                raise ModelError(f"{where}: ply {k} is a {type(p).__name__}, not a Ply")
            if p.material is None:
                raise ModelError(f"{where}: ply {k} has no material; give each ply a material (MAT1, MAT2 or MAT8)")
            if not isinstance(p.material, (Material, AnisotropicMaterial, OrthotropicMaterial)):
                raise ModelError(f"{where}: ply {k} material is a {type(p.material).__name__}")
            _positive(p.thickness, f"{where}: ply {k} thickness")
            if p.theta is None or not math.isfinite(p.theta):
                raise ModelError(f"{where}: ply {k} theta={p.theta!r} must be a finite angle [deg]")
        ids = [p.ply_id for p in self.plies if p.ply_id is not None]
        if ids and (len(ids) != len(self.plies) or len(set(ids)) != len(ids)):
            raise ModelError(f"{where}: global ply ids {ids} must be given for every ply and be distinct")
        if self.lam not in LAMINATE_OPTIONS:
            raise ModelError(f"{where}: lam={self.lam!r} must be one of {LAMINATE_OPTIONS}")
        _positive(self.nsm, f"{where}: nsm", allow_zero=True)
        if self.z0 is not None and not math.isfinite(self.z0):
            raise ModelError(f"{where}: z0={self.z0!r} must be finite")

    @property
    def thickness(self) -> float:
        """Total thickness [m] (a symmetric laminate counts its mirrored plies)."""
        t = sum(p.thickness for p in self.plies)
        return 2 * t if self.lam == "SYM" else t


ShellPropertyLike = Union[ShellProperty, Laminate]


@dataclass(frozen=True)
class ShellGroup:
    """Shell elements sharing a property and a node count.

    ids: (n,) element ids; nodes: (n, 3) triangles or (n, 4) quadrilaterals (node ids, counter-
    clockwise about the element normal); theta: (n,) material angle [deg] from the element x axis
    (Nastran THETA), or material_axis: (n, 3) basic vectors whose projection on the element is the
    material x axis (Nastran MCID's x axis), not both; zoffs: (n,) offset [m] of the reference
    plane from the nodes along the normal; corner_thickness: (n, 3|4) thickness at each node [m]
    or None (the property's); mass: 'lumped' or 'consistent'.
    """

    ids: np.ndarray
    nodes: np.ndarray
    property: ShellPropertyLike
    theta: np.ndarray
    material_axis: np.ndarray | None
    zoffs: np.ndarray
    corner_thickness: np.ndarray | None
    mass: str
    name: str


SHELL_MASS = ("lumped", "consistent")


# Warp of a quad: 2h / sqrt(A), h the corners' distance from their mean plane (through their centroid,
# normal to both diagonals: all four at +-h), A the area projected on it; a warning above this
# (docs/shells.md, "Errors": MacNeal-Harder's twisted beam has 0.049 on its 12 x 2 mesh)
WARP_LIMIT = 0.2


def quad_warp(xyz: np.ndarray) -> np.ndarray:
    """(n,) warp 2h / sqrt(A) of quadrilaterals xyz (n, 4, 3): 0 for a flat one."""
    d = np.cross(xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1])
    twice_area = np.linalg.norm(d, axis=1)
    h = np.abs(np.einsum("ij,ij->i", xyz[:, 0] - xyz.mean(axis=1), d)) / np.maximum(twice_area, 1e-300)
    return 2 * h / np.sqrt(np.maximum(0.5 * twice_area, 1e-300))


def check_shell_geometry(nodes: np.ndarray, xyz: np.ndarray, where: str) -> None:
    """Repeated nodes, zero area, and (quads) non-convex or inverted corners: a ModelError naming
    the first bad element by its nodes; quads warped beyond WARP_LIMIT: a FlexGVTWarning naming the
    most warped. xyz: (n, p, 3) node positions."""
    rep = np.array([len(set(row)) != len(row) for row in nodes.tolist()], bool)
    if rep.any():
        k = int(np.flatnonzero(rep)[0])
        raise ModelError(f"{where}: element {k + 1} (nodes {nodes[k].tolist()}) repeats a node; give distinct "
                         "nodes (a collapsed quad is a triangle: pass it with 3 nodes)")
    p = nodes.shape[1]
    size = np.linalg.norm(xyz - xyz.mean(axis=1, keepdims=True), axis=2).max(axis=1)
    if p == 3:
        normal = np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0])
    else:
        normal = np.cross(xyz[:, 2] - xyz[:, 0], xyz[:, 3] - xyz[:, 1])
    area = 0.5 * np.linalg.norm(normal, axis=1)
    bad = area <= 1e-12 * np.maximum(size, 1e-300) ** 2
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise ModelError(f"{where}: element {k + 1} (nodes {nodes[k].tolist()}) has zero area" +
                         (" or crossing edges (a bow-tie: order the nodes around the element)" if p == 4 else "") +
                         "; move its nodes apart or remove it")
    if p == 4:
        n = normal / (2 * area)[:, None]
        corner = np.stack([np.einsum("ij,ij->i", np.cross(xyz[:, (i + 1) % 4] - xyz[:, i],
                                                          xyz[:, (i + 2) % 4] - xyz[:, (i + 1) % 4]), n)
                           for i in range(4)], axis=1)
        bad = (corner <= 1e-9 * size[:, None] ** 2).any(axis=1)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise ModelError(f"{where}: quadrilateral {k + 1} (nodes {nodes[k].tolist()}) is not convex (an "
                             "inverted or bow-tie corner); order its nodes around the element or split it into "
                             "triangles")
        warp = quad_warp(xyz)
        bad = np.flatnonzero(warp > WARP_LIMIT)
        if len(bad):
            k = int(bad[np.argmax(warp[bad])])
            warnings.warn(f"{where}: {len(bad)} quadrilateral(s) warped beyond 2h/sqrt(A) = {WARP_LIMIT}, the most "
                          f"element {k + 1} (nodes {nodes[k].tolist()}): {warp[k]:.3g}, its corners "
                          f"{warp[k] * math.sqrt(area[k]) / 2:.3g} m off their mean plane. A flat element takes a "
                          "warped quad's mean plane (rigid links to the corners) and loses accuracy as the warp "
                          "grows; refine the mesh there or split the quads into triangles", FlexGVTWarning,
                          stacklevel=3)
