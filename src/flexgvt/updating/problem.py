"""The updating problem: a design point -> every configuration's equilibrium and modes, paired
with the measured ones -> residual vector, objective, constraints and their exact Jacobians.

One working copy of the model is set to each design point; each configuration keeps its compiled
system (DOF numbering, sparsity pattern, symbolic factorisation) and its last equilibrium as the
next solve's warm start.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment

from ..errors import ConvergenceError, ModelError, SingularModelError, SolverError
from ..fem import Modes, solve_static
from ..fem.massprops import rigid_body_basis, system_mass_properties
from ..fem.eigen import modal_frequencies_hz, real_modes
from ..fem.system import System
from ..model import Configuration, Model
from ..correlation.mac import realise
from ..modal import ModalSet
from ..fem.beam_basis import beam_basis
from .._threads import serial_blas
from ..fem.sensitivity import value_derivative
from .derivatives import (eigenvalue_derivatives, eigenvector_derivatives, modal_terms,
                          shared_changes, state_derivatives, value_change)
from .targets import MassTarget, Measured, Objective
from .variables import Parametrisation, Variable

EXTRA_MODES = 6  # analysed beyond the measured ones, so a mode that moves up or down is still found


class DesignPointFailure(SolverError):
    """A configuration could not be solved at a design point (the optimiser backs off)."""


@dataclass
class Block:
    """One configuration's rows: residuals and constraints (c >= 0) with their Jacobians."""

    residuals: np.ndarray
    names: list[str]
    constraints: np.ndarray
    constraint_names: list[str]
    jacobian: np.ndarray | None = None
    constraint_jacobian: np.ndarray | None = None


@dataclass
class ConfigurationPoint:
    """One configuration at one design point."""

    name: str
    state: object
    eigenvalues: np.ndarray  # (n_analysed,) [rad^2/s^2]
    frequencies_hz: np.ndarray  # (n_analysed,)
    phi: np.ndarray  # (n_free, n_analysed) reduced, mass-normalised
    paired: np.ndarray  # (n_measured,) analytical mode index, -1 unpaired
    mac: np.ndarray  # (n_measured,) MAC of each pair (nan without shapes)
    mac_matrix: np.ndarray | None  # (n_measured, n_analysed)
    sensor_shapes: np.ndarray | None  # (n_analysed, n_sensors)
    static: np.ndarray  # (n_static,) computed static deflections
    K: sp.csc_matrix | None = None  # symmetric tangent the modes solve
    M: sp.csc_matrix | None = None
    tangent: sp.csc_matrix | None = None  # full tangent at the equilibrium
    block: "Block | None" = None  # this configuration's residuals, constraints and their Jacobians
    _labels: tuple[str, ...] | None = None

    @property
    def labels(self) -> tuple[str, ...]:
        """Labels (OOP/IP/T, rigid-body names) of the analysed modes."""
        if self._labels is None:
            self._labels = tuple(self.modes().labels)
        return self._labels

    def summary(self) -> dict:
        """What a remote evaluation sends back (no state, no matrices)."""
        return {"name": self.name, "eigenvalues": self.eigenvalues, "frequencies_hz": self.frequencies_hz,
                "paired": self.paired, "mac": self.mac, "mac_matrix": self.mac_matrix, "static": self.static,
                "labels": self.labels, "block": self.block}

    @classmethod
    def from_summary(cls, d: dict) -> "ConfigurationPoint":
        return cls(d["name"], None, d["eigenvalues"], d["frequencies_hz"], None, d["paired"], d["mac"],
                   d["mac_matrix"], None, d["static"], block=d["block"], _labels=d["labels"])

    def modes(self) -> Modes:
        """The analysed modes as fem Modes (full shapes about the state)."""
        system = self.state.system
        T = system.transformation(self.state.positions, self.state.rotations) if system.has_links else None
        shapes = system.expand(self.phi, T).T.reshape(len(self.eigenvalues), system.n_nodes, 6)
        from ..fem.labels import label_modes
        return label_modes(Modes(self.frequencies_hz, np.zeros(len(self.eigenvalues)), self.frequencies_hz.copy(),
                                 shapes, system.cm.node_ids, eigenvalues=self.eigenvalues, state=self.state))


