"""A model in one configuration, compiled to arrays: DOF numbering, constraints, and evaluation of
internal forces, consistent tangent, mass and damping at any state.

System assembles over a tuple of element families (fem.families: beams, point masses, cords,
springs), each evaluating its own elements; it keeps what is not an element: fixed and
prescribed DOFs, rigid and interpolation links, linear constraints, nodal loads, the sparsity
pattern and the factorisation cache.

The model's own arrays are compiled once per model revision and shared by every configuration,
so one model is solved in many configurations without copying it.
"""

from __future__ import annotations

import copy
import threading
import weakref
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property

import numba
import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from ..model import Configuration, Model, RodSection, end_properties, parse_dofs
from .assembly import Pattern
from .checks import check_coordinates, check_values
from ._shell_model import ShellArrays, compile_shells
from .beam import BeamData, element_coefficients, element_frames, local_mass_matrices
from .families import (SPRING_CLAMP_RATIO, SPRING_WARN_RATIO, BeamFamily, CordFamily, Cords, CordSegmentFamily,
                       ElementTerms, Family, PointMassFamily, PointMasses, ShellFamily, SpringFamily, Springs,
                       element_dofs)
from .interpolation import InterpolationData, compile_interpolations, fit, geometric_block, jacobian
from .linsolve import CholmodCache
from .rotations import expm_so3, skew, spin, step_nodes

__all__ = ["SPRING_CLAMP_RATIO", "SPRING_WARN_RATIO", "CompiledModel", "Evaluation", "PointMasses", "Springs",
           "System", "compile_model", "group_values"]


@numba.njit(cache=True)
def _scatter_reduced(dofs, values, dof_map, out):  # pragma: no cover - compiled
    """out[dof_map[dofs[e, a]]] += values[e, a] where the DOF is free (dof_map >= 0)."""
    for e in range(dofs.shape[0]):
        for a in range(dofs.shape[1]):
            k = dof_map[dofs[e, a]]
            if k >= 0:
                out[k] += values[e, a]


@dataclass(frozen=True)
class CompiledModel:
    """Arrays of a model independent of any configuration."""

    node_ids: np.ndarray
    xyz: np.ndarray
    beams: BeamData
    beam_local_mass: np.ndarray
    beam_element_ids: np.ndarray
    beam_group_names: np.ndarray
    masses: PointMasses
    springs: Springs
    links: np.ndarray  # (n_nodes,) index of the independent node for dependents, else -1
    link_dofs: np.ndarray  # (n_nodes, 6) bool: DOFs set by a rigid link or an interpolation link
    interp: InterpolationData
    mpc_dependent: np.ndarray  # (c,) full DOF index of each linear constraint's dependent DOF
    mpc_terms: tuple[tuple[np.ndarray, np.ndarray], ...]  # per constraint: (full DOFs, weights) with u_d = w . u
    shells: tuple[ShellArrays, ...] = ()  # quads, then triangles (those present)


# Compiled arrays per model, weakly keyed (an entry lives as long as its model) and tagged with the
# model's revision: the model stays plain data, the cache is fem's own.
_COMPILED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_COMPILED_LOCK = threading.Lock()


