"""The model's shell groups compiled into per-element kernel arrays: sections (PSHELL, PCOMP/PCOMPG)
in each element's kernel axes, masses per area, and the corotational constants (linear local
stiffness and mass in the reference corotated frame).

Per element: the thickness is the property's, or the mean of the corner thicknesses (CQUAD4/CTRIA3
T1-T4; the kernels take one section per element, so a tapered element gets its mean thickness:
exact for the membrane and shear stiffness and the mass of a linear taper, and within
(dt/t)^2 / 4 for the bending stiffness); the offset ZOFFS moves the reference plane; the material
angle (THETA from side 1-2, or an MCID axis projected on the element) turns the section into the
element's kernel axes (x along side 1-2 projected on the element's plane). A triangle whose PSHELL
has bending but no MID3 gets no transverse shear stiffness (S = 0): Nastran's rigid transverse
shear, which the triangle's DKMT bending takes as DKT (docs/shells.md, "Triangle bending").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from ..model import Material
from ..model.shells import AnisotropicMaterial, Laminate, OrthotropicMaterial, ShellGroup, ShellProperty
from ._shell_corotational import CorotationalShells, corotational_setup
from ._shell_section import PlaneStress, Ply, ShellSection, mat1, mat2, mat8, pcomp, pshell

INITIAL_STRESS = {4: True, 3: False}  # per corner count: see docs/shells.md, "Initial stress"


@dataclass(frozen=True)
class ShellArrays:
    """All shells of one corner count p (4 quads, 3 triangles): nodes (n, p) storage indices,
    C (n, 8, 8) sections in kernel axes, mass (n, 3) [m0, m1, m2] per area, lumped (n,),
    element_ids (n,), group_names (n,), groups (n,) the group's position in Model.shells, thickness
    (n,) [m], the corotational constants (with the element masses in the reference frame) and
    shell_groups (the model's ShellGroup of each position in Model.shells, for derivatives)."""

    nodes: np.ndarray
    C: np.ndarray
    mass: np.ndarray
    thickness: np.ndarray
    lumped: np.ndarray
    element_ids: np.ndarray
    group_names: np.ndarray
    groups: np.ndarray
    corotational: CorotationalShells
    shell_groups: tuple = ()

    @property
    def p(self) -> int:
        return self.nodes.shape[1]


def plane_stress(material, where: str) -> PlaneStress | None:
    """The kernel material of a model material (MAT1, MAT2, MAT8), None for None."""
    if material is None:
        return None
    if isinstance(material, Material):
        return mat1(material.E, material.G, material.nu, material.rho, where=f"{where} material '{material.name}'")
    if isinstance(material, AnisotropicMaterial):
        m = material
        return mat2(m.G11, m.G12, m.G13, m.G22, m.G23, m.G33, m.rho, where=f"{where} material '{m.name}'")
    if isinstance(material, OrthotropicMaterial):
        m = material
        return mat8(m.E1, m.E2, m.nu12, m.G12, m.G1z, m.G2z, m.rho, where=f"{where} material '{m.name}'")
    raise ModelError(f"{where}: material of type {type(material).__name__} is not a shell material")


def property_section(prop, thickness: float | None, where: str) -> ShellSection:
    """The section of a ShellProperty at ``thickness`` [m] (None: the property's), or of a Laminate."""
    if isinstance(prop, Laminate):
        plies = [Ply(plane_stress(p.material, where), p.thickness, p.theta) for p in prop.plies]
        return pcomp(plies, prop.z0, prop.nsm, prop.lam, where=f"{where} laminate '{prop.name}'")
    if not isinstance(prop, ShellProperty):
        raise ModelError(f"{where}: property of type {type(prop).__name__} is not a shell property")
    t = prop.thickness if thickness is None else thickness
    if t is None:
        raise ModelError(f"{where}: property '{prop.name}' has no thickness and the elements give no corner "
                         "thicknesses; give the property a thickness")
    return pshell(t, plane_stress(prop.membrane, where), plane_stress(prop.bending, where), prop.bending_ratio,
                  plane_stress(prop.shear, where), prop.shear_ratio, prop.nsm, plane_stress(prop.coupling, where),
                  where=f"{where} property '{prop.name}'")


def kernel_frames(X: np.ndarray) -> np.ndarray:
    """(n, 3, 3) the kernels' element frames (columns x, y, z) of corners X (n, p, 3): z along the
    cross product of the diagonals (quad) or the normal (triangle), x along side 1-2 projected on
    the element's plane."""
    if X.shape[1] == 4:
        z = np.cross(X[:, 2] - X[:, 0], X[:, 3] - X[:, 1])
    else:
        z = np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0])
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    s = X[:, 1] - X[:, 0]
    x = s - z * np.sum(s * z, axis=1, keepdims=True)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    return np.stack([x, np.cross(z, x), z], axis=-1)