@dataclass
class Point:
    """Everything computed at one design point."""

    x: np.ndarray
    residuals: np.ndarray
    residual_names: list[str]
    configurations: dict[str, ConfigurationPoint]
    mass_properties: object
    jacobian: np.ndarray | None = None
    constraints: np.ndarray = field(default_factory=lambda: np.zeros(0))
    constraint_names: list[str] = field(default_factory=list)
    constraint_jacobian: np.ndarray | None = None
    unpaired: dict[str, list[int]] = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def objective(self) -> float:
        return float(self.residuals @ self.residuals)


class UpdatingProblem:
    """Design variables, configurations and their measured data, and the objective.

    model: the initial model (never changed); configurations: every configuration with test data;
    measured: one Measured per configuration; variables: design variables; mass_target: measured
    mass properties; objective: weights and limits; n_modes: modes analysed per configuration
    (default: measured + 6); static_settings: for the nonlinear static solves.
    """

    def __init__(self, model: Model, configurations, measured, variables, mass_target: MassTarget | None = None,
                 objective: Objective | None = None, n_modes: int | None = None, static_settings=None,
                 follow_sensors: bool = True):
        configurations = list(configurations)
        measured = list(measured)
        names = [c.name for c in configurations]
        if len(set(names)) != len(names):
            raise ModelError(f"updating: configuration names must be unique, got {names}")
        for m in measured:
            if not isinstance(m, Measured):
                raise ModelError("updating: give measured data as flexgvt.updating.Measured "
                                 "(or Measured.from_modal_set)")
            if m.configuration not in names:
                raise ModelError(f"updating: measured data for configuration '{m.configuration}', which is not among "
                                 f"the configurations {names}; name the configuration it was measured in")
        by_name = {m.configuration: m for m in measured}
        if len(by_name) != len(measured):
            raise ModelError("updating: two measured data sets for one configuration; merge them")
        missing = [n for n in names if n not in by_name]
        if missing:
            raise ModelError(f"updating: configuration(s) {missing} have no measured data; give their data or leave "
                             "them out (they can still be predicted from the updated model)")
        self.model = model
        self.configurations = configurations
        self.measured = by_name
        self.par = Parametrisation(model, configurations, variables)
        self.objective = objective or Objective()
        self.mass_target = mass_target
        self.n_modes = n_modes
        self.static_settings = static_settings
        self.follow_sensors = follow_sensors
        self.work = model.copy(f"{model.name} (updating)")
        self._work_at = None  # (x, configurations) the working model is set to
        self.states: dict[str, object] = {}
        # Pairing reference without measured shapes: per configuration, the paired analytical shapes
        # at the point where its frequencies fitted best so far, and that fit.
        self._tracking: dict[str, tuple[float, np.ndarray]] = {}
        self._mass_system = System(self.work, Configuration("mass properties"))
        self._cache: dict[bytes, Point] = {}
        self.workers: list | None = None  # Dask actors evaluating the configurations (updating.parallel)
        self.n_solves = 0
        self.n_gradients = 0
        for m in measured:
            for (node, comp) in m.static:
                self.work.index_of([node], f"static deflection of configuration '{m.configuration}'")
                if not 1 <= int(comp) <= 6:
                    raise ModelError(f"static deflection ({node}, {comp}) of configuration '{m.configuration}': the "
                                     "component must be 1-6")

    def __getstate__(self) -> dict:
        """Pickled as its definition (for a worker process): states, caches and systems stay behind."""
        return {"args": (self.model, self.configurations, list(self.measured.values()), list(self.par.variables),
                         self.mass_target, self.objective, self.n_modes, self.static_settings, self.follow_sensors)}

    def __setstate__(self, state: dict) -> None:
        self.__init__(*state["args"])

    # ------------------------------------------------------------------ pairing reference
    def reference_of(self, point: "Point") -> dict:
        """What reproduces ``point`` when it is evaluated again: the pairing references (its paired
        analytical shapes) and its equilibria as warm starts (solved afresh from the undeformed
        shape, a far design point may not converge where continuation along the run did)."""
        out = {"pairing": {}, "states": {}}
        for name, c in point.configurations.items():
            if c.phi is not None and self.measured[name].shapes is None:
                out["pairing"][name] = (-np.inf, c.phi[:, np.maximum(c.paired, 0)])
            if c.state is not None:
                out["states"][name] = c.state
        return out

    def set_pairing_reference(self, reference: dict) -> None:
        """Pair from now on against ``reference`` (from reference_of) and warm-start from its states;
        cached points are dropped, as their pairing may differ."""
        self._tracking = dict(reference.get("pairing", {}))
        self.states.update(reference.get("states", {}))
        self._cache.clear()

    @property
    def x0(self) -> np.ndarray:
        return np.ones(len(self.par))

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, x: np.ndarray, gradient: bool = False) -> Point:
        """The point at x (cached: the residuals and the Jacobian of one x are computed once)."""
        x = self.par.check(x)
        key = x.tobytes()
        hit = self._cache.get(key)
        if hit is not None and (hit.jacobian is not None or not gradient):
            return hit
        t0 = time.perf_counter()
        if hit is not None and not self.workers:  # the states are at hand: only the Jacobian is missing
            self._set_work(x)
            point = self._assemble(x, hit.configurations, True)
            point.seconds = hit.seconds + time.perf_counter() - t0
            self._cache[key] = point
            return point
        try:
            configs = self._set_work(x)
        except ModelError as exc:  # e.g. a negative modulus from an unbounded step
            raise DesignPointFailure(f"design point outside the physical range: {exc}") from exc
        if self.workers:
            points = self._remote(x, gradient)
        else:
            points = {cfg.name: self._solve(configs[cfg.name]) for cfg in self.configurations}
        point = self._assemble(x, points, gradient)
        point.seconds = time.perf_counter() - t0
        if len(self._cache) > 8:
            self._cache.clear()
        self._cache[key] = point
        return point

    def _set_work(self, x: np.ndarray) -> dict[str, Configuration]:
        """Set the working model to x (left alone when it is there already: an unchanged revision
        keeps its compiled arrays) and return the configurations at x."""
        if self._work_at is not None and np.array_equal(self._work_at[0], x):
            return self._work_at[1]
        self._work_at = None  # a failed apply may leave the model half set
        configs = self.par.apply(self.work, x)
        self._work_at = (x.copy(), configs)
        return configs

    def _remote(self, x: np.ndarray, gradient: bool) -> dict[str, ConfigurationPoint]:
        """Every configuration evaluated by its worker at once (they run in parallel)."""
        futures = [w.evaluate(x, gradient) for w in self.workers]
        out = {}
        for cfg, fut in zip(self.configurations, futures):
            d = fut.result()
            if "failure" in d:
                raise DesignPointFailure(d["failure"])
            self.n_solves += 1
            out[cfg.name] = ConfigurationPoint.from_summary(d)
        return out

    def _solve(self, config: Configuration) -> ConfigurationPoint:
        name = config.name
        start = self.states.get(name)
        try:
            state = solve_static(self.work, config, settings=self.static_settings, start=start)
        except (ConvergenceError, SingularModelError) as exc:
            raise DesignPointFailure(f"configuration '{name}' did not converge at this design point: {exc}") from exc
        self.n_solves += 1
        system = state.system
        x, R = state.positions, state.rotations
        ev = system.evaluate(x, R, state.load_factor)
        tangent = ev.tangent.tocsc()
        K = (0.5 * (tangent + tangent.T)).tocsc()
        M = system.mass_matrix(x, R)
        meas = self.measured[name]
        n = self.n_modes or len(meas.frequencies_hz) + EXTRA_MODES
        n = min(n, system.n_free - 1)
        try:
            lam, phi = real_modes(K, M, n, None, system.clamped, system.cholmod_cache)
        except Exception as exc:  # ARPACK or factorisation failure at this design point
            raise DesignPointFailure(f"configuration '{name}': the eigen-solution failed at this design point "
                                     f"({exc})") from exc
        T = system.transformation(x, R) if system.has_links else None
        f = modal_frequencies_hz(lam, K, M, system, x, T)  # rigid-body modes at 0 Hz, as solve_modes
        self.states[name] = state
        sensors = meas.sensors
        shapes_s = seen = None
        if meas.shapes is not None:
            S = sensors.matrix(state.node_ids, state, follow=self.follow_sensors)
            shapes_s = np.asarray(S @ system.expand(phi, T)).T
        elif meas.observed_by is not None:
            S = meas.observed_by.matrix(state.node_ids, state, follow=self.follow_sensors)
            amp = np.linalg.norm(np.asarray(S @ system.expand(phi, T)), axis=0)
            best = amp[f > 0].max(initial=0.0)
            seen = amp >= meas.visibility * best if best > 0 else None
        paired, mac, macm = self._pair(name, meas, f, phi, shapes_s, M, seen)
        static = np.array([state.displacements[state.node(node), int(c) - 1] for (node, c) in meas.static])
        return ConfigurationPoint(name, state, lam, f, phi, paired, mac, macm, shapes_s, static, K, M, tangent)

    def _pair(self, name, meas: Measured, f, phi, shapes_s, M, seen=None):
        """Measured -> analytical pairing: by MAC with the measured shapes (frequency as tie-break,
        a floor below which a measured mode stays unpaired); without shapes, by MAC with a reference
        (so modes that cross stay paired), and at the first point by frequency (least squares on log
        frequency among the modes the sensors see, when ``seen`` is given). The reference is the
        paired analytical shapes of the design point where this configuration's frequencies fitted
        best so far: an optimiser's rejected trial steps do not move it, so the pairing at a point
        does not depend on the order in which points were tried."""
        elastic = f > 0
        fm = meas.frequencies_hz
        closeness = np.abs(np.log(np.where(f[None, :] > 0, f[None, :], 1e-300) / fm[:, None]))
        if shapes_s is not None:
            from ..correlation import pair
            got = pair(ModalSet(fm, shapes=meas.shapes), ModalSet(f, shapes=shapes_s),
                       mac_floor=self.objective.mac_floor, max_frequency_ratio=self.objective.max_frequency_ratio)
            paired = np.full(len(fm), -1)
            paired[got.measured] = got.analytical
            mac = np.full(len(fm), np.nan)
            mac[got.measured] = got.mac
            return paired, mac, got.mac_matrix
        best, previous = self._tracking.get(name, (np.inf, None))
        if previous is not None and previous.shape[0] == phi.shape[0]:
            weighted = M @ phi
            num = (previous.T @ weighted) ** 2
            den = np.einsum("ij,ij->j", previous, M @ previous)[:, None] * np.einsum("ij,ij->j", phi, weighted)[None, :]
            score = num / np.where(den > 0, den, 1.0)
            score[:, ~elastic] = -1.0
            rows, cols = linear_sum_assignment(-score)
            paired = np.full(len(fm), -1)
            paired[rows] = cols
        else:
            usable = elastic if seen is None else elastic & seen
            # Squared: the sum of |log| is the same for every assignment of a cluster lying on one
            # side of the measured frequencies, so the order would be left to round-off.
            cost = np.where(usable[None, :], closeness ** 2, 1e6)
            rows, cols = linear_sum_assignment(cost)
            paired = np.full(len(fm), -1)
            paired[rows] = cols
        ok = paired >= 0
        fit = float(np.mean(closeness[np.flatnonzero(ok), paired[ok]] ** 2)) if ok.all() else np.inf
        if previous is None or fit < best:
            self._tracking[name] = (fit, phi[:, np.maximum(paired, 0)])
        return paired, np.full(len(fm), np.nan), None

    def _mass_props(self):
        system = self._mass_system = self._mass_system.for_values(self.work, self._mass_system.config)
        x, R = system.undeformed
        return system_mass_properties(system, x, R)

    def _mass_vector(self, mp) -> tuple[np.ndarray, list[str], np.ndarray]:
        """Mass residuals (relative errors), their names and reference scales."""
        t = self.mass_target
        w = self.objective
        vals, names, refs = [], [], []
        if t is None:
            return np.zeros(0), [], np.zeros(0)
        if t.mass is not None:
            vals.append(w.mass * (mp.mass - t.mass) / t.mass)
            names.append("mass")
            refs.append(t.mass)
        if t.cg is not None:
            for a, c0 in zip("xyz", t.cg):
                scale = abs(c0) if abs(c0) > 0 else t.cg_scale
                vals.append(w.cg * (mp.cg["xyz".index(a)] - c0) / scale)
                names.append(f"cg_{a}")
                refs.append(scale)
        if t.inertia is not None:
            for a, i0 in zip(("xx", "yy", "zz"), t.inertia):
                vals.append(w.inertia * (mp.inertia["xyz".index(a[0]), "xyz".index(a[0])] - i0) / i0)
                names.append(f"I{a}")
                refs.append(i0)
        return np.array(vals), names, np.array(refs)

    @serial_blas  # small dense products between kernel calls: a second BLAS thread only waits
    def _assemble(self, x, points: dict[str, ConfigurationPoint], gradient: bool) -> Point:
        """Every configuration's block (computed here unless a remote evaluation brought it) and the
        mass-property rows, in one residual vector and one constraint vector."""
        changes = shared_changes(self.par, self.work, x) if gradient else None
        for cfg in self.configurations:
            p = points[cfg.name]
            if p.block is None or (gradient and p.block.jacobian is None):
                p.block = self._block(x, p, gradient, changes)
        mp = self._mass_props()
        mres, mnames, _ = self._mass_vector(mp)
        blocks = [points[c.name].block for c in self.configurations]
        mcon, mcon_names = self._mass_constraints(mp)
        point = Point(x.copy(), np.concatenate([b.residuals for b in blocks] + [mres]),
                      [n for b in blocks for n in b.names] + mnames, points, mp,
                      constraints=np.concatenate([b.constraints for b in blocks] + [mcon]),
                      constraint_names=[n for b in blocks for n in b.constraint_names] + mcon_names,
                      unpaired={c.name: np.flatnonzero(points[c.name].paired < 0).tolist()
                                for c in self.configurations})
        if gradient:
            nv = len(self.par)
            dmp = self._mass_derivatives(x, changes)
            point.jacobian = np.vstack([b.jacobian for b in blocks] + [dmp])
            crows = [b.constraint_jacobian for b in blocks]
            if len(mcon):
                rel_d = dmp / self._mass_weights()[:, None]
                crows += [np.vstack([row for r in rel_d for row in (-r[None, :], r[None, :])])]
            point.constraint_jacobian = np.vstack(crows) if crows else np.zeros((0, nv))
            self.n_gradients += 1
        return point

    def _block(self, x: np.ndarray, p: ConfigurationPoint, gradient: bool, changes: list | None = None) -> Block:
        """Residuals (frequencies, 1 - MAC, static deflections), constraints (MAC >= mac_min) and,
        with gradient, their exact Jacobian rows for one configuration."""
        w = self.objective
        name, meas = p.name, self.measured[p.name]
        fm = meas.frequencies_hz
        ok = p.paired >= 0
        idx = np.maximum(p.paired, 0)
        fa = p.frequencies_hz[idx]
        wf = self._frequency_weights(meas)
        use_mac = meas.shapes is not None and w.mac > 0
        use_static = bool(meas.static) and w.static > 0
        use_mac_min = meas.shapes is not None and w.mac_min is not None
        use_xor = meas.shapes is not None and w.orthogonality > 0
        res = [np.where(ok, w.frequency * wf * (fa - fm) / fm, 0.0)]
        names = [f"{name}: f{i + 1}" for i in range(len(fm))]
        if use_mac:
            res.append(np.where(ok, w.mac * (1.0 - np.nan_to_num(p.mac)), 0.0))
            names += [f"{name}: 1-MAC{i + 1}" for i in range(len(fm))]
        if use_static:
            ref = np.array(list(meas.static.values()))
            scale = np.maximum(np.abs(ref), 1e-3)
            res.append(w.static * (p.static - ref) / scale)
            names += [f"{name}: static {k}" for k in meas.static]
        if use_xor:  # over all measured modes, so the vector keeps its length if a pair is lost
            pi = np.flatnonzero(ok)
            full = np.zeros((len(fm), len(fm)))
            full[np.ix_(pi, pi)] = _cross_orthogonality(realise(meas.shapes[pi]), p.sensor_shapes[p.paired[pi]]) \
                - np.eye(len(pi))
            res.append(w.orthogonality * full.ravel())
            names += [f"{name}: XOR[{a + 1},{b + 1}]" for a in range(len(fm)) for b in range(len(fm))]
        con, con_names = np.zeros(0), []
        if use_mac_min:
            con = np.where(ok, np.nan_to_num(p.mac) - w.mac_min, 0.0)
            con_names = [f"{name}: MAC{i + 1} >= {w.mac_min}" for i in range(len(fm))]
        block = Block(np.concatenate(res), names, con, con_names)
        if not gradient:
            return block
        d = state_derivatives(self.par, self.work, x, p.state, p.tangent, changes=changes)
        need_vectors = use_mac or use_mac_min or use_xor
        terms = modal_terms(d, p.state, p.phi[:, idx], p.eigenvalues[idx], need_vectors)
        forms = d.quadratic(p.phi[:, idx])
        dlam = eigenvalue_derivatives(p.eigenvalues[idx], p.phi[:, idx], d, terms, forms)
        df = dlam / (8 * np.pi**2 * np.where(fa > 0, fa, 1.0))[:, None]
        rows = [np.where(ok[:, None], (w.frequency * wf / fm)[:, None] * df, 0.0)]
        shapes = self._shape_derivatives(p, meas, d, dlam, terms, forms[1], mac_only=not use_xor) \
            if need_vectors else None
        dmac = self._mac_derivatives(meas, shapes, mac_only=not use_xor) if (use_mac or use_mac_min) else None
        if use_mac:
            rows.append(np.where(ok[:, None], -w.mac * dmac, 0.0))
        if use_static:
            rows.append(w.static * self._static_derivatives(p, meas, d) / scale[:, None])
        if use_xor:
            pi = np.flatnonzero(ok)
            A = np.column_stack([shapes[i][0] for i in pi])
            dA = np.stack([shapes[i][1] for i in pi], axis=1)  # (n_sensors, n_pairs, n_var)
            full = np.zeros((len(fm), len(fm), len(self.par)))
            full[np.ix_(pi, pi)] = _cross_orthogonality_derivative(realise(meas.shapes[pi]), A, dA).reshape(
                len(pi), len(pi), -1)
            rows.append(w.orthogonality * full.reshape(len(fm) ** 2, -1))
        block.jacobian = np.vstack(rows)
        block.constraint_jacobian = np.where(ok[:, None], dmac, 0.0) if use_mac_min else np.zeros((0, len(self.par)))
        return block

    def _frequency_weights(self, meas: Measured) -> np.ndarray:
        """1, or (median relative scatter / relative scatter) of each mode when standard deviations are given."""
        if not self.objective.use_std or meas.frequency_std_hz is None or not np.any(meas.frequency_std_hz > 0):
            return np.ones(len(meas.frequencies_hz))
        rel = meas.frequency_std_hz / meas.frequencies_hz
        floor = np.median(rel[rel > 0])
        return floor / np.maximum(rel, floor * 0.1)

    def _mass_constraints(self, mp) -> tuple[np.ndarray, list[str]]:
        """Mass properties within +-mass_limits (relative), as c >= 0."""
        w = self.objective
        if w.mass_limits is None or self.mass_target is None:
            return np.zeros(0), []
        rel, mnames, _ = self._mass_vector(mp)
        rel = rel / self._mass_weights()
        vals = [v for r in rel for v in (w.mass_limits - r, w.mass_limits + r)]
        names = [n for m in mnames for n in (f"{m} <= +{w.mass_limits:g}", f"{m} >= -{w.mass_limits:g}")]
        return np.array(vals), names

    def _mass_weights(self) -> np.ndarray:
        t, w = self.mass_target, self.objective
        out = []
        if t.mass is not None:
            out.append(w.mass)
        if t.cg is not None:
            out += [w.cg] * 3
        if t.inertia is not None:
            out += [w.inertia] * 3
        return np.where(np.array(out) > 0, np.array(out), 1.0)

    # ------------------------------------------------------------------ Jacobian pieces
    def _shape_derivatives(self, p: ConfigurationPoint, meas: Measured, d, dlam, terms=None, dmass=None,
                           mac_only: bool = False) -> dict:
        """{measured mode i: (a, da)}: the paired analytical shape at the sensors (n_sensors,) and its
        derivative (n_sensors, n_var), the shape moving with p (Nelson) and the sensors turning with
        the structure; mac_only: da is the MAC's derivative (1, n_var) instead, by the adjoint of
        the MAC's gradient with respect to the shape (two solves per mode whatever the number of
        variables)."""
        system = p.state.system
        T = system.transformation(p.state.positions, p.state.rotations) if system.has_links else None
        S = meas.sensors.matrix(p.state.node_ids, p.state, follow=self.follow_sensors)
        S = (S @ T).tocsr() if T is not None else S[:, np.flatnonzero(system.dof_map >= 0)]  # on reduced DOFs
        turn = self.follow_sensors and np.any(d.du)
        if turn:  # the sensors turn with their nodes as the state moves with p
            rows = meas.sensors.rows(p.state.node_ids)
            spins = system.expand(d.du, T).reshape(system.n_nodes, 6, -1)[rows, 3:]  # (n_sensors, 3, n_var)
        out = {}
        for i, j in enumerate(p.paired):
            if j < 0:
                continue
            phi = p.phi[:, j]
            a = S @ phi
            g = _mac_gradient(meas.shapes[i], a)[None, :] if mac_only else None
            da = eigenvector_derivatives(p.K, p.M, p.eigenvalues[j], phi, dlam[i], d, terms, mode=i,
                                         dmass=None if dmass is None else dmass[i],
                                         project=S if g is None else np.asarray(S.T @ g[0])[None, :])
            if turn:
                turning = np.einsum("sc,sck->sk", meas.sensors.turning(p.state.node_ids, p.state,
                                                                        system.expand(phi, T)), spins)
                da += turning if g is None else g @ turning
            out[i] = (a, da)
        return out

    def _mac_derivatives(self, meas: Measured, shapes: dict, mac_only: bool = False) -> np.ndarray:
        """(n_measured, n_var) dMAC/dp of each pair from the analytical shapes' derivatives (or the
        MAC's own with mac_only)."""
        out = np.zeros((len(meas.frequencies_hz), len(self.par)))
        for i, (a, da) in shapes.items():
            out[i] = da.reshape(-1) if mac_only else _mac_gradient(meas.shapes[i], a) @ da
        return out

    def _static_derivatives(self, p: ConfigurationPoint, meas: Measured, d) -> np.ndarray:
        system = p.state.system
        T = system.transformation(p.state.positions, p.state.rotations) if system.has_links else None
        du = system.expand(d.du, T).reshape(system.n_nodes, 6, -1)
        rows = [du[p.state.node(node), int(c) - 1] for (node, c) in meas.static]
        return np.array(rows)

    def _mass_derivatives(self, x: np.ndarray, changes=None) -> np.ndarray:
        """d(mass residuals)/dp from the exact derivative of the undeformed mass matrix, projected on
        the rigid-body motions (the moments m, m cg, I are linear in it); beam variables through
        the element mass blocks per unit value (fem.beam_basis), all at once."""
        if self.mass_target is None:
            return np.zeros((0, len(self.par)))
        design = changes if changes is not None else shared_changes(self.par, self.work, x)
        system = self._mass_system
        X, I3 = system.undeformed
        phi = rigid_body_basis(X)
        rb = np.zeros((len(self.par), 6, 6))
        if design.batched.any():
            basis = beam_basis(system, X, I3, 0.0, design.rows, design.local_units(system.cm.beams), stiffness=False)
            forms = basis.bilinear_mass(basis.element_values(phi))  # (8 k, 6, 6)
            rb += np.asarray(design.DM.T @ forms.reshape(len(forms), 36)).reshape(-1, 6, 6)
        for k in np.flatnonzero(~design.batched):
            change = design.changes[k] if design.changes[k] is not None else \
                value_change(self.par, self.work, x, k, system.config.name)
            dM = value_derivative(system, X, I3, 0.0, change, full_mass=True)[2]
            rb[k] = phi.T @ (dM @ phi)
        return self._mass_chain(np.column_stack([_moments(m) for m in rb]))

    def _mass_chain(self, dmom: np.ndarray) -> np.ndarray:
        """From d(moments) to d(residuals) at the current mass properties."""
        t, w = self.mass_target, self.objective
        mp = self._mass_props()
        m, c = mp.mass, mp.cg
        dm, dS, dI0 = dmom[0], dmom[1:4], dmom[4:7]
        dc = (dS - c[:, None] * dm[None, :]) / m
        # I_cg,aa = I0_aa - m (|c|^2 - c_a^2)
        dIcg = dI0 - (dm[None, :] * (np.sum(c * c) - c * c)[:, None]
                      + m * (2 * (c @ dc)[None, :] - 2 * c[:, None] * dc))
        rows = []
        if t.mass is not None:
            rows.append(w.mass * dm / t.mass)
        if t.cg is not None:
            for a, c0 in enumerate(t.cg):
                rows.append(w.cg * dc[a] / (abs(c0) if abs(c0) > 0 else t.cg_scale))
        if t.inertia is not None:
            for a, i0 in enumerate(t.inertia):
                rows.append(w.inertia * dIcg[a] / i0)
        return np.array(rows)