def compile_model(model: Model, imperfection: Mapping[int, tuple] | None = None) -> CompiledModel:
    """Compile the model's arrays, cached in fem (weakly keyed by the model) against its revision.
    imperfection: {node id: (dx, dy, dz)} offsets of the stress-free geometry [m] (a configuration's
    imperfect article), compiled and cached beside the perfect one."""
    key = None
    if imperfection:
        key = tuple(sorted((int(k), tuple(map(float, v))) for k, v in imperfection.items()))
    with _COMPILED_LOCK:
        cached = _COMPILED.get(model)
    if cached is not None and cached[0] == model.revision and key in cached[1]:
        return cached[1][key]
    if model.n_nodes == 0:
        raise ModelError(f"model '{model.name}' has no nodes; add nodes and elements first")
    xyz = model.xyz
    if key is not None:
        xyz = xyz.copy()
        nodes = model.index_of([k for k, _ in key], "configuration imperfection")
        xyz[nodes] += np.array([v for _, v in key])
    check_coordinates(model.node_ids, xyz, f"model '{model.name}'")
    nodes, E0, L0, stiff, rhoA, rhoI, lumped, eids, names, arch = [], [], [], [], [], [], [], [], [], []
    lumped_axial = []
    for group in model.beams:
        idx = model.index_of(group.nodes, f"beam group '{group.name}'")
        frames = element_frames(xyz, idx, group.orientation)
        length = np.linalg.norm(xyz[idx[:, 1]] - xyz[idx[:, 0]], axis=1)
        n = len(idx)
        coefficients, mass_per_length, inertia = group_values(group.material, group.section, group.rotary_inertia,
                                                              length)
        stiff.append(coefficients)
        rhoI.append(inertia)
        rhoA.append(mass_per_length)
        lumped.append(np.full(n, group.mass == "lumped"))
        lumped_axial.append(np.full(n, group.mass != "consistent"))
        arch.append(np.full(n, 0.0 if isinstance(group.section, RodSection) else 1.0))
        nodes.append(idx)
        E0.append(frames)
        L0.append(length)
        eids.append(group.ids)
        names.append(np.full(n, group.name, dtype=object))

    def cat(parts, shape):
        return np.concatenate(parts) if parts else np.zeros(shape)

    beams = BeamData(cat(nodes, (0, 2)).astype(np.int64), np.ascontiguousarray(cat(E0, (0, 3, 3))), cat(L0, (0,)),
                     np.ascontiguousarray(cat(stiff, (0, 8))), cat(rhoA, (0, 2)), cat(rhoI, (0, 2, 3)),
                     cat(lumped, (0,)).astype(bool), cat(arch, (0,)), cat(lumped_axial, (0,)).astype(bool))
    links = np.full(model.n_nodes, -1)
    link_dofs = np.zeros((model.n_nodes, 6), bool)
    for link in model.rigid_links:
        deps = model.index_of(list(link.dependents))
        links[deps] = model.index_of([link.independent])[0]
        link_dofs[np.ix_(deps, [int(c) - 1 for c in link.components])] = True
    interp = compile_interpolations(model, xyz)
    link_dofs[interp.reference] |= interp.tied
    mpc_dep, mpc_terms = [], []
    for con in model.constraints:
        idx = model.index_of([t[0] for t in con.terms], "linear constraint")
        dofs = 6 * idx + np.array([t[1] - 1 for t in con.terms])
        coef = np.array([t[2] for t in con.terms], float)
        mpc_dep.append(int(dofs[0]))
        mpc_terms.append((dofs[1:], -coef[1:] / coef[0]))
    mpc_dep = np.array(mpc_dep, int)
    busy = link_dofs.reshape(-1)[mpc_dep]
    if np.any(busy):
        raise ModelError(f"model '{model.name}': a linear constraint's dependent DOF (node "
                         f"{model.node_ids[mpc_dep[busy][0] // 6]}) is already set by a rigid or interpolation link")
    drivers = {6 * model.index_of([link.independent])[0] + k for link in model.rigid_links for k in range(6)}
    drivers |= {6 * int(i) + k for nodes in interp.nodes for i in nodes for k in range(3)}  # translations drive a fit
    used = [d for d in mpc_dep if d in drivers]
    if used:
        raise ModelError(f"model '{model.name}': a linear constraint's dependent DOF is on node "
                         f"{model.node_ids[used[0] // 6]}, which drives a rigid or interpolation link; make another "
                         "DOF of the constraint the dependent one")
    link_dofs.reshape(-1)[mpc_dep] = True
    for dofs, _ in mpc_terms:
        if np.any(link_dofs.reshape(-1)[dofs]):
            raise ModelError(f"model '{model.name}': a linear constraint's independent DOF (node "
                             f"{model.node_ids[dofs[link_dofs.reshape(-1)[dofs]][0] // 6]}) is itself set by a link "
                             "or another constraint; chains are not supported: write the constraint on the "
                             "independent DOFs")
    compiled = CompiledModel(model.node_ids, xyz, beams, local_mass_matrices(beams), cat(eids, (0,)).astype(int),
                             cat(names, (0,)), _masses(model, model.masses), Springs.of(model, model.springs), links,
                             link_dofs, interp, mpc_dep, tuple(mpc_terms), compile_shells(model, xyz))
    with _COMPILED_LOCK:
        entry = _COMPILED.get(model)
        if entry is None or entry[0] != model.revision:
            entry = (model.revision, {})
            _COMPILED[model] = entry
        entry[1][key] = compiled
    return compiled


def group_values(material, section, rotary_inertia: bool, length: np.ndarray):
    """Per-element values of a beam group of lengths ``length`` [m]: kernel coefficients (n, 8) (see
    beam.element_coefficients), mass per length rho A at the first and second node (n, 2) [kg/m]
    and inertia per length (n, 2, 3) (rho Ip, rho Iy, rho Iz at each node; the bending terms zero
    without rotary inertia) [kg m]."""
    pa, pb = end_properties(section)
    E, G, rho = material.E, material.shear_modulus, material.rho
    n = len(length)
    coefficients = element_coefficients(E, G, pa, pb, length)
    rot = 1.0 if rotary_inertia else 0.0
    inertia = np.array([[rho * p["Ip"], rot * rho * p["Iy"], rot * rho * p["Iz"]] for p in (pa, pb)])
    return coefficients, np.tile([rho * pa["A"], rho * pb["A"]], (n, 1)), np.tile(inertia, (n, 1, 1))


def _masses(model: Model, items) -> PointMasses:
    items = list(items)
    if not items:
        return PointMasses.empty()
    return PointMasses(model.index_of([m.node for m in items], "concentrated mass"),
                       np.array([m.mass for m in items]), np.array([m.offset for m in items]),
                       np.array([m.inertia for m in items]))


