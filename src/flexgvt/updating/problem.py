"""The updating problem: a design point -> every configuration's equilibrium and modes, paired
with the measured ones -> residual vector, objective, constraints and their exact Jacobians.

One working copy of the model is set to each design point; each configuration keeps its compiled
system (DOF numbering, sparsity pattern, symbolic factorisation) and its last equilibrium as the
next solve's warm start. UpdatingProblem composes the units: the points it returns
(updating.points), their cache (updating.cache), the pairing policy (updating.pairing), each
configuration's rows and Jacobian (updating.blocks), the mass-target rows (updating.masstargets)
and remote evaluation (updating.remote, updating.parallel).
"""

from __future__ import annotations

import time

import numpy as np

from ..correlation import sensors_see
from ..errors import ConvergenceError, ModelError, SingularModelError
from ..fem import solve_static
from ..fem.eigen import modal_frequencies_hz, real_modes
from ..model import Configuration, Model
from .._threads import serial_blas
from .blocks import ConfigurationBlocks
from .cache import PointCache
from .derivatives import shared_changes
from .masstargets import MassResiduals
from .pairing import PairingPolicy
from .prior import measurement_variance, prior_std
from .points import Block, ConfigurationPoint, DesignPointFailure, Point
from .remote import remote_points
from .targets import MassTarget, Measured, Objective
from .variables import Parametrisation, Variable

EXTRA_MODES = 6  # analysed beyond the measured ones, so a mode that moves up or down is still found