def _mac_gradient(m: np.ndarray, a: np.ndarray) -> np.ndarray:
    """(n_sensors,) d MAC(m, a) / d a of a measured (real or complex) shape m and a real analytical a."""
    c = np.vdot(m, a)
    mm = np.real(np.vdot(m, m))
    aa = float(a @ a)
    mac = abs(c) ** 2 / (mm * aa)
    return 2 * np.real(np.conj(c) * m.conj()) / (mm * aa) - 2 * mac * a / aa


def _xor_parts(Psi: np.ndarray, A: np.ndarray):
    """Q = pinv(A) Psi^T: the measured shapes' coordinates in the paired analytical shapes at the
    sensors (the SEREP mass of those modes: Q is the cross-orthogonality before scaling)."""
    AtA_inv = np.linalg.inv(A.T @ A)
    P = AtA_inv @ A.T
    return P, AtA_inv, P @ Psi.T


def _cross_orthogonality(Psi: np.ndarray, A: np.ndarray) -> np.ndarray:
    """(n_pairs, n_pairs) cross-orthogonality of the measured shapes Psi (n, n_sensors) with the paired
    analytical ones (A: (n_pairs, n_sensors)) through the SEREP-reduced mass of the paired analytical
    modes: row i = measured mode i's coordinates in the analytical modes, scaled to unit generalised
    mass and signed so its diagonal term is positive (1 on the diagonal, 0 off it for a perfect model)."""
    _, _, Q = _xor_parts(Psi, A.T)
    Q = Q.T  # (n_measured, n_pairs)
    norm = np.linalg.norm(Q, axis=1, keepdims=True)
    sign = np.sign(np.diag(Q))[None, :]  # each analytical shape's arbitrary sign, turned to its pair's
    return sign * Q / np.where(norm > 0, norm, 1.0)