def _rotation8(angle: np.ndarray) -> np.ndarray:
    """(n, 8, 8) blockdiag(T, T, R) of _shell_section.strain_rotation for each angle [rad]."""
    out = np.zeros((len(angle), 8, 8))
    c, s = np.cos(angle), np.sin(angle)
    T = np.stack([np.stack([c * c, s * s, c * s], -1), np.stack([s * s, c * c, -c * s], -1),
                  np.stack([-2 * c * s, 2 * c * s, c * c - s * s], -1)], 1)
    out[:, :3, :3] = T
    out[:, 3:6, 3:6] = T
    out[:, 6:, 6:] = np.stack([np.stack([c, s], -1), np.stack([-s, c], -1)], 1)
    return out


def group_sections(group: ShellGroup, X: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """C (n, 8, 8) in kernel axes, mass (n, 3) and thickness (n,) [m] of a shell group's elements
    with corners X."""
    n = len(group.ids)
    laminate = isinstance(group.property, Laminate)
    if group.corner_thickness is not None and not laminate:
        t = np.asarray(group.corner_thickness, float).mean(axis=1)
    else:  # a laminate's thickness is its plies' (Nastran ignores T1-T4 for PCOMP)
        t = np.full(n, np.nan)
    z = np.asarray(group.zoffs, float) if group.zoffs is not None else np.zeros(n)
    keys = np.stack([t, z], axis=1)
    uniq, inverse = np.unique(np.nan_to_num(keys, nan=-1.0), axis=0, return_inverse=True)
    inverse = np.asarray(inverse).reshape(-1)
    C = np.zeros((len(uniq), 8, 8))
    mass = np.zeros((len(uniq), 3))
    thickness = np.zeros(len(uniq))
    for k, (tk, zk) in enumerate(uniq):
        sec = property_section(group.property, None if tk < 0 else float(tk), where)
        if zk:
            sec = sec.offset(float(zk))
        C[k, :3, :3], C[k, :3, 3:6], C[k, 3:6, :3], C[k, 3:6, 3:6] = sec.A, sec.B, sec.B.T, sec.D
        C[k, 6:, 6:] = sec.S
        mass[k] = sec.m0, sec.m1, sec.m2
        thickness[k] = sec.thickness
    C, mass, thickness = C[inverse], mass[inverse], thickness[inverse]
    prop = group.property
    if X.shape[1] == 3 and isinstance(prop, ShellProperty) and prop.shear is None and prop.bending is not None:
        C[:, 6:, 6:] = 0.0  # MID3 blank on a triangle: rigid in transverse shear (DKT)
    if group.material_axis is not None:
        frames = kernel_frames(X)
        axis = np.asarray(group.material_axis, float)
        angle = np.arctan2(np.einsum("ni,ni->n", axis, frames[:, :, 1]), np.einsum("ni,ni->n", axis, frames[:, :, 0]))
    else:
        angle = np.radians(np.asarray(group.theta, float)) if group.theta is not None else np.zeros(n)
    if np.any(angle):
        T = _rotation8(angle)
        C = np.einsum("nji,njk,nkl->nil", T, C, T)
    return np.ascontiguousarray(C), np.ascontiguousarray(mass), thickness


def compile_shells(model, xyz: np.ndarray) -> tuple[ShellArrays, ...]:
    """The model's shells as kernel arrays, one ShellArrays per corner count present (quads first)."""
    parts: dict[int, list] = {4: [], 3: []}
    for g, group in enumerate(model.shells):
        where = f"shell group '{group.name}'"
        idx = model.index_of(group.nodes.reshape(-1), where).reshape(group.nodes.shape)
        C, mass, thickness = group_sections(group, xyz[idx], where)
        n = len(idx)
        parts[idx.shape[1]].append((idx, C, mass, thickness, np.full(n, group.mass == "lumped"),
                                    np.asarray(group.ids, int), np.full(n, group.name, dtype=object), np.full(n, g)))
    out = []
    for p in (4, 3):
        if not parts[p]:
            continue
        nodes, C, mass, thickness, lumped, ids, names, groups = (np.concatenate(a) for a in zip(*parts[p]))
        nodes = np.ascontiguousarray(nodes, dtype=np.int64)
        data = corotational_setup(xyz[nodes], C, ids=ids, initial_stress=INITIAL_STRESS[p], mass=mass,
                                  lumped=lumped)
        out.append(ShellArrays(nodes, C, mass, thickness, lumped, ids, names, groups, data, tuple(model.shells)))
    return tuple(out)
