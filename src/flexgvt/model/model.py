"""The structural model: nodes, beams, masses, springs and rigid links. Plain data, no numerics."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Iterable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from .configuration import parse_dofs
from .components import (ConcentratedMass, InterpolationLink, LinearConstraint, RigidLink, Spring, as_vector,
                         find_items)
from .material import Material
from .section import RodSection, Section
from .shells import SHELL_MASS, Laminate, ShellGroup, ShellProperty, ShellPropertyLike, check_shell_geometry

# consistent: cubic bending, linear axial and torsion; lumped: half of everything at each node;
# consistent-bending: cubic bending, axial and torsional mass lumped (MSC Nastran's CBEAM under COUPMASS).
MASS_FORMULATIONS = ("consistent", "lumped", "consistent-bending")


@dataclass(frozen=True)
class BeamGroup:
    """Beam elements sharing a material and section.

    nodes: (n, 2) node ids; orientation: (n, 3) vectors giving the local z axis (the part
    perpendicular to the beam axis); rotary_inertia: include bending rotary inertia
    rho*I (torsional inertia rho*Ip is always kept); mass: one of MASS_FORMULATIONS.
    """

    ids: np.ndarray
    nodes: np.ndarray
    material: Material
    section: Section
    orientation: np.ndarray
    rotary_inertia: bool
    mass: str
    name: str


class Model:
    """A structural model built with ``add_*`` calls. Units: SI.

    Local beam axes: x from the first to the second node, z along the part of ``orientation``
    perpendicular to x, y = z cross x. A RectangularSection's width lies along y, height along z.
    """

    def __init__(self, name: str = "model") -> None:
        self.name = name
        self._node_ids: list[np.ndarray] = []
        self._node_xyz: list[np.ndarray] = []
        self._node_index: dict[int, int] = {}
        self._beams: list[BeamGroup] = []
        self._shells: list[ShellGroup] = []
        self._masses: list[ConcentratedMass] = []
        self._springs: list[Spring] = []
        self._rigid_links: list[RigidLink] = []
        self._interpolations: list[InterpolationLink] = []
        self._constraints: list[LinearConstraint] = []
        self._next_node = 1
        self._next_element = 1
        self.revision = 0  # bumped by every change; solvers cache compiled arrays against it

    # ------------------------------------------------------------------ nodes
    def add_nodes(self, xyz: Sequence[Sequence[float]] | np.ndarray, ids: Iterable[int] | None = None) -> np.ndarray:
        """Add nodes at ``xyz`` [m], shape (n, 3); returns their integer ids."""
        xyz = np.atleast_2d(np.asarray(xyz, dtype=float))
        if xyz.ndim != 2 or xyz.shape[1] != 3:
            raise ModelError(f"add_nodes: xyz must have shape (n, 3), got {xyz.shape}")
        bad = ~np.all(np.isfinite(xyz), axis=1)
        if bad.any():
            raise ModelError(f"add_nodes: coordinates of node(s) at row(s) {np.flatnonzero(bad)[:10].tolist()} "
                             "contain NaN or infinity")
        if ids is None:
            new_ids = np.arange(self._next_node, self._next_node + len(xyz))
        else:
            raw = list(ids)
            bad = [i for i in raw if isinstance(i, bool) or not isinstance(i, (int, np.integer, float, np.floating))
                   or not (math.isfinite(i) and float(i).is_integer() and abs(int(i)) < 2**62)]
            if bad:
                raise ModelError(f"add_nodes: node id {bad[0]!r} is not an integer of magnitude below 2**62; renumber "
                                 "the node")
            new_ids = np.asarray(raw, dtype=np.int64).astype(int)
            if new_ids.shape != (len(xyz),):
                raise ModelError(f"add_nodes: {len(new_ids)} ids for {len(xyz)} nodes")
        if len(np.unique(new_ids)) != len(new_ids):
            raise ModelError("add_nodes: duplicate node ids in the call")
        taken = [i for i in new_ids.tolist() if i in self._node_index]
        if taken:
            raise ModelError(f"add_nodes: node id(s) {taken[:10]} already exist")
        start = self.n_nodes
        for k, nid in enumerate(new_ids.tolist()):
            self._node_index[nid] = start + k
        self._node_ids.append(new_ids)
        self._node_xyz.append(xyz.copy())
        self._next_node = max(self._next_node, int(new_ids.max()) + 1)
        self.revision += 1
        return new_ids.copy()

    @property
    def n_nodes(self) -> int:
        return len(self._node_index)

    @property
    def node_ids(self) -> np.ndarray:
        """(n_nodes,) node ids in storage order."""
        return np.concatenate(self._node_ids) if self._node_ids else np.zeros(0, dtype=int)

    @property
    def xyz(self) -> np.ndarray:
        """(n_nodes, 3) undeformed coordinates [m] in storage order."""
        return np.concatenate(self._node_xyz) if self._node_xyz else np.zeros((0, 3))

    def index_of(self, node_ids: ArrayLike, what: str = "node") -> np.ndarray:
        """Storage indices of node ids; a ModelError names any unknown id."""
        arr = np.asarray(node_ids, dtype=int)
        flat = arr.reshape(-1)
        try:
            out = np.fromiter((self._node_index[i] for i in flat.tolist()), dtype=int, count=flat.size)
        except KeyError as exc:
            raise ModelError(f"{what}: node {exc.args[0]} does not exist in model '{self.name}'") from None
        return out.reshape(arr.shape)

    # ------------------------------------------------------------------ elements
    def add_beams(self, pairs: ArrayLike, material: Material | None, section: Section | None,
                  orientation: ArrayLike = (0.0, 0.0, 1.0), rotary_inertia: bool = True, mass: str = "consistent",
                  name: str = "") -> np.ndarray:
        """Add beam elements between node id ``pairs`` (n, 2); returns element ids.

        section: one section for every element, or a TaperedSection (a section at each element's
        first and second node, linear between them).
        orientation: one vector or (n, 3) vectors fixing local z (see class docstring).
        rotary_inertia: False drops bending rotary inertia (thin-strip reference solutions do);
        torsional inertia rho*Ip is always kept. mass: 'consistent' (cubic bending, linear axial and
        torsion), 'lumped' (half at each node) or 'consistent-bending' (cubic bending, axial and
        torsional mass lumped: MSC Nastran's CBEAM under PARAM,COUPMASS).
        name: a region tag that design variables and reports can refer to.
        """
        if material is None:
            raise ModelError(f"add_beams{f' ({name})' if name else ''}: no material given; pass material=Material(...)")
        if section is None:
            raise ModelError(f"add_beams{f' ({name})' if name else ''}: no section given; pass section=...")
        if mass not in MASS_FORMULATIONS:
            raise ModelError(f"add_beams: mass='{mass}' must be one of {MASS_FORMULATIONS}")
        pairs = np.atleast_2d(np.asarray(pairs, dtype=int))
        if pairs.ndim != 2 or pairs.shape[1] != 2:
            raise ModelError(f"add_beams: pairs must have shape (n, 2), got {pairs.shape}")
        idx = self.index_of(pairs, "add_beams")
        xyz = self.xyz
        axis = xyz[idx[:, 1]] - xyz[idx[:, 0]]
        length = np.linalg.norm(axis, axis=1)
        scale = max(float(np.ptp(xyz, axis=0).max()) if len(xyz) else 1.0, 1e-300)
        short = length <= 1e-9 * scale
        if short.any():
            k = int(np.flatnonzero(short)[0])
            raise ModelError(f"add_beams: element between nodes {pairs[k].tolist()} has zero length; "
                             "merge the nodes or remove the element")
        orient = np.broadcast_to(np.asarray(orientation, dtype=float), (len(pairs), 3)).copy()
        if not np.all(np.isfinite(orient)):
            raise ModelError("add_beams: orientation contains NaN or infinity")
        perp = orient - (np.sum(orient * axis, axis=1) / length**2)[:, None] * axis
        bad = np.linalg.norm(perp, axis=1) <= 1e-6 * np.linalg.norm(orient, axis=1)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise ModelError(f"add_beams: orientation {orient[k].tolist()} is parallel to the element between nodes "
                             f"{pairs[k].tolist()}; give a vector perpendicular to the beam axis")
        ids = np.arange(self._next_element, self._next_element + len(pairs))
        self._next_element += len(pairs)
        self._beams.append(BeamGroup(ids, pairs.copy(), material, section, orient, bool(rotary_inertia), mass, name))
        self.revision += 1
        return ids

    def add_rods(self, pairs: ArrayLike, material: Material | None, area: float, torsion_constant: float = 0.0,
                 mass: str = "lumped", name: str = "") -> np.ndarray:
        """Add rod elements (axial E A and torsion G J, no bending; Nastran CROD/CONROD) between node id
        ``pairs`` (n, 2); returns element ids. Geometrically nonlinear like the beams (a tensioned rod
        has the string stiffness N / L). mass: 'lumped' (m/2 per node, Nastran's default) or
        'consistent' (linear shape functions in all three directions); no rotary inertia.
        """
        pairs = np.atleast_2d(np.asarray(pairs, dtype=int))
        if pairs.ndim != 2 or pairs.shape[1] != 2:
            raise ModelError(f"add_rods: pairs must have shape (n, 2), got {pairs.shape}")
        idx = self.index_of(pairs, "add_rods")
        axis = self.xyz[idx[:, 1]] - self.xyz[idx[:, 0]]
        # Any vector off the rod axis will do (a rod has no bending axes): the global axis least aligned.
        orientation = np.eye(3)[np.argmin(np.abs(axis), axis=1)]
        return self.add_beams(pairs, material, RodSection(area, torsion_constant), orientation=orientation,
                              rotary_inertia=False, mass=mass, name=name)

    def add_shells(self, elements: ArrayLike, property: ShellPropertyLike | None = None, *,
                   material: Material | None = None, thickness: float | None = None, name: str = "",
                   theta: ArrayLike = 0.0, material_axis: ArrayLike | None = None, zoffs: ArrayLike = 0.0,
                   corner_thickness: ArrayLike | None = None, mass: str = "lumped") -> np.ndarray:
        """Add shell elements (Nastran CQUAD4/CTRIA3): ``elements`` (n, 4) quadrilaterals or (n, 3)
        triangles of node ids, counter-clockwise about the normal; returns element ids.

        property: a ShellProperty (PSHELL) or Laminate (PCOMP); or material= and thickness= [m] for
        a solid isotropic plate (ShellProperty.isotropic). theta: material angle [deg] from the
        element x axis (one or (n,)); material_axis: instead, one or (n, 3) basic vectors projected
        on the element (Nastran MCID). zoffs: reference-plane offset [m] along the normal (one or
        (n,)); corner_thickness: (n, p) thickness [m] at each node, >= 0 and not all zero (None: the property's).
        mass: 'lumped' or 'consistent'. name: the group's tag for design variables and reports.
        """
        where = f"add_shells{f' ({name})' if name else ''}"
        if property is None:
            if material is None or thickness is None:
                raise ModelError(f"{where}: give property=ShellProperty(...)/Laminate(...), or material= and "
                                 "thickness=")
            property = ShellProperty.isotropic(material, thickness, name=name)
        elif material is not None or thickness is not None:
            raise ModelError(f"{where}: give either property= or material= and thickness=, not both")
        if not isinstance(property, (ShellProperty, Laminate)):
            raise ModelError(f"{where}: property is a {type(property).__name__}; give a ShellProperty or Laminate")
        if mass not in SHELL_MASS:
            raise ModelError(f"{where}: mass='{mass}' must be one of {SHELL_MASS}")
        try:
            nodes = np.atleast_2d(np.asarray(elements, dtype=np.int64)).astype(int)
        except (TypeError, ValueError, OverflowError):
            raise ModelError(f"{where}: elements must be an (n, 3) or (n, 4) array of node ids") from None
        if nodes.ndim != 2 or nodes.shape[1] not in (3, 4) or not len(nodes):
            raise ModelError(f"{where}: elements must have shape (n, 3) or (n, 4), got {nodes.shape}")
        n, p = nodes.shape
        idx = self.index_of(nodes, where)
        check_shell_geometry(nodes, self.xyz[idx], where)

        def per_element(value, shape, what, positive=False):
            try:
                arr = np.broadcast_to(np.asarray(value, dtype=float), shape).copy()
            except (TypeError, ValueError):
                raise ModelError(f"{where}: {what} must be one value or one per element, shape {shape}") from None
            if not np.all(np.isfinite(arr)) or (positive and np.any(arr <= 0)):
                k = int(np.flatnonzero(~np.isfinite(arr) | (positive & (arr <= 0))).min() // max(arr[0].size, 1))
                raise ModelError(f"{where}: {what} of element {k + 1} (nodes {nodes[k].tolist()}) is "
                                 f"{arr[k].tolist()}; it must be finite{' and positive' if positive else ''}")
            return arr

        th = per_element(theta, (n,), "theta")
        axis = None
        if material_axis is not None:
            if np.any(th != 0):
                raise ModelError(f"{where}: give theta or material_axis, not both")
            axis = per_element(material_axis, (n, 3), "material_axis")
            if np.any(np.linalg.norm(axis, axis=1) == 0):
                raise ModelError(f"{where}: material_axis has a zero vector; give a direction")
        z = per_element(zoffs, (n,), "zoffs")
        corners = None if corner_thickness is None else per_element(corner_thickness, (n, p), "corner_thickness")
        if corners is not None and (np.any(corners < 0) or np.any(corners.max(axis=1) <= 0)):
            # Nastran's T1-T4 are >= 0: a tapered edge (HA145E's plate) has zero thickness at its corners
            k = int(np.flatnonzero(np.any(corners < 0, axis=1) | (corners.max(axis=1) <= 0))[0])
            raise ModelError(f"{where}: corner_thickness of element {k + 1} (nodes {nodes[k].tolist()}) is "
                             f"{corners[k].tolist()}; each must be >= 0 and at least one positive")
        if corners is None and property.thickness is None:
            raise ModelError(f"{where}: property '{property.name}' has no thickness; give corner_thickness or a "
                             "thickness on the property")
        ids = np.arange(self._next_element, self._next_element + n)
        self._next_element += n
        self._shells.append(ShellGroup(ids, nodes.copy(), property, th, axis, z, corners, mass, name))
        self.revision += 1
        return ids

    def add_mass(self, node: int, mass: float, offset: ArrayLike = (0.0, 0.0, 0.0), inertia: ArrayLike | None = None,
                 name: str = "",
                 id: int | None = None) -> ConcentratedMass:
        """Concentrated mass [kg] at ``offset`` [m] from ``node``; inertia: scalar, (3,) or (3, 3) [kg m^2];
        name, id: optional, unique among the model's masses (design variables address masses by them)."""
        self.index_of([node], "add_mass")
        self._check_key(self._masses, name, id, f"add_mass at node {node}")
        if not np.isfinite(mass) or mass < 0:
            raise ModelError(f"add_mass at node {node}: mass={mass!r} must be finite and >= 0")
        J = np.zeros((3, 3)) if inertia is None else np.asarray(inertia, dtype=float)
        if J.ndim == 0:
            J = float(J) * np.eye(3)
        elif J.shape == (3,):
            J = np.diag(J)
        if J.shape != (3, 3) or not np.all(np.isfinite(J)) or not np.allclose(J, J.T):
            raise ModelError(f"add_mass at node {node}: inertia must be a finite symmetric 3x3 tensor")
        item = ConcentratedMass(int(node), float(mass), as_vector(offset, 3, f"add_mass at node {node}: offset"), J,
                                str(name), None if id is None else int(id))
        self._masses.append(item)
        self.revision += 1
        return item

    def add_spring(self, node_a: int, node_b: int | None = None, stiffness: ArrayLike = 0.0, damping: ArrayLike = 0.0,
                   frame: ArrayLike | None = None, name: str = "", id: int | None = None,
                   tables=None) -> Spring:
        """6-component spring/damper between two nodes, or to ground when node_b is None (see Spring);
        name, id: optional, unique among the model's springs (design variables address springs by them);
        tables: force-deflection tables of nonlinear components ({component 1..6: SpringTable})."""
        self.index_of([node_a] + ([] if node_b is None else [node_b]), "add_spring")
        self._check_key(self._springs, name, id, f"add_spring at node {node_a}")
        item = Spring.make(node_a, node_b, stiffness, damping, frame, name, id, tables)
        self._springs.append(item)
        self.revision += 1
        return item

    def add_rigid_link(self, independent: int, dependents: Iterable[int], components: str = "123456") -> RigidLink:
        """The ``components`` of ``dependents`` follow ``independent`` rigidly (see RigidLink)."""
        deps = tuple(int(d) for d in dependents)
        self.index_of([independent, *deps], "add_rigid_link")
        dofs = parse_dofs(components, "add_rigid_link: components")
        rotations = {d for d in dofs if d >= 3}
        if rotations and rotations != {3, 4, 5}:
            raise ModelError(f"add_rigid_link: components {components!r} tie some rotations but not all three; "
                             "finite rotations about single axes are not defined. Tie 456 or none of them")
        if independent in deps:
            raise ModelError(f"add_rigid_link: node {independent} cannot depend on itself")
        taken = {d for link in self.rigid_links for d in link.dependents}
        clash = [d for d in deps if d in taken or any(d == link.independent for link in self.rigid_links)]
        if clash:
            raise ModelError(f"add_rigid_link: node(s) {clash} already belong to another rigid link; merge the links")
        if any(independent in link.dependents for link in self.rigid_links):
            raise ModelError(f"add_rigid_link: independent node {independent} is a dependent of another link")
        item = RigidLink(int(independent), deps, "".join(str(d + 1) for d in dofs))
        self._rigid_links.append(item)
        self.revision += 1
        return item

    def add_interpolation(self, reference: int, nodes: Iterable[int], weights: ArrayLike = 1.0,
                          components: str = "123456") -> InterpolationLink:
        """``reference`` follows the weighted best-fit rigid motion of ``nodes`` (RBE3, see InterpolationLink)."""
        nodes = tuple(int(n) for n in nodes)
        where = f"add_interpolation(reference={reference})"
        self.index_of([reference, *nodes], where)
        if len(set(nodes)) != len(nodes) or reference in nodes or not nodes:
            raise ModelError(f"{where}: give distinct nodes, at least one, not including the reference")
        w = as_vector(weights, len(nodes), f"{where}: weights")
        if np.any(w <= 0):
            raise ModelError(f"{where}: weights must be positive, got {w.tolist()}")
        dofs = parse_dofs(components, f"{where}: components")
        if set(dofs) not in ({0, 1, 2}, {0, 1, 2, 3, 4, 5}):
            raise ModelError(f"{where}: components must be '123456' or '123', got {components!r}")
        xyz = self.xyz[self.index_of(list(nodes))]
        c = w @ xyz / w.sum()
        r = xyz - c
        J = np.einsum("i,ij,ik->jk", w, r, r)
        ev = np.linalg.eigvalsh(np.trace(J) * np.eye(3) - J)
        size = max(np.abs(r).max(), 1e-300)
        if ev[0] <= 1e-9 * max(ev[-1], 1e-300):
            # Nodes on one line (or one node): the rotation about the line is not defined. A
            # reference on the line moving with its translations only is still defined.
            arm = self.xyz[self.index_of([reference])[0]] - c
            line = np.linalg.eigh(J)[1][:, -1] if np.abs(r).max() > 0 else np.zeros(3)
            off_line = np.linalg.norm(arm - (arm @ line) * line)
            if 3 in dofs or off_line > 1e-9 * max(size, np.linalg.norm(arm), 1e-300):
                raise ModelError(f"{where}: the nodes lie on one line (or coincide), so the fitted rotation about it "
                                 "is not defined; add a node off the line, or tie only the translations (components="
                                 "'123') of a reference on the line")
        linked = {n for link in self.rigid_links for n in (link.independent, *link.dependents)}
        refs = {i.reference for i in self._interpolations}
        ins = {n for i in self._interpolations for n in i.nodes}
        if reference in linked | refs | ins or any(n in linked - {l.independent for l in self.rigid_links} or
                                                   n in refs for n in nodes):
            raise ModelError(f"{where}: the reference may not be part of a rigid link or another interpolation, and "
                             "the nodes may not be rigid-link dependents or references; connect the structural nodes")
        item = InterpolationLink(int(reference), nodes, w, "".join(str(d + 1) for d in dofs))
        self._interpolations.append(item)
        self.revision += 1
        return item

    def add_constraint(self, terms: Iterable[tuple[int, int, float]]) -> LinearConstraint:
        """Linear constraint sum a_j u_j = 0 (Nastran MPC, see LinearConstraint); terms: [(node,
        component 1-6, coefficient), ...] in basic axes, the first one's DOF is eliminated."""
        where = "add_constraint"
        items = []
        for term in terms:
            try:
                node, comp, coef = int(term[0]), int(term[1]), float(term[2])
            except (TypeError, ValueError, IndexError):
                raise ModelError(f"{where}: each term is (node, component, coefficient), got {term!r}") from None
            if comp not in (1, 2, 3, 4, 5, 6):
                raise ModelError(f"{where}: component {comp} of node {node} must be 1-6")
            if not np.isfinite(coef):
                raise ModelError(f"{where}: coefficient of node {node} component {comp} is not finite")
            items.append((node, comp, coef))
        if not items or items[0][2] == 0.0:
            raise ModelError(f"{where}: the first (dependent) term needs a non-zero coefficient")
        self.index_of([t[0] for t in items], where)
        keys = [(n, c) for n, c, _ in items]
        if len(set(keys)) != len(keys):
            raise ModelError(f"{where}: a DOF appears twice in one constraint: merge its coefficients")
        dependents = {c.terms[0][:2] for c in self._constraints}
        if keys[0] in dependents:
            raise ModelError(f"{where}: node {keys[0][0]} component {keys[0][1]} is already the dependent DOF of "
                             "another constraint")
        item = LinearConstraint(tuple(items))
        self._constraints.append(item)
        self.revision += 1
        return item

    # ------------------------------------------------------------------ values (design variables)
    def set_beam_group(self, index: int, material: Material | None = None, section: Section | None = None,
                       mass: str | None = None) -> None:
        """Give beam group ``index`` (position in ``beams``) another material and/or section of the
        same kind, and/or another mass formulation (the elements and their connectivity stay)."""
        group = self._beams[index]
        if section is not None and type(section) is not type(group.section):
            raise ModelError(f"beam group '{group.name}': a {type(group.section).__name__} cannot become a "
                             f"{type(section).__name__}")
        if mass is not None and mass not in MASS_FORMULATIONS:
            raise ModelError(f"beam group '{group.name}': mass='{mass}' must be one of {MASS_FORMULATIONS}")
        self._beams[index] = replace(group, material=group.material if material is None else material,
                                     section=group.section if section is None else section,
                                     mass=group.mass if mass is None else mass)
        self.revision += 1

    def set_shell_group(self, index: int, property: ShellPropertyLike | None = None,
                        mass: str | None = None) -> None:
        """Give shell group ``index`` (position in ``shells``) another property of the same kind
        (ShellProperty or Laminate) and/or mass formulation; the elements stay."""
        group = self._shells[index]
        if property is not None and type(property) is not type(group.property):
            raise ModelError(f"shell group '{group.name}': a {type(group.property).__name__} cannot become a "
                             f"{type(property).__name__}")
        if property is not None and property.thickness is None and group.corner_thickness is None:
            raise ModelError(f"shell group '{group.name}': property '{property.name}' has no thickness")
        if mass is not None and mass not in SHELL_MASS:
            raise ModelError(f"shell group '{group.name}': mass='{mass}' must be one of {SHELL_MASS}")
        self._shells[index] = replace(group, property=group.property if property is None else property,
                                      mass=group.mass if mass is None else mass)
        self.revision += 1

    def shell_group(self, name: str) -> int:
        """Position in ``shells`` of the group named ``name``; ModelError when none or several."""
        found = [k for k, g in enumerate(self._shells) if g.name == name]
        if len(found) != 1:
            raise ModelError(f"model '{self.name}': {len(found)} shell groups are named '{name}' (named: "
                             f"{sorted({g.name for g in self._shells})[:10]}); give a unique group name")
        return found[0]

    def set_mass(self, index: int, mass: float | None = None, offset: ArrayLike | None = None) -> None:
        """Change concentrated mass ``index`` (position in ``masses``): its mass [kg] and/or offset [m]."""
        item = self._masses[index]
        m = item.mass if mass is None else float(mass)
        if not np.isfinite(m) or m < 0:
            raise ModelError(f"concentrated mass at node {item.node}: mass={mass!r} must be finite and >= 0")
        off = item.offset if offset is None else as_vector(offset, 3, f"concentrated mass at node {item.node}: offset")
        self._masses[index] = replace(item, mass=m, offset=off)
        self.revision += 1

    def set_spring(self, index: int, stiffness: ArrayLike | None = None, damping: ArrayLike | None = None) -> None:
        """Change spring ``index`` (position in ``springs``): its 6 stiffnesses and/or dampings."""
        item = self._springs[index]
        self._springs[index] = Spring.make(item.node_a, item.node_b,
                                           item.stiffness if stiffness is None else stiffness,
                                           item.damping if damping is None else damping, item.frame, item.name,
                                           item.id, item.tables)
        self.revision += 1

    @staticmethod
    def _check_key(items: list, name: str, id: int | None, where: str) -> None:
        if name and any(m.name == name for m in items):
            raise ModelError(f"{where}: the name '{name}' is taken; give each mass or spring its own name")
        if id is not None and any(m.id == int(id) for m in items):
            raise ModelError(f"{where}: the id {id} is taken; give each mass or spring its own id")

    def find(self, kind: str, key: str | int) -> list[int]:
        """Positions in ``masses`` or ``springs`` (kind 'mass' or 'spring') of the items named ``key``
        (a name or an fnmatch pattern, 'S*LE') or with id ``key`` (an integer); ModelError when none."""
        return find_items(self.masses if kind == "mass" else self.springs, key, f"model '{self.name}'", kind)

    def copy(self, name: str | None = None) -> "Model":
        """An independent copy (components are immutable and shared)."""
        new = Model(self.name if name is None else name)
        for attr, value in vars(self).items():
            if isinstance(value, list):
                setattr(new, attr, list(value))
            elif isinstance(value, dict):
                setattr(new, attr, dict(value))
            elif attr != "name":
                setattr(new, attr, value)
        return new

    # Read-only views: every change goes through add_* or set_* so solvers' caches see it.
    @property
    def beams(self) -> tuple[BeamGroup, ...]:
        return tuple(self._beams)

    @property
    def shells(self) -> tuple[ShellGroup, ...]:
        """Shell element groups (solvers that do not assemble shells must refuse a model with any)."""
        return tuple(self._shells)

    @property
    def masses(self) -> tuple[ConcentratedMass, ...]:
        return tuple(self._masses)

    @property
    def springs(self) -> tuple[Spring, ...]:
        return tuple(self._springs)

    @property
    def rigid_links(self) -> tuple[RigidLink, ...]:
        return tuple(self._rigid_links)

    @property
    def interpolations(self) -> tuple[InterpolationLink, ...]:
        return tuple(self._interpolations)

    @property
    def constraints(self) -> tuple[LinearConstraint, ...]:
        return tuple(self._constraints)

    @property
    def n_beams(self) -> int:
        return sum(len(g.ids) for g in self.beams)

    @property
    def n_shells(self) -> int:
        return sum(len(g.ids) for g in self._shells)

    def __repr__(self) -> str:
        return (f"Model('{self.name}': {self.n_nodes} nodes, {self.n_beams} beams, "
                + (f"{self.n_shells} shells, " if self._shells else "") + f"{len(self.masses)} masses, "
                f"{len(self.springs)} springs, {len(self.rigid_links)} rigid links)")