def _cross_orthogonality_derivative(Psi: np.ndarray, A: np.ndarray, dA: np.ndarray) -> np.ndarray:
    """d(cross-orthogonality).ravel() / dp ((n_pairs^2, n_var)) from the paired analytical shapes'
    derivatives dA (n_sensors, n_pairs, n_var): d pinv(A) = -pinv(A) dA pinv(A) + (A^T A)^-1 dA^T (I - A pinv(A))."""
    P, AtA_inv, Q = _xor_parts(Psi, A)
    resid = Psi.T - A @ Q  # (n_sensors, n_measured)
    n = Q.shape[1]
    out = np.empty((n * n, dA.shape[2]))
    Qt = Q.T
    norm = np.linalg.norm(Qt, axis=1, keepdims=True)
    sign = np.sign(np.diag(Qt))[None, :]
    for k in range(dA.shape[2]):
        dAk = dA[:, :, k]
        dQ = -P @ dAk @ Q + AtA_inv @ dAk.T @ resid
        dQt = dQ.T
        dnorm = np.sum(Qt * dQt, axis=1, keepdims=True) / norm
        out[:, k] = (sign * (dQt / norm - Qt * dnorm / norm**2)).ravel()
    return out


def _moments(Mrb: np.ndarray) -> np.ndarray:
    """(m, m cg (3), diagonal of the inertia about the origin (3)) from a rigid-body mass matrix."""
    mS = Mrb[3:, :3]
    return np.r_[np.trace(Mrb[:3, :3]) / 3, mS[2, 1], mS[0, 2], mS[1, 0], np.diag(Mrb[3:, 3:])]


__all__ = ["Block", "ConfigurationPoint", "DesignPointFailure", "Point", "UpdatingProblem", "Variable"]