def _with_points(cm: CompiledModel, xyz: np.ndarray) -> CompiledModel:
    """cm with the points ``xyz`` (p, 3) appended as nodes (ids after the largest) whose rotations are
    held (a distributed cord's interior points: translations only)."""
    from dataclasses import replace
    p = len(xyz)
    start = int(cm.node_ids.max()) + 1 if len(cm.node_ids) else 1
    held = np.zeros((p, 6), bool)
    held[:, 3:] = True
    return replace(cm, node_ids=np.r_[cm.node_ids, start + np.arange(p)], xyz=np.vstack([cm.xyz, xyz]),
                   links=np.r_[cm.links, np.full(p, -1)], link_dofs=np.vstack([cm.link_dofs, held]))


def _same_configuration(a: Configuration, b: Configuration) -> bool:
    """a == b, where items holding arrays (springs, masses) compare element-wise."""
    if a is b:
        return True
    try:
        return bool(a == b)
    except ValueError:  # dataclass equality on array fields
        return False


@dataclass
class Evaluation:
    """Residual pieces and tangent at one state (reduced DOFs)."""

    internal: np.ndarray  # reduced internal-force vector (incl. load potentials of offset masses)
    external: np.ndarray  # reduced applied-load vector at this load factor
    tangent: sp.csc_matrix | None
    outputs: dict  # each family's ElementTerms.output by family name
    blocks: list | None = None  # element tangents, when evaluate(assemble=False) left K unassembled

    @property
    def beam_forces(self) -> np.ndarray:
        """(n_beams, 7) local forces [N, M1, M2] (see beam.beam_forces)."""
        return self.outputs["beam"]

    @property
    def axial_forces(self) -> np.ndarray:
        """(n_beams,) axial forces [N], tension positive."""
        return self.outputs["beam"][:, 0]

    @property
    def cord_tension(self) -> np.ndarray:
        """(n_cords,) [N] at the attachment (a distributed cord's: its member there)."""
        return self._cords(0, "attachment_tension")

    @property
    def cord_length(self) -> np.ndarray:
        """(n_cords,) [m] (a distributed cord's: along its points)."""
        return self._cords(1, "total_length")

    def _cords(self, k: int, field: str) -> np.ndarray:
        out = self.outputs["cord"][k]
        seg = self.outputs.get("cord_segments")
        if seg is None or not len(seg.rows):
            return out
        out = np.array(out, float)
        out[seg.rows] = getattr(seg, field)
        return out


