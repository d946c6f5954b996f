"""Shell sections: membrane, coupling, bending and transverse-shear stiffness of a plate property.

A section relates the resultants per unit length to the generalised strains of the reference
surface (engineering shear strains, element axes):

    [N]   [A  B] [eps  ]        N = [Nx, Ny, Nxy] [N/m],   eps   = [ex, ey, gxy]
    [M] = [B  D] [kappa],       M = [Mx, My, Mxy] [N m/m], kappa = [kx, ky, kxy] [1/m]
    Q = S gamma,                Q = [Qxz, Qyz]  [N/m],     gamma = [gxz, gyz]

with kx = d(beta_x)/dx etc., beta the rotations of the normal (u = u0 + z beta_x). Masses per unit
area: m0 = int rho dz + NSM [kg/m^2], m1 = int rho z dz [kg/m], m2 = int rho z^2 dz [kg] (z from the
reference plane: a shell offset ZOFFS or a laminate's Z0 enters through m1 and B).

PSHELL (Nastran semantics): A = T G1, D = (12I/T^3) T^3/12 G2, S = (TS/T) T G3, B = T^2 G4 (MID4)
plus the offset terms; G1..G4 the plane-stress matrices of MID1..MID4 (MAT1 or MAT2). PCOMP/PCOMPG:
classical lamination theory over MAT8 plies.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError

SHEAR_FACTOR = 5.0 / 6.0  # Nastran's default TS/T, and the laminate's shear correction factor


@dataclass(frozen=True)
class PlaneStress:
    """A material in plane stress: Q (3, 3) [Pa] on [ex, ey, gxy], G (2, 2) [Pa] transverse shear on
    [gxz, gyz] (material axes), density rho [kg/m^3]."""

    Q: np.ndarray
    G: np.ndarray
    rho: float = 0.0


@dataclass(frozen=True)
class ShellSection:
    """Stiffness and mass of a shell section per unit area (see the module docstring)."""

    A: np.ndarray  # (3, 3) membrane [N/m]
    B: np.ndarray  # (3, 3) membrane-bending coupling [N]
    D: np.ndarray  # (3, 3) bending [N m]
    S: np.ndarray  # (2, 2) transverse shear [N/m]
    m0: float  # mass per area incl. NSM [kg/m^2]
    m1: float = 0.0  # first mass moment about the reference plane [kg/m]
    m2: float = 0.0  # rotary inertia per area [kg]
    thickness: float = 0.0  # total thickness [m]
    extra: dict = field(default_factory=dict, compare=False)  # provenance (card fields), not used

    def offset(self, z: float) -> "ShellSection":
        """The section about a reference plane at -z from its own (the mid-surface lies at +z from
        the nodes: Nastran's ZOFFS). Strains at the mid-surface are eps + z kappa."""
        A, B, D = self.A, self.B, self.D
        return ShellSection(A, B + z * A, D + z * (B + B.T) + z * z * A, self.S, self.m0,
                            self.m1 + z * (self.m0 - self.extra.get("nsm", 0.0)),
                            self.m2 + 2 * z * self.m1 + z * z * (self.m0 - self.extra.get("nsm", 0.0)),
                            self.thickness, dict(self.extra, zoffs=z))

    def rotated(self, angle: float) -> "ShellSection":
        """The section in axes turned by -angle [rad]: for a material whose axis 1 lies at
        ``angle`` from the element x axis (Nastran THETA)."""
        T, R = strain_rotation(angle)
        return ShellSection(T.T @ self.A @ T, T.T @ self.B @ T, T.T @ self.D @ T, R.T @ self.S @ R,
                            self.m0, self.m1, self.m2, self.thickness, self.extra)


def strain_rotation(angle: float) -> tuple[np.ndarray, np.ndarray]:
    """(T, R): material-axis strains from element-axis strains, eps_mat = T eps_el (engineering
    shear), gamma_mat = R gamma_el, for material axis 1 at ``angle`` [rad] from element x."""
    c, s = np.cos(angle), np.sin(angle)
    T = np.array([[c * c, s * s, c * s], [s * s, c * c, -c * s], [-2 * c * s, 2 * c * s, c * c - s * s]])
    R = np.array([[c, s], [-s, c]])
    return T, R


def mat1(E: float | None, G: float | None = None, nu: float | None = None, rho: float = 0.0,
         where: str = "MAT1") -> PlaneStress:
    """Isotropic material from two (or three) of E, G, nu as Nastran's MAT1 completes them; with all
    three the shear term is G (Nastran keeps the given G)."""
    given = sum(v is not None for v in (E, G, nu))
    if given < 2 and not (given == 1 and E is not None):
        raise ModelError(f"{where}: give at least two of E, G, NU (or E alone, NU = 0)")
    if E is None:
        E = 2 * (1 + nu) * G
    if G is None:
        G = E / (2 * (1 + (nu or 0.0)))
    if nu is None:
        nu = E / (2 * G) - 1
    if E <= 0 or G <= 0 or not -1 < nu < 0.5:
        raise ModelError(f"{where}: E = {E:g}, G = {G:g}, NU = {nu:g} is not a stable isotropic material "
                         "(E > 0, G > 0, -1 < NU < 0.5): correct the card")
    f = E / (1 - nu * nu)
    Q = np.array([[f, nu * f, 0.0], [nu * f, f, 0.0], [0.0, 0.0, G]])
    return PlaneStress(Q, G * np.eye(2), rho)


def mat2(G11, G12, G13, G22, G23, G33, rho: float = 0.0, where: str = "MAT2") -> PlaneStress:
    """Anisotropic plane-stress material (MAT2). Used as MID3 its transverse-shear matrix is
    [[G11, G12], [G12, G22]] (Nastran's reading of a MAT2 for shear)."""
    Q = np.array([[G11, G12, G13], [G12, G22, G23], [G13, G23, G33]], float)
    if np.linalg.eigvalsh(Q)[0] < 0:
        raise ModelError(f"{where}: the matrix [G11..G33] is not positive semi-definite: correct the card")
    return PlaneStress(Q, np.array([[G11, G12], [G12, G22]], float), rho)


def mat8(E1, E2, nu12, G12, G1z=None, G2z=None, rho: float = 0.0, where: str = "MAT8") -> PlaneStress:
    """Orthotropic ply in its own axes (MAT8); G1z, G2z blank: G12 (as Nastran's default for shear)."""
    if E1 <= 0 or E2 <= 0 or G12 <= 0:
        raise ModelError(f"{where}: E1 = {E1:g}, E2 = {E2:g}, G12 = {G12:g} must be positive: correct the card")
    nu21 = nu12 * E2 / E1
    den = 1 - nu12 * nu21
    if den <= 0:
        raise ModelError(f"{where}: NU12 = {nu12:g} with E1/E2 = {E1 / E2:g} gives 1 - nu12 nu21 <= 0: "
                         "not a stable ply")
    Q = np.array([[E1 / den, nu12 * E2 / den, 0.0], [nu12 * E2 / den, E2 / den, 0.0], [0.0, 0.0, G12]])
    G1z = G12 if G1z is None else G1z
    G2z = G12 if G2z is None else G2z
    return PlaneStress(Q, np.diag([G1z, G2z]).astype(float), rho)


def pshell(T: float, mid1: PlaneStress | None, mid2: PlaneStress | None = None, bmir: float = 1.0,
           mid3: PlaneStress | None = None, tst: float = SHEAR_FACTOR, nsm: float = 0.0,
           mid4: PlaneStress | None = None, where: str = "PSHELL") -> ShellSection:
    """Section of a Nastran PSHELL: T thickness [m], bmir = 12I/T^3, tst = TS/T, nsm [kg/m^2].

    MID2 blank: membrane only (no bending, no transverse shear). MID3 blank with MID2 given: Nastran
    takes the plate rigid in transverse shear; the section uses the shear of MID2 times TS/T instead
    (the difference is of order (T/L)^2, and an infinite shear stiffness would lock MITC4 on
    distorted meshes). Mass: rho of MID1 (else MID2) times T plus NSM."""
    if not np.isfinite(T) or T <= 0:
        raise ModelError(f"{where}: thickness T = {T!r} must be positive: give the shell a thickness")
    if mid1 is None and mid2 is None:
        raise ModelError(f"{where}: neither MID1 nor MID2 is given: the shell has no stiffness")
    if bmir <= 0 or tst <= 0:
        raise ModelError(f"{where}: 12I/T^3 = {bmir:g} and TS/T = {tst:g} must be positive")
    z3 = np.zeros((3, 3))
    A = T * mid1.Q if mid1 is not None else z3.copy()
    D = bmir * T**3 / 12 * mid2.Q if mid2 is not None else z3.copy()
    B = T * T * mid4.Q if mid4 is not None else z3.copy()
    if mid2 is None:
        S = np.zeros((2, 2))
    else:
        S = tst * T * (mid3.G if mid3 is not None else mid2.G)
    rho = mid1.rho if mid1 is not None else mid2.rho
    return ShellSection(A, B, D, S, rho * T + nsm, 0.0, rho * T**3 / 12 if mid2 is not None else 0.0, T,
                        {"nsm": nsm, "card": where})


@dataclass(frozen=True)
class Ply:
    """One ply of a laminate: material in ply axes, thickness [m], angle [deg] of axis 1 from the
    element (or material) x axis."""

    material: PlaneStress
    thickness: float
    theta: float = 0.0


def pcomp(plies: list[Ply], z0: float | None = None, nsm: float = 0.0, lam: str = "",
          shear_factor: float = SHEAR_FACTOR, where: str = "PCOMP") -> ShellSection:
    """Laminate section by classical lamination theory (PCOMP/PCOMPG; plies bottom to top).

    z0: distance from the reference plane to the bottom surface [m] (blank: -thickness/2).
    lam: "" (all plies given) or "SYM" (the plies given are the bottom half of a symmetric stack).
    A = sum Qb_k (z_k - z_k-1), B = sum Qb_k (z_k^2 - z_k-1^2)/2, D = sum Qb_k (z_k^3 - z_k-1^3)/3
    with Qb_k the ply stiffness in element axes. Transverse shear: shear_factor times the
    thickness-sum of the rotated ply shear moduli (first-order theory; Nastran's PCOMP shear from
    the bending stress distribution differs for strongly heterogeneous stacks)."""
    lam = (lam or "").strip().upper()
    if lam not in ("", "SYM"):
        raise ModelError(f"{where}: LAM = {lam!r} is not supported (blank or SYM): "
                         "list every ply explicitly")
    if not plies:
        raise ModelError(f"{where}: the laminate has no plies: give at least one ply (MID, T, THETA)")
    stack = list(plies) + (list(reversed(plies)) if lam == "SYM" else [])
    for k, p in enumerate(stack):
        if not np.isfinite(p.thickness) or p.thickness <= 0:
            raise ModelError(f"{where}: ply {k + 1} has thickness {p.thickness!r}: ply thicknesses must be positive")
    total = sum(p.thickness for p in stack)
    z = (-total / 2 if z0 is None else z0) + np.concatenate([[0.0], np.cumsum([p.thickness for p in stack])])
    A, B, D, S = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((2, 2))
    m0 = m1 = m2 = 0.0
    for k, p in enumerate(stack):
        T, R = strain_rotation(np.radians(p.theta))
        Qb = T.T @ p.material.Q @ T
        Gb = R.T @ p.material.G @ R
        za, zb = z[k], z[k + 1]
        A += Qb * (zb - za)
        B += Qb * (zb**2 - za**2) / 2
        D += Qb * (zb**3 - za**3) / 3
        S += Gb * (zb - za)
        rho = p.material.rho
        m0 += rho * (zb - za)
        m1 += rho * (zb**2 - za**2) / 2
        m2 += rho * (zb**3 - za**3) / 3
    return ShellSection(A, B, D, shear_factor * S, m0 + nsm, m1, m2, total,
                        {"nsm": nsm, "card": where, "z": z})


def section_arrays(sections: list[ShellSection], index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-element arrays for the kernels: C (n, 8, 8) = [[A, B, 0], [B^T, D, 0], [0, 0, S]] and
    mass (n, 3) = [m0, m1, m2], element e taking sections[index[e]]."""
    C = np.zeros((len(sections), 8, 8))
    mass = np.zeros((len(sections), 3))
    for k, s in enumerate(sections):
        C[k, :3, :3] = s.A
        C[k, :3, 3:6] = s.B
        C[k, 3:6, :3] = s.B.T
        C[k, 3:6, 3:6] = s.D
        C[k, 6:, 6:] = s.S
        mass[k] = s.m0, s.m1, s.m2
    index = np.asarray(index)
    return np.ascontiguousarray(C[index]), np.ascontiguousarray(mass[index])