class UpdatingProblem:
    """Design variables, configurations and their measured data, and the objective.

    model: the initial model (never changed); configurations: every configuration with test data;
    measured: one Measured per configuration; variables: design variables; mass_target: measured
    mass properties; objective: weights and limits; n_modes: modes analysed per configuration
    (default: measured + 6, plus 3 per interior point of a distributed cord: the cords' own modes);
    static_settings: for the nonlinear static solves.
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
        self.pairing = PairingPolicy(self.objective)
        self.blocks = ConfigurationBlocks(self.par, self.work, self.objective, self.measured, follow_sensors)
        self.mass_residuals = MassResiduals(mass_target, self.objective, self.par, self.work)
        self.prior_weights = self._prior_weights()
        self.cache = PointCache()
        self._reference: dict | None = None  # the reference set last (set_pairing_reference) ...
        self._moves_at_set = 0  # ... and the pairing's moves then
        self.workers: list | None = None  # Dask actors evaluating the configurations (updating.parallel)
        self.n_solves = 0
        # {configuration: design points evaluated here whose equilibrium was unstable}
        self.unstable: dict[str, int] = {}
        self.n_gradients = 0
        for m in measured:
            for (node, comp) in m.static:
                self.work.index_of([node], f"static deflection of configuration '{m.configuration}'")
                if not 1 <= int(comp) <= 6:
                    raise ModelError(f"static deflection ({node}, {comp}) of configuration '{m.configuration}': the "
                                     "component must be 1-6")

    def _prior_weights(self) -> np.ndarray | None:
        """(n,) weights w of the prior rows w (x - 1) (Objective.prior 'bounds'): sigma / s_k, sigma the
        standard deviation of one weighted frequency residual from the measured scatter and s_k the
        standard deviation of a uniform distribution over variable k's bounds, so that |r|^2 / sigma^2
        is the negative log posterior (up to a constant) of a Gaussian prior of variance s_k^2."""
        if self.objective.prior == "none":
            return None
        sigma2 = measurement_variance(list(self.measured.values()), self.objective, self.blocks.frequency_weights)
        if sigma2 is None:
            raise ModelError("updating: objective prior 'bounds' weighs each variable's prior against the measured "
                             "frequency scatter, and no configuration gives frequency standard deviations; give "
                             "them (Measured.frequency_std_hz; a project's identified modes carry PolyMAX's), or "
                             "set prior = 'none'")
        return np.sqrt(sigma2) / prior_std(self.par.variables)

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
        return {"pairing": self.pairing.reference_of(point, self.measured),
                "states": {name: c.state for name, c in point.configurations.items() if c.state is not None}}

    def set_pairing_reference(self, reference: dict, keep: "Point | None" = None) -> None:
        """Pair from now on against ``reference`` (from reference_of) and warm-start from its states;
        cached points are dropped, as their pairing may differ (kept when ``reference`` is the very
        one set last and no point has moved the pairing since: they were paired against it, so the
        answer evaluated again reuses its point). keep: the point ``reference`` was made from
        (reference_of(keep)): evaluated again, each configuration is solved from its own equilibrium,
        and where every one comes back bit for bit (Newton accepts it as it stands) the rest of the
        evaluation (tangent, modes, pairing against its own shapes, Jacobian) would repeat it
        exactly, so ``keep`` is the answer (PointCache.hold; a linear configuration's start and
        answer are not computed twice)."""
        if keep is not None:  # the same solve completed with its Jacobian, if it is cached
            cached = self.cache.get(keep.x.tobytes())
            if cached is not None and cached.jacobian is not None and cached.configurations is keep.configurations:
                keep = cached
        if reference is not self._reference or self.pairing.moves != self._moves_at_set:
            self.cache.clear()
        self.pairing.reference = dict(reference.get("pairing", {}))
        self.states.update(reference.get("states", {}))
        self._reference, self._moves_at_set = reference, self.pairing.moves
        if keep is not None and not self.workers and keep.configurations and all(
                c.state is not None and reference.get("states", {}).get(n) is c.state
                for n, c in keep.configurations.items()):
            self.cache.hold(keep.x.tobytes(), keep)

    @property
    def x0(self) -> np.ndarray:
        """The initial design point: every variable at 1 (its initial value)."""
        return np.ones(len(self.par))

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, x: np.ndarray, gradient: bool = False) -> Point:
        """The point at x (cached: the residuals and the Jacobian of one x are computed once)."""
        x = self.par.check(x)
        key = x.tobytes()
        hit = self.cache.get(key)
        if hit is not None and (hit.jacobian is not None or not gradient):
            return hit
        if hit is not None and not self.workers:  # the states are at hand: only the Jacobian is missing
            point = self.with_jacobian(hit)
            self.cache.replace(key, point)
            return point
        t0 = time.perf_counter()
        held = self.cache.held(key)
        try:
            configs = self._set_work(x)
        except ModelError as exc:  # e.g. a negative modulus from an unbounded step
            raise DesignPointFailure(f"design point outside the physical range: {exc}") from exc
        if self.workers:
            points = self._remote(x, gradient)
        elif held is not None:  # every equilibrium first: the held point is the answer only if all repeat
            states = {cfg.name: self._equilibrium(configs[cfg.name]) for cfg in self.configurations}
            if all(_same(states[n], c.state) for n, c in held.configurations.items()):
                self.states.update({n: c.state for n, c in held.configurations.items()})
                point = self.with_jacobian(held) if gradient else held
                self.cache.add(key, point)
                return point
            points = {cfg.name: self._point(cfg.name, states[cfg.name]) for cfg in self.configurations}
        else:  # each configuration solved and analysed in turn (the other order moves the modes by round-off)
            points = {cfg.name: self._point(cfg.name, self._equilibrium(configs[cfg.name]))
                      for cfg in self.configurations}
        point = self._assemble(x, points, gradient)
        point.seconds = time.perf_counter() - t0
        self.cache.add(key, point)
        return point

    def with_jacobian(self, point: Point) -> Point:
        """``point`` with its Jacobian, computed about its own equilibria (no new solve: the numbers
        of evaluate(x, gradient=True) at once); evaluated again where workers solved it (no states here)."""
        if point.jacobian is not None:
            return point
        if self.workers or any(c.state is None for c in point.configurations.values()):
            return self.evaluate(point.x, gradient=True)
        t0 = time.perf_counter()
        self._set_work(point.x)
        out = self._assemble(point.x, point.configurations, True)
        out.seconds = point.seconds + time.perf_counter() - t0
        return out

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
        out = {}
        for name, point in remote_points(self.workers, self.configurations, x, gradient):
            self.n_solves += 1
            out[name] = point
        return out

    def _equilibrium(self, config: Configuration):
        """The configuration's equilibrium on the working model, warm-started from its last one."""
        try:
            return solve_static(self.work, config, settings=self.static_settings, start=self.states.get(config.name))
        except (ConvergenceError, SingularModelError) as exc:
            raise DesignPointFailure(f"configuration '{config.name}' did not converge at this design point: "
                                     f"{exc}") from exc

    def _point(self, name: str, state) -> ConfigurationPoint:
        """The configuration's modes at its equilibrium ``state``, paired with the measured ones."""
        self.n_solves += 1
        system = state.system
        positions, R = state.positions, state.rotations
        ev = system.evaluate(positions, R, state.load_factor)
        tangent = ev.tangent.tocsc()
        K = (0.5 * (tangent + tangent.T)).tocsc()
        M = system.mass_matrix(positions, R)
        meas = self.measured[name]
        # By default also every mode of a distributed cord's own (3 per interior point), which may lie
        # among the measured ones.
        n = self.n_modes or len(meas.frequencies_hz) + EXTRA_MODES + 3 * system.n_cord_points
        n = min(n, system.n_free - 1)
        try:
            lam, phi = real_modes(K, M, n, None, system.clamped, system.cholmod_cache)
        except Exception as exc:  # ARPACK or factorisation failure at this design point
            raise DesignPointFailure(f"configuration '{name}': the eigen-solution failed at this design point "
                                     f"({exc})") from exc
        T = system.transformation(positions, R) if system.has_links else None
        f = modal_frequencies_hz(lam, K, M, system, positions, T)  # rigid-body modes at 0 Hz, as solve_modes
        if np.any(f < 0):  # a negative eigenvalue of the tangent: the equilibrium is unstable
            self.unstable[name] = self.unstable.get(name, 0) + 1
        self.states[name] = state
        sensors = meas.sensors
        shapes_s = seen = None
        if meas.shapes is not None:
            S = sensors.matrix(state.node_ids, state, follow=self.follow_sensors)
            full = system.expand(phi, T)
            shapes_s = np.asarray(S @ full).T
            seen = sensors_see(shapes_s, np.asarray(full).T)
        elif meas.observed_by is not None:
            S = meas.observed_by.matrix(state.node_ids, state, follow=self.follow_sensors)
            amp = np.linalg.norm(np.asarray(S @ system.expand(phi, T)), axis=0)
            best = amp[f > 0].max(initial=0.0)
            seen = amp >= meas.visibility * best if best > 0 else None
        static = np.array([state.displacements[state.node(node), int(c) - 1] for (node, c) in meas.static])
        point = ConfigurationPoint(name, state, lam, f, phi, np.full(len(meas.frequencies_hz), -1),
                                   np.full(len(meas.frequencies_hz), np.nan), None, shapes_s, static, K, M, tangent,
                                   seen=seen)
        point.paired, point.mac, point.mac_matrix = self.pairing.pair(name, meas, f, phi, shapes_s, M, seen,
                                                                      labels=lambda: point.labels)
        return point

    @serial_blas  # small dense products between kernel calls: a second BLAS thread only waits
    def _assemble(self, x, points: dict[str, ConfigurationPoint], gradient: bool) -> Point:
        """Every configuration's block (computed here unless a remote evaluation brought it) and the
        mass-property rows, in one residual vector and one constraint vector."""
        changes = shared_changes(self.par, self.work, x) if gradient else None
        for cfg in self.configurations:
            p = points[cfg.name]
            if p.block is None or (gradient and p.block.jacobian is None):
                p.block = self.blocks.block(x, p, gradient, changes)
        mp = self.mass_residuals.properties()
        mres, mnames, _ = self.mass_residuals.vector(mp)
        blocks = [points[c.name].block for c in self.configurations]
        mcon, mcon_names = self.mass_residuals.constraints(mp)
        w = self.prior_weights
        prior = [] if w is None else [w * (x - 1.0)]
        pnames = [] if w is None else [f"prior {n}" for n in self.par.names]
        point = Point(x.copy(), np.concatenate([b.residuals for b in blocks] + [mres] + prior),
                      [n for b in blocks for n in b.names] + mnames + pnames, points, mp,
                      constraints=np.concatenate([b.constraints for b in blocks] + [mcon]),
                      constraint_names=[n for b in blocks for n in b.constraint_names] + mcon_names,
                      unpaired={c.name: np.flatnonzero(points[c.name].paired < 0).tolist()
                                for c in self.configurations}, n_prior=len(pnames))
        if gradient:
            nv = len(self.par)
            dmp = self.mass_residuals.derivatives(x, changes)
            point.jacobian = np.vstack([b.jacobian for b in blocks] + [dmp] + ([] if w is None else [np.diag(w)]))
            crows = [b.constraint_jacobian for b in blocks]
            if len(mcon):
                rel_d = dmp / self.mass_residuals.weights()[:, None]
                crows += [np.vstack([row for r in rel_d for row in (-r[None, :], r[None, :])])]
            point.constraint_jacobian = np.vstack(crows) if crows else np.zeros((0, nv))
            self.n_gradients += 1
        return point


def _same(a, b) -> bool:
    """Two states at the very same equilibrium, bit for bit."""
    return b is not None and np.array_equal(a.positions, b.positions) and np.array_equal(a.rotations, b.rotations)


__all__ = ["Block", "ConfigurationPoint", "DesignPointFailure", "Point", "UpdatingProblem", "Variable"]