class System:
    """One model in one configuration. Reduced DOFs exclude fixed DOFs and rigid-link dependents."""

    def __init__(self, model: Model, config: Configuration):
        self._set_values(model, config)
        cm, n = self.cm, self.n_nodes
        where = f"configuration '{config.name}'"
        fixed = np.zeros(6 * n, bool)
        for node, spec in config.fixed.items():
            i = model.index_of([node], f"{where}: fixed")[0]
            fixed[6 * i + np.array(parse_dofs(spec, f"{where}: fixed[{node}]"))] = True
        # Prescribed DOFs (enforced displacements) are held like fixed ones, at their ramped values.
        self.prescribed_dofs = np.zeros(0, int)
        self.prescribed_values = np.zeros(0)
        if config.prescribed:
            dofs, vals = [], []
            for node, items in config.prescribed.items():
                i = model.index_of([node], f"{where}: prescribed")[0]
                for comp, value in items.items():
                    dofs.append(6 * i + comp - 1)
                    vals.append(value)
            self.prescribed_dofs, self.prescribed_values = np.array(dofs, int), np.array(vals, float)
            fixed[self.prescribed_dofs] = True
        dependent = cm.links >= 0
        bad = np.flatnonzero((cm.link_dofs & fixed.reshape(n, 6)).any(axis=1))
        if len(bad):
            raise ModelError(f"{where}: node {cm.node_ids[bad[0]]} has DOFs tied by a rigid link (or an interpolation "
                             "link), which cannot be fixed or prescribed; fix its independent node(s) instead")
        # Grounded springs far stiffer than the structure (a clamp modelled as a 1e15 N/m spring) hold
        # their DOFs as constraints: kept as springs they spoil the factorisations (see spring_clamps).
        self._config_fixed = fixed.copy()
        self.spring_clamped = self.spring_clamps(fixed)
        fixed[self.spring_clamped] = True
        self.fixed = fixed
        self.dependent = dependent
        free = ~fixed & ~cm.link_dofs.reshape(-1)
        self.dof_map = np.full(6 * n, -1)
        self.dof_map[free] = np.arange(free.sum())
        self.n_free = int(free.sum())
        self.rotation_mask = (np.arange(6 * n) % 6 >= 3)[free]  # reduced DOFs that are rotations
        if self.n_free == 0:
            raise ModelError(f"{where}: every DOF is fixed; nothing to solve")

        self.has_links = bool(dependent.any()) or len(cm.interp) > 0 or len(cm.mpc_dependent) > 0
        blocks = [element_dofs(family.nodes) for family in self.families]
        self._blocks = blocks
        if self.has_links:
            self.pattern = Pattern(blocks, np.arange(6 * n), 6 * n)
        else:
            self.pattern = Pattern(blocks, self.dof_map, self.n_free)

    def _set_values(self, model: Model, config: Configuration) -> None:
        """The arrays that design variables change (material, section, masses, springs, cords, loads);
        the DOF numbering and the sparsity pattern built on them are left alone."""
        self.model = model
        self.config = config
        cm = compile_model(model, config.imperfection)
        self._revision = model.revision
        gvec = config.gravity_vector
        cords = CordFamily.build(model, config, cm.xyz)
        # Distributed cords: their interior points are this configuration's nodes, after the model's.
        segments = CordSegmentFamily.build(config, cords.cords, cm.xyz)
        distributed = (segments,) if len(segments.w) else ()
        if len(segments.points):
            cm = _with_points(cm, segments.point_xyz)
        self.n_cord_points = len(segments.points)  # each adds 3 modes of the cord's own (surge, string)
        self.cm = cm
        n = len(cm.xyz)
        self.n_nodes = n
        masses = cm.masses.merged(_masses(model, config.masses)).merged(cords.point_masses())
        if distributed:
            masses = masses.merged(segments.point_masses())
        # The families in a fixed order: the pattern's blocks and ValueChange's block indices follow it.
        self.families: tuple[Family, ...] = (
            BeamFamily(cm.beams, cm.beam_local_mass, cm.beam_element_ids, cm.beam_group_names),
            PointMassFamily.build(masses, gvec), cords,
            SpringFamily(cm.springs.merged(Springs.of(model, config.springs)), cm.xyz),
            *(ShellFamily.build(arrays) for arrays in cm.shells), *distributed)
        self._family_index = {family.name: k for k, family in enumerate(self.families)}
        # Applied loads at load factor 1 (fixed direction): the families' (lumped weight, distributed
        # loads, the hanging share of heavy cords), then the nodal loads.
        where = f"configuration '{config.name}'"
        f = np.zeros((n, 6))
        for family in self.families:
            family.add_applied(f, config, gvec)
        for load in config.forces:
            i = model.index_of([load.node], f"{where}: load")[0]
            f[i, :3] += load.force
            f[i, 3:] += load.moment
        self.applied = f.reshape(-1)
        check_values(self)

    # ------------------------------------------------------------------ families
    def family(self, name: str) -> Family:
        """The element family called ``name`` ("beam", "mass", "cord", "spring", "shell4", "shell3")."""
        return self.families[self._family_index[name]]

    @property
    def masses(self) -> PointMasses:
        """The point masses (the model's, the configuration's, then the heavy cords' share)."""
        return self.family("mass").masses

    @property
    def mass_weight(self) -> np.ndarray:
        """(m, 3) weight of each point mass at full load [N]."""
        return self.family("mass").weight

    @property
    def springs(self) -> Springs:
        return self.family("spring").springs

    @property
    def cords(self) -> Cords:
        return self.family("cord").cords

    # The cords' arrays under their former System names (callers outside fem read them).
    cord_nodes = property(lambda self: self.cords.nodes_a)
    cord_nodes_b = property(lambda self: self.cords.nodes_b)
    cord_offset = property(lambda self: self.cords.offset)
    cord_anchor = property(lambda self: self.cords.anchor)
    cord_k = property(lambda self: self.cords.stiffness)
    cord_c = property(lambda self: self.cords.damping)
    cord_l0 = property(lambda self: self.cords.l0)
    cord_w = property(lambda self: self.cords.w)
    cord_lgeom = property(lambda self: self.cords.lgeom)

    def cord_state(self, x: np.ndarray, R: np.ndarray, rows=slice(None)) -> tuple:
        """(x_a, R_a, x_b, R_b) of the cords' two nodes (the same node twice for a cord at a node)."""
        return self.family("cord").state(x, R, rows)

    def cord_l0_at(self, lam: float) -> np.ndarray:
        """Unstretched cord lengths along the load ramp: unstrained at lam = 0, nominal at lam = 1."""
        return self.cords.l0_at(lam)

    def structure_diagonal(self) -> np.ndarray:
        """|diagonal| (6n,) of the undeformed, unloaded tangent of the structural families (beams,
        masses, cords; not springs) over all DOFs [N/m, N m/rad]: the structure's own stiffness at
        each DOF."""
        x, R = self.undeformed
        dofs, vals = [], []
        for family, blk in zip(self.families, self._family_dofs()):
            if family.structural:
                K = family.terms(x, R, 0.0, True).tangent
                dofs.append(blk.reshape(-1))
                vals.append(np.abs(np.diagonal(K, axis1=1, axis2=2)).reshape(-1))
        return np.bincount(np.concatenate(dofs), weights=np.concatenate(vals), minlength=6 * self.n_nodes)

    def _family_dofs(self) -> list[np.ndarray]:
        return [element_dofs(family.nodes) for family in self.families]

    def spring_clamps(self, fixed: np.ndarray) -> np.ndarray:
        """Full DOFs (sorted) that grounded springs hold as constraints (SpringFamily.clamps) against
        the structure's own diagonal stiffness (structure_diagonal)."""
        s = self.springs
        if not np.any(s.stiffness > 0):
            return np.zeros(0, int)
        return self.family("spring").clamps(self.structure_diagonal(), fixed, self.cm.link_dofs, self.cm.node_ids,
                                            f"configuration '{self.config.name}'")

    def _topology(self) -> tuple:
        """What the DOF numbering and the sparsity pattern depend on."""
        return tuple(a for family in self.families for a in family.topology()) + (
            self.cm.links, self.cm.link_dofs, self.cm.interp.reference if len(self.cm.interp) else np.zeros(0, int),
            self.cm.mpc_dependent)

    def for_values(self, model: Model, config: Configuration) -> "System":
        """This system for the same model object (possibly changed since: new material, section,
        mass, spring values) in a configuration of the same topology (other cord or spring values,
        load factors): a sibling sharing the DOF numbering, the sparsity pattern and the symbolic
        factorisation; a new System when the topology changed. Returns self when nothing changed."""
        if model is self.model and model.revision == self._revision and _same_configuration(config, self.config):
            return self
        if model is not self.model or dict(config.fixed) != dict(self.config.fixed) or \
                dict(config.prescribed).keys() != dict(self.config.prescribed).keys():
            return System(model, config)
        sibling = copy.copy(self)
        for cached in ("_applied_reduced", "has_damping"):
            sibling.__dict__.pop(cached, None)
        sibling._set_values(model, config)
        before, after = self._topology(), sibling._topology()
        if len(self.cm.xyz) != len(sibling.cm.xyz) or any(a.shape != b.shape or np.any(a != b)
                                                          for a, b in zip(before, after)):
            return System(model, config)
        if len(sibling.springs.b) and not np.array_equal(sibling.spring_clamps(self._config_fixed),
                                                         self.spring_clamped):
            return System(model, config)  # a spring crossed SPRING_CLAMP_RATIO: other constraints
        if self.has_prescribed:
            sibling.prescribed_values = np.array([v for items in config.prescribed.values() for v in items.values()],
                                                 float)
        return sibling

    # ------------------------------------------------------------------ DOF helpers
    @staticmethod
    def _rigid_motions(x: np.ndarray, centre: np.ndarray) -> np.ndarray:
        """(n, 6, 6): DOF values of the six unit rigid motions about ``centre`` at nodes x."""
        modes = np.zeros((len(x), 6, 6))
        for a in range(3):
            e = np.zeros(3)
            e[a] = 1.0
            modes[:, a, a] = 1.0
            modes[:, :3, 3 + a] = np.cross(e, x - centre)
            modes[:, 3 + a, 3 + a] = 1.0
        return modes

    def unrestrained_rigid_motions(self, x: np.ndarray, *, basis_only: bool = False):
        """Rigid-body motions about the centroid of positions x, (6n, 6), and a basis (6, k) of
        their combinations that the fixed DOFs leave free (k = 0 for a clamped structure);
        basis_only: the basis alone (the motions are built only at the fixed nodes)."""
        c = x.mean(axis=0)
        fixed = self.fixed.reshape(-1, 6)
        at = np.flatnonzero(fixed.any(axis=1))
        fixed_rows = self._rigid_motions(x[at], c)[fixed[at]]
        basis = np.eye(6)
        if len(fixed_rows):
            try:
                _, sv, vt = np.linalg.svd(fixed_rows, full_matrices=True)
            except np.linalg.LinAlgError as exc:  # non-finite coordinates: check_values lets none through
                raise ModelError(f"configuration '{self.config.name}': the rigid-body motions of the fixed nodes "
                                 f"cannot be formed ({exc}); check the node coordinates") from exc
            rank = int(np.sum(sv > 1e-9 * max(sv.max(), 1e-300)))
            basis = vt[rank:].T
        if basis_only:
            return basis
        return self._rigid_motions(x, c).reshape(6 * self.n_nodes, 6), basis

    @cached_property
    def clamped(self) -> bool:
        """The fixed DOFs restrain every rigid-body motion (of the undeformed geometry)."""
        return self.unrestrained_rigid_motions(self.cm.xyz, basis_only=True).shape[1] == 0

    @property
    def has_prescribed(self) -> bool:
        return len(self.prescribed_dofs) > 0

    def impose(self, x: np.ndarray, R: np.ndarray, lam: float) -> tuple[np.ndarray, np.ndarray]:
        """State with the prescribed DOFs at lam times their values: translations from the undeformed
        position, rotations exp(lam phi) with phi the node's prescribed rotation vector (its other
        rotation components are held at zero)."""
        if not self.has_prescribed:
            return x, R
        x, R = x.copy(), R.copy()
        nodes, comps = np.divmod(self.prescribed_dofs, 6)
        tr = comps < 3
        x[nodes[tr], comps[tr]] = self.cm.xyz[nodes[tr], comps[tr]] + lam * self.prescribed_values[tr]
        if np.any(~tr):
            phi = np.zeros((self.n_nodes, 3))
            phi[nodes[~tr], comps[~tr] - 3] = self.prescribed_values[~tr]
            turned = np.unique(nodes[~tr])
            R[turned] = expm_so3(lam * phi[turned])
        return x, R

    @property
    def undeformed(self) -> tuple[np.ndarray, np.ndarray]:
        return self.cm.xyz.copy(), np.broadcast_to(np.eye(3), (self.n_nodes, 3, 3)).copy()

    def link_offsets(self, R: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dependent node indices, their independent nodes and the rotated offsets R_i (X_d - X_i)."""
        deps = np.flatnonzero(self.dependent)
        ind = self.cm.links[deps]
        r0 = self.cm.xyz[deps] - self.cm.xyz[ind]
        return deps, ind, (R[ind] @ r0[:, :, None])[:, :, 0]

    def transformation(self, x: np.ndarray, R: np.ndarray) -> sp.csr_matrix:
        """Full (6n) <- reduced DOF map T at the current state (rigid links rotate with the state)."""
        n = self.n_nodes
        rows, cols, vals = [], [], []
        free = np.flatnonzero(self.dof_map >= 0)
        rows.append(free)
        cols.append(self.dof_map[free])
        vals.append(np.ones(len(free)))
        deps, ind, r = self.link_offsets(R)
        if len(deps):
            # dx_d = dx_i - S(r) w_i ;  w_d = w_i  (rows of the tied components only)
            blocks = np.zeros((len(deps), 6, 6))
            blocks[:, :3, :3] = np.eye(3)
            blocks[:, :3, 3:] = -skew(r)
            blocks[:, 3:, 3:] = np.eye(3)
            blocks *= self.cm.link_dofs[deps][:, :, None]
            rr = (6 * deps[:, None, None] + np.arange(6)[None, :, None]).repeat(6, axis=2)
            cc = self.dof_map[(6 * ind[:, None, None] + np.arange(6)[None, None, :]).repeat(6, axis=1)]
            keep = (cc >= 0) & (blocks != 0)
            rows.append(rr[keep])
            cols.append(cc[keep])
            vals.append(blocks[keep])
        ip = self.cm.interp
        for k in range(len(ip)):
            J = jacobian(x[ip.nodes[k]], ip.weights[k], ip.arms0[k], ip.ref_arm0[k]) * ip.tied[k][:, None]
            rr = np.repeat(6 * ip.reference[k] + np.arange(6), J.shape[1])
            cc = np.tile(self.dof_map[(6 * ip.nodes[k][:, None] + np.arange(3)).ravel()], 6)
            keep = (cc >= 0) & (J.ravel() != 0)
            rows.append(rr[keep])
            cols.append(cc[keep])
            vals.append(J.ravel()[keep])
        for dep, (dofs, weights) in zip(self.cm.mpc_dependent, self.cm.mpc_terms):
            cc = self.dof_map[dofs]
            keep = (cc >= 0) & (weights != 0)
            rows.append(np.full(keep.sum(), dep))
            cols.append(cc[keep])
            vals.append(weights[keep])
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(6 * n, self.n_free))

    def reduce_vector(self, v_full: np.ndarray, T=None) -> np.ndarray:
        """A full force vector (6n,) reduced to the reduced DOFs: T^T f with links (the dependents'
        forces carried to their independent DOFs). For displacements use reduce_displacement."""
        if not self.has_links:
            return v_full[self.dof_map >= 0]
        return T.T @ v_full

    def reduce_displacement(self, u_full: np.ndarray) -> np.ndarray:
        """A full displacement vector (6n, ...) that satisfies the links (a rigid motion, a mode
        shape) as reduced DOFs: its values at the independent free DOFs (expand's inverse)."""
        return u_full[self.dof_map >= 0]

    def expand(self, v_red: np.ndarray, T=None) -> np.ndarray:
        """Reduced DOF vector(s) -> full (6n, ...) with fixed DOFs zero and dependents following."""
        if not self.has_links:
            out = np.zeros((6 * self.n_nodes,) + v_red.shape[1:], dtype=v_red.dtype)
            out[self.dof_map >= 0] = v_red
            return out
        return T @ v_red

    # ------------------------------------------------------------------ evaluation
    @cached_property
    def _scatter_dofs(self) -> np.ndarray:
        return np.concatenate([blk.reshape(-1) for blk in self._blocks])

    def _scatter(self, vectors: list[np.ndarray]) -> np.ndarray:
        """Sum element vectors (one array per block of self._blocks) into a full DOF vector."""
        vals = np.concatenate([v.reshape(-1) for v in vectors])
        return np.bincount(self._scatter_dofs, weights=vals, minlength=6 * self.n_nodes)

    def evaluate(self, x: np.ndarray, R: np.ndarray, lam: float, tangent: bool = True,
                 assemble: bool = True, reference: Evaluation | None = None) -> Evaluation:
        """Internal and applied forces (reduced) and the consistent tangent at a state and load factor.

        assemble=False (no rigid links): the element tangents are kept in ``blocks`` for
        :meth:`newton_matrix` or :meth:`tangent_of` instead of an assembled ``tangent``.
        reference: an evaluation at another state whose beam forces replace the beams' own in the
        stress-dependent part of the tangent (see solve_static's predictor); forces stay exact.
        """
        terms = self._element_terms(x, R, lam, tangent, reference)
        outputs = {family.name: t.output for family, t in zip(self.families, terms)}
        gs = [t.forces for t in terms]
        Ks = [t.tangent for t in terms]
        if not self.has_links:  # straight into the reduced vectors
            internal = np.zeros(self.n_free)
            for dofs, g in zip(self._blocks, gs):
                if len(g):
                    _scatter_reduced(dofs, np.ascontiguousarray(g, dtype=float), self.dof_map, internal)
            blocks = Ks if tangent and not assemble else None
            K = self.pattern.assemble(Ks) if tangent and assemble else None
            return Evaluation(internal, lam * self._applied_reduced, K, outputs, blocks)
        g_full = self._scatter(gs)
        f_full = lam * self.applied
        T = self.transformation(x, R)
        K = None
        if tangent:
            K = self._reduce_with_links(self.pattern.assemble(Ks), T, x, R, g_full - f_full)
        return Evaluation(self.reduce_vector(g_full, T), self.reduce_vector(f_full, T), K, outputs)

    def full_state(self, x: np.ndarray, R: np.ndarray, lam: float) -> tuple:
        """Residual (6n,), consistent tangent and mass matrix over all DOFs, no constraint applied."""
        terms = self._element_terms(x, R, lam, True, None)
        return (self._scatter([t.forces for t in terms]) - lam * self.applied,
                self.full_pattern.assemble([t.tangent for t in terms]), self.full_mass_matrix(x, R))

    def _element_terms(self, x, R, lam, tangent, reference: Evaluation | None) -> list[ElementTerms]:
        """Each family's element terms; reference: an evaluation whose outputs the families use in
        their stress-dependent tangent."""
        return [family.terms(x, R, lam, tangent, None if reference is None else reference.outputs.get(family.name))
                for family in self.families]

    @cached_property
    def _applied_reduced(self) -> np.ndarray:
        return self.applied[self.dof_map >= 0]

    def tangent_of(self, ev: Evaluation) -> sp.csc_matrix:
        """The assembled tangent of an evaluation (assembling its element blocks if needed)."""
        if ev.tangent is None and ev.blocks is not None:
            ev.tangent = self.pattern.assemble(ev.blocks)
        return ev.tangent

    def newton_matrix(self, ev: Evaluation, M: sp.csc_matrix, alpha: float) -> sp.csc_matrix:
        """Symmetric part of the tangent plus alpha M (what Newton's Cholesky factorises); from the
        element blocks in one pass when the evaluation kept them."""
        p = self.pattern
        if ev.tangent is None and ev.blocks is not None and M.nnz == p.nnz:
            return p.matrix(p.add_symmetric(alpha * M.data, ev.blocks))
        return self.stabilised_tangent(self.tangent_of(ev), M, alpha, part="symmetric")

    def factor_newton_matrix(self, ev: Evaluation, M: sp.csc_matrix, alpha: float, cache: CholmodCache):
        """cache.factor(newton_matrix(ev, M, alpha)), the element blocks scattered straight into the
        analysed pattern where the evaluation kept them (see CholmodCache.factor_blocks)."""
        if ev.tangent is None and ev.blocks is not None and M.nnz == self.pattern.nnz:
            return cache.factor_blocks(self.pattern, ev.blocks, M.data, alpha)
        return cache.factor(self.newton_matrix(ev, M, alpha))

    def _reduce_with_links(self, K_full, T, x, R, r_full) -> sp.csc_matrix:
        """T^T K T plus the geometric term of the rotating rigid-link offsets and interpolation fits."""
        K = (T.T @ K_full @ T).tocsc()
        deps, ind, r = self.link_offsets(R)
        fd = r_full.reshape(-1, 6)[deps, :3] * self.cm.link_dofs[deps, :3]  # forces the link carries
        blocks = skew(fd) @ skew(r)  # d(r x f)/d spin of the independent node
        rot = self.dof_map[6 * ind[:, None] + 3 + np.arange(3)]
        rows = np.repeat(rot, 3, axis=1).ravel()
        cols = np.tile(rot, (1, 3)).ravel()
        keep = (rows >= 0) & (cols >= 0)
        extra = sp.csc_matrix((blocks.reshape(-1)[keep], (rows[keep], cols[keep])), shape=K.shape)
        ip = self.cm.interp
        if len(ip):  # the rotating fit of interpolation links carries the reference's load
            rr, cc, vv = [], [], []
            for k in range(len(ip)):
                load = r_full.reshape(-1, 6)[ip.reference[k]] * ip.tied[k]
                if not np.any(load):
                    continue
                G = geometric_block(x[ip.nodes[k]], ip.weights[k], ip.arms0[k], ip.ref_arm0[k], load)
                dofs = self.dof_map[(6 * ip.nodes[k][:, None] + np.arange(3)).ravel()]
                ok = dofs >= 0
                G = G[np.ix_(ok, ok)]
                rr.append(np.repeat(dofs[ok], ok.sum()))
                cc.append(np.tile(dofs[ok], ok.sum()))
                vv.append(G.ravel())
            if rr:
                extra = extra + sp.csc_matrix((np.concatenate(vv), (np.concatenate(rr), np.concatenate(cc))),
                                              shape=K.shape)
        return (K + extra).tocsc()

    def update(self, x: np.ndarray, R: np.ndarray, delta_red: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Apply a reduced increment: translations add, rotations compose by spatial spin."""
        if not self.has_links:
            return step_nodes(x, R, delta_red, self.dof_map)
        T = self.transformation(x, R)
        d = self.expand(delta_red, T).reshape(-1, 6)
        x_new = x + d[:, :3]
        R_new = spin(R, d[:, 3:])
        if self.has_links:
            if len(self.cm.mpc_dependent):  # linear in the translations u = x - X
                u = np.zeros((self.n_nodes, 6))
                u[:, :3] = x_new - self.cm.xyz
                u = u.reshape(-1)
                for dep, (dofs, weights) in zip(self.cm.mpc_dependent, self.cm.mpc_terms):
                    if dep % 6 < 3 and np.all(dofs % 6 < 3):  # exact on total translations; else incremental
                        x_new[dep // 6, dep % 6] = self.cm.xyz[dep // 6, dep % 6] + weights @ u[dofs]
            deps, ind, r = self.link_offsets(R_new)
            tied = self.cm.link_dofs[deps]
            x_new[deps] = np.where(tied[:, :3], x_new[ind] + r, x_new[deps])
            turn = tied[:, 3]
            R_new[deps[turn]] = R_new[ind[turn]]
            ip = self.cm.interp
            for k in range(len(ip)):
                x_ref, Q, _ = fit(x_new[ip.nodes[k]], ip.weights[k], ip.arms0[k], ip.ref_arm0[k])
                ref, tied = ip.reference[k], ip.tied[k]
                x_new[ref] = np.where(tied[:3], x_ref, x_new[ref])
                if tied[3]:
                    R_new[ref] = Q
        return x_new, R_new

    def stabilised_tangent(self, K: sp.csc_matrix, M: sp.csc_matrix, alpha: float,
                           part: str = "full") -> sp.csc_matrix:
        """The matrix Newton factorises, K + alpha M for K and M of this system's evaluate() and
        mass_matrix(): part "full" or "symmetric" (its symmetric part, what a Cholesky factorisation
        reads). Without rigid links K and M live on one pattern and this is elementwise on their
        data.
        """
        p = self.pattern
        if not self.has_links and K.nnz == M.nnz == p.nnz:
            if part == "full":
                return p.matrix(K.data + alpha * M.data)
            return p.symmetric(K.data, M.data, alpha)
        A = (K + alpha * M).tocsc()
        if part == "full":
            return A
        A = (0.5 * (A + A.T)).tocsc()
        A.sort_indices()
        return A

    # ------------------------------------------------------------------ mass and damping
    def mass_matrix(self, x: np.ndarray, R: np.ndarray, frame: str = "deformed") -> sp.csc_matrix:
        """Reduced mass matrix about the state (beam mass in corotated frames, offset masses rotated);
        frame="undeformed": the element and point-mass matrices of the undeformed configuration
        (reduced with the links' state at (x, R)), as Nastran SOL 400 keeps them."""
        values = self._mass_values(x, R) if frame == "deformed" else self._mass_values(*self.undeformed)
        return self._reduce_plain(self.pattern.assemble(values), x, R)

    @cached_property
    def full_pattern(self) -> Pattern:
        """The pattern over all DOFs (constraints not applied)."""
        return self.pattern if self.has_links else Pattern(self._blocks, np.arange(6 * self.n_nodes), 6 * self.n_nodes)

    def full_mass_matrix(self, x: np.ndarray, R: np.ndarray) -> sp.csc_matrix:
        """(6n, 6n) mass matrix about the state over all DOFs (constraints not applied)."""
        return self.full_pattern.assemble(self._mass_values(x, R))

    def _mass_values(self, x, R) -> list[np.ndarray]:
        return [family.mass_values(x, R) for family in self.families]

    def damping_matrix(self, x: np.ndarray, R: np.ndarray) -> sp.csc_matrix:
        """Reduced viscous damping matrix (springs/dampers and cords) about the state."""
        values = [family.damping_values(x, R) for family in self.families]
        return self._reduce_plain(self.pattern.assemble(values), x, R)

    def _reduce_plain(self, A, x, R) -> sp.csc_matrix:
        if not self.has_links:
            return A
        T = self.transformation(x, R)
        return (T.T @ A @ T).tocsc()

    @cached_property
    def cholmod_cache(self) -> CholmodCache:
        """The symbolic Cholesky analysis of this system's pattern, shared by every solve on it
        (Newton iterations, warm-started solves, the modes about its states)."""
        return CholmodCache()

    @cached_property
    def inertia_cache(self) -> CholmodCache:
        """The symbolic analysis of the stability checks' K - s M (fem.stability), kept apart from
        cholmod_cache: that matrix's stored pattern is not the Newton matrix's, and sharing one cache
        re-analysed both at every switch (18 analyses in the 0.25 m wingbox's -1 g solve, 10 apart)."""
        return CholmodCache()

    @cached_property
    def has_damping(self) -> bool:
        return any(family.has_damping for family in self.families)
