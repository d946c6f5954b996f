"""Geometrically nonlinear static solution: Newton-Raphson with load increments, automatic step
cutting, a stabilising stiffness for mechanisms that vanishes at convergence, and warm starts.

All loads of a configuration (gravity, forces, distributed loads) and the pre-tension of the
suspension cords are ramped together by the load factor lambda from 0 to 1.
"""

from __future__ import annotations

import dataclasses
import time
import warnings
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import scipy.sparse as sp

from ..errors import ConvergenceError, FlexGVTWarning, InstabilityError, ModelError, SingularModelError, SolverError
from ..model import Configuration, Model, NodalLoad
from ..model.configuration import parse_dofs
from .checks import check_connected
from .eigen import real_modes
from .arclength import trace
from .rotations import logm_so3, scaled_increment
from .linsolve import HAVE_FAST, CholmodCache, serial_blas, superlu
from .knee import knee
from .stability import BUCKLING_MODES, Instability, locate, negative_eigenvalues
from .system import Evaluation, System


@dataclass(frozen=True)
class IterationRecord:
    """One Newton iteration: load step, load factor, iteration, residual and energy norms."""

    step: int
    load_factor: float
    iteration: int
    residual: float  # ||r|| / reference force
    energy: float  # |du . r| / reference energy
    stabilisation: float  # diagonal stabilisation needed beyond the mass term in this iteration (0: none)


@dataclass(frozen=True)
class State:
    """An equilibrium state of a model in a configuration.

    positions (n_nodes, 3) [m]; rotations (n_nodes, 3, 3) from the undeformed orientation;
    displacements (n_nodes, 6): translations [m] and rotation vectors [rad]; node order node_ids.
    """

    model: Model
    configuration: Configuration
    node_ids: np.ndarray
    positions: np.ndarray
    rotations: np.ndarray
    load_factor: float
    history: tuple[IterationRecord, ...]
    axial_forces: np.ndarray  # (n_beams,) [N], tension positive
    cord_tension: np.ndarray  # (n_cords,) [N]
    cord_length: np.ndarray  # (n_cords,) [m]
    stabilised_mechanism: bool = False
    solve_time_s: float = 0.0
    system: System | None = field(default=None, repr=False, compare=False)
    cautions: tuple[str, ...] = ()  # physically doubtful features of the solution (see check_state)
    steps: tuple[State, ...] = field(default=(), repr=False, compare=False)  # states at solve_static's load_factors
    instability: Instability | None = None  # where the load path lost stability (see StaticSettings.buckling)

    @property
    def displacements(self) -> np.ndarray:
        u = self.positions - self.system.cm.xyz
        return np.concatenate([u, logm_so3(self.rotations)], axis=1)

    @property
    def converged_steps(self) -> int:
        return len({r.step for r in self.history})

    def node(self, node_id: int) -> int:
        """Row of a node id in the state's arrays."""
        return int(self.model.index_of([node_id], "state.node")[0])

    def summary(self) -> str:
        u = self.displacements
        k = int(np.argmax(np.linalg.norm(u[:, :3], axis=1)))
        return (f"'{self.configuration.name}': load factor {self.load_factor:g}, {self.converged_steps} steps, "
                f"{len(self.history)} iterations, max displacement {np.linalg.norm(u[k, :3]):.4g} m at node "
                f"{self.node_ids[k]}" + "".join(f"\n  warning: {c}" for c in self.cautions))


@dataclass(frozen=True)
class StaticSettings:
    """Settings of the nonlinear static solver.

    increments: initial number of equal load increments; max_iterations per increment;
    tolerance: residual norm relative to the applied-load norm; energy_tolerance: absolute
    energy norm accepted when the residual has stagnated at its round-off floor;
    relative_energy_tolerance: an increment is also converged once a Newton correction's energy
    |du . r| falls below this fraction of the increment's first one (quadratic convergence: the
    correction is applied and its residual only checked, which saves the iterations otherwise
    spent at the round-off floor of stiff axial members); polish_iterations: at the final and
    requested levels, at most this many more Newton corrections after that, until one's energy is
    below energy_tolerance (the axial forces of stiff members, and the pre-stressed frequencies
    with them, converge well after the energy norm); intermediate_energy_tolerance: the
    same for load levels on the way, whose state only seeds the next increment (the problem is
    elastic, nothing accumulates; the final and requested levels keep the strict tolerance);
    there the increment ends without a new tangent once the correction computed with the last
    factor meets it; chord_steps: corrections with that factor tried first when it does not
    (each must cut the energy tenfold; 0 by default: from a stretched state they diverge more
    often than they help); min_increment: smallest load increment before giving up;
    max_increment_growth: largest growth of an increment after an easy step (1.0 keeps every
    increment equal); desired_iterations: the increment is scaled by sqrt(desired / taken)
    after each step. cord_strain_limit: the stretch beyond a cord's design length, as a fraction of
    its unstretched length, past which the state reports it as stretched beyond any real spring
    (see check_state): 1.0 (100 %, about rubber shock cord's rated elongation) by default.
    buckling: what an unstable final state (a negative tangent eigenvalue: a buckled skin, a limit
    point) does: "ignore" (no check), "warn" (default: locate the loss of stability along the path,
    State.instability, a caution), "stop" (raise InstabilityError with the last stable state) or
    "continue" (solve again with a small geometric imperfection in the buckling shape, which takes
    the structure onto its post-buckled path; the returned state's configuration carries it as
    Configuration.imperfection); imperfection: its largest offset [m] (0: a tenth of the
    thickness of most buckled shells, or 1e-4 of the structure's size).
    """

    increments: int = 20
    max_iterations: int = 25
    tolerance: float = 1e-8
    energy_tolerance: float = 1e-14
    relative_energy_tolerance: float = 1e-12
    polish_iterations: int = 2
    intermediate_energy_tolerance: float = 1e-6
    chord_steps: int = 0
    min_increment: float = 1e-5
    max_increment_growth: float = 1.5
    desired_iterations: int = 5
    cholmod: bool = True  # use the symmetric factorisation (PARDISO, or CHOLMOD) where installed (else SuperLU)
    cord_strain_limit: float = 1.0  # a cord stretched past its design length by this x its unstretched one: warned
    buckling: str = "warn"  # an unstable final state: "ignore", "warn", "stop" or "continue" (see solve_static)
    imperfection: float = 0.0  # [m] the post-buckled path's imperfection; 0: a tenth of the buckled shells' thickness
    control: str = "load"  # "load" (load stepping) or "arc-length" (past limit points: fem.arclength)
    arc_length: float = 0.0  # [m] first arc-length step (0: the tangent predictor of a 1/increments load step)
    max_arc_steps: int = 500  # arc-length steps before giving up


# Pseudo-dynamic stabilisation [rad^2/s^2]: (2 pi 1 mHz)^2 times the mass matrix is added to the
# tangent in every linear solve. It restrains mechanisms (a strip hung on its elastic axis) and is
# negligible against any physical mode, so it slows Newton by a factor ~alpha/omega^2 at most and
# vanishes at convergence (the residual is always that of the true system).
STABILISATION = (2 * np.pi * 1e-3) ** 2


class _Factor:
    """Factorised K + alpha M (PARDISO or CHOLMOD on its symmetric part where available, else SuperLU), with
    optional iterative refinement on K; a diagonal term is added only if every factorisation fails."""

    def __init__(self, system: System, ev: Evaluation, M: sp.csc_matrix, reference: float,
                 cholmod: CholmodCache | None = None):
        self._system, self._ev = system, ev
        self.stabilisation = 0.0
        # Applied nodal moments (fixed in direction) put a skew part in the tangent that does not
        # vanish at equilibrium: Newton with the symmetric part alone then converges slowly or not at
        # all (the strip rolled up by end moments: thousands of cut increments), so LU takes the
        # whole tangent there.
        moments = any(np.any(np.asarray(load.moment, float)) for load in system.config.forces)
        if cholmod is not None and HAVE_FAST and not moments:
            chol = system.factor_newton_matrix(ev, M, STABILISATION, cholmod)
            if chol is not None:
                self._solve = chol.solve_A
                return
        K = self.K
        # Exact zeros of the shared pattern left out (a copy: the pattern's index arrays are
        # shared): SuperLU would carry them and their fill (1,000-element strip: 5.3 -> 2.8 ms).
        base = system.stabilised_tangent(K, M, STABILISATION).copy()
        base.eliminate_zeros()
        diag = np.abs(K.diagonal())
        scale = np.where(diag > 0, diag, reference)
        for alpha in (0.0, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2):
            A = base if alpha == 0 else (base + sp.diags(alpha * scale)).tocsc()
            try:
                self._solve = superlu(A).solve
            except RuntimeError:
                continue
            self.stabilisation = alpha
            return
        raise SingularModelError("the tangent stiffness is singular even with a stabilising stiffness; "
                                 "the model has an unrestrained mechanism without mass")

    @property
    def K(self) -> sp.csc_matrix:
        return self._system.tangent_of(self._ev)

    def solve(self, b: np.ndarray, refine: int = 0) -> np.ndarray:
        """Solve (K + alpha M) x = b, then ``refine`` steps of iterative refinement towards K x = b.

        Newton needs none (the mass term changes each step by at most alpha/omega^2 ~ 1e-5 for any
        mode above 0.3 Hz); the linear static solution refines to the exact K^-1 b.
        """
        x = self._solve(b)
        for _ in range(refine):  # recover the solution of K x = b where K is regular
            x = x + self._solve(b - self.K @ x)
        return x


_RIGID_NAMES = ("translation along x", "translation along y", "translation along z",
                "rotation about x", "rotation about y", "rotation about z")


def _pushed_rigid_motion(system: System, K: sp.csc_matrix | Callable[[], sp.csc_matrix], f_red: np.ndarray,
                         x: np.ndarray, R: np.ndarray) -> np.ndarray | None:
    """The rigid-body motion (coefficients of the six canonical motions about the centroid) that
    the loads push along and nothing restrains, or None. K: the undeformed tangent, or a function
    giving it (called only if a rigid motion is free)."""
    if system.clamped:
        return None
    modes, basis = system.unrestrained_rigid_motions(x)
    if callable(K):
        K = K()
    phi = system.reduce_displacement(modes @ basis)
    phi /= np.linalg.norm(phi, axis=0)
    Ksym = 0.5 * (K + K.T)
    try:
        w, v = np.linalg.eigh(phi.T @ (Ksym @ phi))
    except (np.linalg.LinAlgError, ValueError) as exc:  # non-finite: checks.check_values lets none through
        raise SolverError(f"configuration '{system.config.name}': the stiffness of the rigid-body motions is not "
                          f"finite ({exc}); check the model for absurd values (stiffness, coordinates)") from exc
    scale = max(abs(Ksym.diagonal()).max(), 1e-300)
    null = v[:, w <= 1e-13 * scale]  # motions with no stiffness above round-off
    if null.shape[1] == 0:
        return None
    push = (phi @ null).T @ f_red  # generalised load on each unrestrained motion
    if np.linalg.norm(push) <= 1e-8 * max(np.linalg.norm(f_red), 1e-300):
        return None
    return basis @ (null @ push)


def _unrestrained_error(system: System, coeffs: np.ndarray, extra: str = "") -> SingularModelError:
    pushed = [_RIGID_NAMES[i] for i in np.flatnonzero(np.abs(coeffs) > 0.1 * np.abs(coeffs).max())]
    return SingularModelError(
        f"configuration '{system.config.name}': the model is under-constrained: the loads push it along "
        f"{' and '.join(pushed)} and nothing restrains that motion{extra}. Fix DOFs (fixed={{node: '123456'}}), "
        "add springs or suspension cords, or remove the load.")


def _rigid_body_check(system: System, K: sp.csc_matrix | Callable[[], sp.csc_matrix], f_red: np.ndarray,
                      x: np.ndarray, R: np.ndarray) -> None:
    """Raise a clear error if the loads push along a rigid-body motion that nothing restrains."""
    coeffs = _pushed_rigid_motion(system, K, f_red, x, R)
    if coeffs is not None:
        raise _unrestrained_error(system, coeffs)


def _sag_may_hold(system: System, coeffs: np.ndarray) -> bool:
    """A structure on loaded cords under gravity, pushed only in rotation: once it sags its centre of
    mass can hang below the cords' line (a strip hung on two cords along its axis, its centre of
    mass off that axis, rolls a little and is held)."""
    big = np.abs(coeffs) > 0.1 * np.abs(coeffs).max()
    return bool(len(system.cord_nodes) and system.config.gravity != 0.0 and not big[:3].any())


# Holding-spring stiffness during the load ramp, released in these steps (fractions of the start).
_RELEASE = (1.0, 1e-1, 1e-2, 1e-3, 1e-4, 0.0)


def _hold_then_release(model: Model, configuration: Configuration, system: System, coeffs: np.ndarray,
                       settings: StaticSettings, load_factors, progress) -> State:
    """Equilibrium of a structure that its deformation restrains but its undeformed shape does not:
    the load ramp with a rotational spring at the node nearest the centroid holding its rotations
    (all three: the pushed motion mixes them; stiffness weight x span per radian), then that spring
    released step by step, each
    step a Newton solve at full load from the last; the last has no spring, so the state is the
    structure's own equilibrium. Ramping without the spring would roll the structure over at small
    loads (a strip ends up edgewise, an unstable branch at full load)."""
    from ..model import Spring
    x0 = system.cm.xyz
    node = int(system.cm.node_ids[np.argmin(np.linalg.norm(x0 - x0.mean(axis=0), axis=1))])
    span = max(float(np.ptp(x0, axis=0).max()), 1e-3)
    weight = _total_weight(system)
    k0 = weight * span

    def held(f: float) -> Configuration:
        return configuration.with_(springs=configuration.springs + (
            Spring.make(node, None, stiffness=np.r_[np.zeros(3), np.full(3, f * k0)]),))

    state = _solve_static(model, held(1.0), settings=settings, load_factors=load_factors, progress=progress)
    saved = state.steps  # the states at load_factors come from the held ramp
    done, fractions = 1.0, list(_RELEASE[1:])
    while fractions:
        f = fractions[0]
        cfg = configuration if f == 0.0 else held(f)
        try:
            state = _solve_static(model, cfg, settings=settings, start=state, _warm_only=True)
        except ConvergenceError:
            mid = np.sqrt(done * max(f, done * 1e-3))
            if done / mid < 1.05:
                raise _unrestrained_error(system, coeffs, " until it deforms, and releasing the spring that held it "
                                          "during the load ramp did not converge") from None
            fractions.insert(0, mid)
            continue
        done = f
        fractions.pop(0)
    if not _stable(state):
        raise _unrestrained_error(system, coeffs, " until it deforms, and the equilibrium found once the spring that "
                                  "held it during the load ramp was released is unstable")
    return dataclasses.replace(state, steps=saved)


def _stable(state: State) -> bool:
    """No mode of the state's tangent (symmetric part) with the mass matrix below -(2 pi 0.01 Hz)^2.

    DOFs without mass (rotations of point masses without inertia) get a small mass for this check
    only: the number of negative eigenvalues is K's own whatever the positive mass (Sylvester's
    law of inertia), and with that mass a neutral massless motion whose stiffness is round-off
    (+-eps |K|) stays above the limit instead of passing for an instability by the sign of its
    last digit, while a negative stiffness 100 times above round-off still falls below it."""
    system, x, R = state.system, state.positions, state.rotations
    M = system.mass_matrix(x, R)
    K = system.newton_matrix(system.evaluate(x, R, state.load_factor, assemble=False), M, 0.0)
    limit = (2 * np.pi * 0.01) ** 2
    massless = np.asarray(abs(M).sum(axis=1)).ravel() == 0
    if massless.any():
        fill = 100 * np.finfo(float).eps * max(abs(K).max(), 1e-300) / limit
        M = (M + sp.diags(np.where(massless, fill, 0.0))).tocsc()
    lam, _ = real_modes(K, M, 1, shift=-1.0)
    return bool(lam[0] > -limit)


def _total_weight(system: System) -> float:
    """Total weight [N] of the compiled system at full load."""
    from .massprops import system_mass_properties
    x, R = system.undeformed
    return system_mass_properties(system, x, R).mass * float(np.linalg.norm(system.config.gravity_vector))


def _held_at_rest(system: System, x: np.ndarray, R: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A start state with the fixed DOFs of ``system`` undeformed (translations; rotations of nodes
    with all three held): a start from another configuration (or with a spring that is now stiff
    enough to hold its DOFs) may have them displaced, and Newton never moves a fixed DOF."""
    x, R = x.copy(), R.copy()
    fixed = system.fixed.reshape(-1, 6)
    x[fixed[:, :3]] = system.cm.xyz[fixed[:, :3]]
    R[fixed[:, 3:].all(axis=1)] = np.eye(3)
    return x, R


def _limit_rotation(delta: np.ndarray, system: System, limit: float = 0.5) -> np.ndarray:
    """Scale a Newton correction so no rotation exceeds ``limit`` [rad] (guards nearly singular tangents)."""
    rot = np.abs(delta[system.rotation_mask]).max(initial=0.0)
    return delta * (limit / rot) if rot > limit else delta


@serial_blas
def solve_static(model: Model, configuration: Configuration, *, settings: StaticSettings | None = None,
                 start: State | None = None, load_factors: np.ndarray | None = None,
                 progress: Callable[[float], None] | None = None, keep_steps: bool = False) -> State:
    """Geometrically nonlinear static equilibrium of ``model`` in ``configuration``.

    start: a previous State to warm-start from (same model, e.g. another design point); the full
    load is tried first, then the load ramp. load_factors: extra load levels (fractions of the
    loads, 0 to 1) whose states the result keeps in ``State.steps``. keep_steps=True (deprecated:
    read ``state.steps``) returns (state, list(state.steps)) as before.
    progress: called with the converged load factor after each increment.
    A structure on cords under gravity that only its deformation restrains (a strip hung on two
    cords along its axis with its centre of mass off that axis) is ramped with its free rotation
    held by a spring, then released (see _hold_then_release).
    Raises ConvergenceError (with .state = last converged state, .history) if the load cannot
    be reached, SingularModelError for under-constrained models.
    """
    settings = settings or StaticSettings()
    if settings.buckling not in BUCKLING_MODES:
        raise ModelError(f"StaticSettings.buckling='{settings.buckling}' must be one of {BUCKLING_MODES}")
    if settings.control not in ("load", "arc-length"):
        raise ModelError(f"StaticSettings.control='{settings.control}' must be 'load' or 'arc-length'")
    trail = _Trail() if settings.buckling != "ignore" else None
    state = _solve_static(model, configuration, settings=settings, start=start, load_factors=load_factors,
                          progress=progress, trail=trail)
    if trail is not None:
        state = _stability(state, trail, settings, load_factors, progress)
    state = check_state(state, settings)
    if keep_steps:  # shown once per calling line by the warnings filter's registry
        warnings.warn("solve_static(keep_steps=True) is deprecated: the states at load_factors are in the "
                      "result's .steps (solve_static(...).steps)", DeprecationWarning, stacklevel=3)
        return state, list(state.steps)
    return state


class _Trail(list):
    """The converged increments (load factor, x, R) of a load ramp, and the run that made them."""

    run = None


def _stability(state: State, trail: _Trail, settings: StaticSettings, load_factors, progress) -> State:
    """The state after settings.buckling's check of a ramped solve (a warm start's path is not
    known: its modes say whether it is stable): where the path lost stability, if it did. Not with
    applied nodal moments: fixed in direction, they are not conservative under large rotations, and
    the tangent's symmetric part is then no stability test (it has two negative eigenvalues on
    Sze, Liu & Lo's strip rolled into a full circle by end moments, whose stability under such
    moments is not a question that test asks)."""
    if len(trail) < 2 or trail.run is None or trail[-1][0] < 1.0 - 1e-12:
        return state
    if any(np.any(np.asarray(load.moment, float)) for load in state.configuration.forces):
        return state
    run = trail.run

    def resolve(lam: float, x: np.ndarray, R: np.ndarray):
        got = _newton(run, *run.system.impose(x, R, lam), lam, 0, predicted=False)
        if got is None:
            raise ConvergenceError(f"configuration '{state.configuration.name}': locating the loss of stability, "
                                   f"Newton did not converge at load factor {lam:.4g}", state=state)
        return got[0], got[1]

    event = locate(run.system, trail, resolve)
    if event is None and not state.configuration.imperfection:
        # A configuration given an imperfection follows its post-buckled path by design: its knee is expected.
        event = knee(run.system, trail, resolve)
    if event is None:
        return state
    name = state.configuration.name
    # A knee of a stable path is followed as it is: the loads' own imperfection chose its branch.
    if event.recovered and (settings.buckling != "continue" or event.found_by == "path"):
        how = ("the loads' own imperfection (or the load step) chose it" if event.found_by == "path" else
               "reached without a chosen imperfection: which branch round-off picked is not controlled")
        note = (f"configuration '{name}': the load path passed a {event.describe()}; the final equilibrium is on "
                f"a stable (post-buckled) branch, {how} (StaticSettings(buckling='stop') stops before it)")
        if settings.buckling == "stop":
            event = dataclasses.replace(event, recovered=False)
        else:
            warnings.warn(note, FlexGVTWarning, stacklevel=4)
            return dataclasses.replace(state, instability=event, cautions=state.cautions + (note,))
    if settings.buckling == "stop":
        k = max(i for i, t in enumerate(trail) if t[0] <= event.bracket[0] + 1e-12)
        lam, x, R = trail[k]
        stable = run.state(x, R, lam, run.system.evaluate(x, R, lam, tangent=False), state.stabilised_mechanism)
        raise InstabilityError(f"configuration '{name}': the structure loses stability by {event.describe()}; the "
                               f"last stable equilibrium (load factor {lam:.4g}) is in the error's .state and the "
                               "instability in .instability. Lower the loads, stiffen the structure there, or solve "
                               "with StaticSettings(buckling='continue') to follow the post-buckled path",
                               state=stable, history=tuple(run.history), instability=event)
    if settings.buckling == "continue":
        amplitude = settings.imperfection or _default_imperfection(run.system, event)
        for attempt in range(3):
            size = amplitude * 10.0**attempt
            shape = event.shape[:, :3]
            rows = np.flatnonzero(np.linalg.norm(shape, axis=1) > 1e-6)
            offsets = {int(state.node_ids[i]): tuple(size * shape[i]) for i in rows}
            perturbed = dataclasses.replace(state.configuration, imperfection=offsets)
            again = _solve_static(state.model, perturbed, settings=settings, load_factors=load_factors,
                                  progress=progress)
            if negative_eigenvalues(again.system, again.positions, again.rotations, 1.0) == 0:
                note = (f"configuration '{name}': {event.describe()}; followed onto the post-buckled path with an "
                        f"imperfection of {size:.3g} m in the buckling shape (configuration.imperfection)")
                warnings.warn(note, FlexGVTWarning, stacklevel=4)
                return dataclasses.replace(again, instability=event, cautions=again.cautions + (note,))
            state = again
    note = (f"configuration '{name}': the load path loses stability: {event.describe()}. The equilibrium found is "
            "unstable (its lowest modes are labelled 'unstable'); StaticSettings(buckling='continue') follows the "
            "post-buckled path instead, buckling='stop' stops at the last stable state")
    warnings.warn(note, FlexGVTWarning, stacklevel=4)
    return dataclasses.replace(state, instability=event, cautions=state.cautions + (note,))


def _default_imperfection(system: System, event: Instability) -> float:
    """A tenth of the thickness most of the shells the buckling shape moves have (the nodes it moves
    by at least half its largest translation), else 1e-4 of the structure's size [m]. Most, not the
    thinnest: the 0.1 m wingbox's skin wrinkle moves the ribs' edges too, and their 2 mm set 0.2 mm
    where the buckled 8 mm skin asks 0.8 mm."""
    moving = np.flatnonzero(np.linalg.norm(event.shape[:, :3], axis=1) >= 0.5)
    found = [t for family in system.families for t in (getattr(family, "thickness_at", lambda nodes: None)(moving),)
             if t is not None]
    if found:
        return 0.1 * max(found, key=lambda t: (t[1], -t[0]))[0]
    return 1e-4 * float(np.linalg.norm(np.ptp(system.cm.xyz, axis=0)))


def _with_loads(configuration: Configuration, loads: np.ndarray, model: Model) -> Configuration:
    """The configuration with nodal loads (n_nodes, 6) [N, N m] added (storage order of model)."""
    rows = np.flatnonzero(np.any(loads != 0.0, axis=1))
    extra = tuple(NodalLoad(int(model.node_ids[i]), tuple(loads[i, :3]), tuple(loads[i, 3:])) for i in rows)
    return dataclasses.replace(configuration, forces=tuple(configuration.forces) + extra)


@dataclass
class _Run:
    """What the steps of one static solve share: the system, its settings, the mass matrix and
    factorisation cache, the reference load and length of the residual and energy norms, and the
    convergence record."""

    model: Model
    configuration: Configuration
    system: System
    settings: StaticSettings
    t0: float
    mass: sp.csc_matrix
    cholmod: CholmodCache | None
    load_ref: float
    length: float
    history: list[IterationRecord] = field(default_factory=list)
    trail: list | None = None  # the converged increments (load factor, x, R), when asked for

    def state(self, x, R, lam: float, ev: Evaluation, stabilised: bool) -> State:
        return State(self.model, self.configuration, self.system.cm.node_ids, x.copy(), R.copy(), lam,
                     tuple(self.history), ev.axial_forces, ev.cord_tension, ev.cord_length, stabilised,
                     time.perf_counter() - self.t0, self.system)

    def reference(self, ev: Evaluation, lam: float) -> float:
        """The force the residual at load factor lam is measured against [N]."""
        return max(np.linalg.norm(ev.external), self.load_ref * lam, 1e-300)

    def energy(self, delta: np.ndarray, r: np.ndarray, ref: float) -> float:
        """|du . r| per (reference force x length)."""
        return abs(delta @ r) / max(ref * self.length, 1e-300)


def _solve_static(model: Model, configuration: Configuration, *, settings: StaticSettings | None = None,
                  start: State | None = None, load_factors: np.ndarray | None = None,
                  progress: Callable[[float], None] | None = None, _warm_only: bool = False,
                  trail: list | None = None) -> State:
    """solve_static without the plausibility check of its final state (check_state). trail: a list
    that receives the converged increments (load factor, x, R) of a load ramp."""
    t0 = time.perf_counter()
    settings = settings or StaticSettings()
    # A warm start on the same model object (values possibly changed since, as an optimiser's
    # design points change them) keeps the start's DOF numbering, pattern and symbolic analysis.
    system = (start.system.for_values(model, configuration)
              if (start is not None and start.system is not None and start.model is model)
              else System(model, configuration))
    if not _warm_only:
        check_connected(system)
    x, R = system.undeformed
    mass = system.mass_matrix(x, R)
    cholmod = system.cholmod_cache if settings.cholmod else None
    ev0 = system.evaluate(x, R, 1.0, tangent=False)
    load_ref = max(np.linalg.norm(ev0.external), np.linalg.norm(ev0.internal), 1e-12)
    length = np.abs(system.cm.xyz).max() + 1.0  # correction energies |du . r| are per (load x length) [m]
    run = _Run(model, configuration, system, settings, t0, mass, cholmod, load_ref, length, trail=trail)
    if trail is not None:
        trail.run = run
    # The tangent with the full load at the undeformed state: loaded cords already give their
    # pendulum stiffness there (a tilted cord pulls sideways and restrains that motion too).
    pushed = None if _warm_only else _pushed_rigid_motion(system, lambda: system.evaluate(x, R, 1.0).tangent,
                                                          ev0.external - ev0.internal, x, R)
    if pushed is not None:
        if not _sag_may_hold(system, pushed):
            raise _unrestrained_error(system, pushed)
        if start is None:
            return _hold_then_release(model, configuration, system, pushed, settings, load_factors, progress)
    levels = sorted(set(np.round(np.asarray(load_factors, float), 12))) if load_factors is not None else []
    if start is not None:
        if start.system is not system and (start.positions.shape != x.shape):
            raise ModelError("solve_static(start=...): the start state belongs to a model of another size")
        got = _newton(run, *system.impose(*_held_at_rest(system, start.positions, start.rotations), 1.0), 1.0, 0)
        if got is not None:
            return run.state(*got[:2], 1.0, *got[2:])
        if _warm_only:
            raise ConvergenceError(f"configuration '{configuration.name}': Newton-Raphson did not converge from "
                                   "the start state", state=start, history=tuple(run.history))
        if pushed is not None:  # the warm start failed: ramp again with the free rotation held
            return _hold_then_release(model, configuration, system, pushed, settings, load_factors, progress)
    if not (np.any(system.applied) or np.any(system.mass_weight) or len(system.cord_nodes) or system.has_prescribed):
        # Nothing loads the structure: the undeformed state is the equilibrium.
        state = run.state(x, R, 1.0, system.evaluate(x, R, 1.0, tangent=False), False)
        return dataclasses.replace(state, steps=(state,) * len(levels))
    if settings.control == "arc-length":
        path = trace(system, x, R, levels, settings, mass, progress)
        run.history.extend(IterationRecord(*h, 0.0, 0.0) for h in path.history)
        saved = [run.state(xk, Rk, lk, system.evaluate(xk, Rk, lk, tangent=False), False)
                 for lk, xk, Rk in path.levels + [path.final]]
        return dataclasses.replace(saved[-1], steps=tuple(saved[:-1] if 1.0 not in levels else saved),
                                   instability=path.limits[0] if path.limits else None)
    return _ramp(run, x, R, levels, progress)


def _ramp(run: _Run, x: np.ndarray, R: np.ndarray, levels: list[float],
          progress: Callable[[float], None] | None) -> State:
    """The load-stepping driver: increments of the load factor from 0 to 1 (through every requested
    level), each predicted from the last two converged states and corrected by Newton, cut in half
    when Newton fails and scaled by Crisfield's rule after each success. Returns the final state
    with the states at ``levels`` in its steps."""
    system, settings = run.system, run.settings
    lam = 0.0
    step = 0
    previous = None
    saved: list[State] = []
    increment = 1.0 / settings.increments
    converged = system.evaluate(x, R, 0.0, tangent=False)
    last = run.state(x, R, 0.0, converged, False)
    if levels and levels[0] <= 0.0:
        saved.append(last)
    if run.trail is not None:
        run.trail.append((0.0, x, R))
    while lam < 1.0 - 1e-12:
        target = min(1.0, lam + increment)
        nxt = [lv for lv in levels if lam + 1e-12 < lv < target - 1e-12]
        if nxt:
            target = nxt[0]
        step += 1
        xs, Rs = _predict(run, x, R, lam, target, previous)
        strict = target >= 1.0 - 1e-12 or any(abs(target - lv) < 1e-12 for lv in levels)
        tol = settings.relative_energy_tolerance if strict else settings.intermediate_energy_tolerance
        got = _newton(run, *system.impose(xs, Rs, target), target, step, tol, converged, predicted=xs is not x)
        if got is None and xs is not x:  # from the converged state instead, without the predictor
            got = _newton(run, *system.impose(x, R, target), target, step, tol, converged, predicted=False)
        if got is None:
            increment *= 0.5
            if increment < settings.min_increment:
                raise ConvergenceError(
                    f"configuration '{run.configuration.name}': Newton-Raphson did not converge beyond load factor "
                    f"{lam:.4g} (the increment was cut below {settings.min_increment:g}). Likely causes: a limit "
                    "or buckling point (the structure cannot carry the full load), a mechanism or a slack cord "
                    "that leaves part of the model free, or loads far beyond the elastic range. The last "
                    "converged state is in the error's .state and the convergence record in .history.",
                    state=last, history=tuple(run.history))
            continue
        previous = (x, R, lam)
        x, R, ev, stab = got
        converged = ev
        lam = target
        last = run.state(x, R, lam, ev, stab or last.stabilised_mechanism)
        if run.trail is not None:
            run.trail.append((lam, last.positions, last.rotations))
        if any(abs(lam - lv) < 1e-12 for lv in levels):
            saved.append(last)
        if progress is not None:
            progress(lam)
        # Crisfield's rule: aim at the desired number of iterations per increment.
        iters = sum(1 for h in run.history if h.step == step)
        scale = np.sqrt(settings.desired_iterations / max(iters, 1))
        increment = min(increment * min(scale, settings.max_increment_growth), 1.0)
    return dataclasses.replace(last, steps=tuple(saved))


def _newton(run: _Run, x: np.ndarray, R: np.ndarray, lam: float, step: int, energy_tolerance: float | None = None,
            reference: Evaluation | None = None, predicted: bool = True):
    """Iterate to equilibrium at load factor lam.

    energy_tolerance: the relative energy that converges the increment (the settings' relative one
    by default); at or above the intermediate tolerance the increment is an intermediate one
    (finished with the last factor where it can, see _chord_finish), else it is polished (see
    _accepted_in_energy). reference: the evaluation at the last converged state. The tangent at
    the first extrapolated state takes its beam forces for the stress-dependent part (see
    _predict): at (x, R) when it is a predicted state, else (x, R) is that converged state and the
    first correction is the tangent predictor, so the tangent after it.
    Returns (x, R, ev, stabilised) or None. The residual is checked before factorising.
    """
    system, settings = run.system, run.settings
    if energy_tolerance is None:
        energy_tolerance = settings.relative_energy_tolerance
    intermediate = energy_tolerance >= settings.intermediate_energy_tolerance
    stabilised = False
    previous = np.inf
    growth = 0
    first_energy = None
    it = 0
    polish = 0 if intermediate else settings.polish_iterations
    accepted, accepted_res = None, np.inf  # a state accepted in energy, kept while it is polished
    ev = system.evaluate(x, R, lam, assemble=False, reference=reference if predicted else None)
    while it < settings.max_iterations:
        r = ev.internal - ev.external
        ref = run.reference(ev, lam)
        res = np.linalg.norm(r) / ref
        if not np.isfinite(res):
            return accepted
        if res < settings.tolerance:
            run.history.append(IterationRecord(step, lam, it, res, 0.0, 0.0))
            return x, R, ev, stabilised
        try:
            fac = _Factor(system, ev, run.mass, run.load_ref, run.cholmod)
        except SingularModelError:
            return accepted
        delta = -fac.solve(r)
        energy = run.energy(delta, r, ref)
        run.history.append(IterationRecord(step, lam, it, res, energy, fac.stabilisation))
        stabilised |= fac.stabilisation > 0
        # The energy norm is converged and the residual has stagnated at its round-off floor
        # (very stiff structures on soft supports): the correction would change nothing.
        stagnant = res > 0.5 * previous or res < 1e3 * settings.tolerance
        if not np.all(np.isfinite(delta)):
            return accepted
        if it > 0 and energy < settings.energy_tolerance and stagnant:
            return _stagnated(run, x, R, ev, lam, delta, res, ref, step, it, stabilised, accepted, accepted_res)
        growth = growth + 1 if res > previous else 0
        if growth >= 4:
            return accepted
        previous = res
        x, R = system.update(x, R, _limit_rotation(delta, system))
        it += 1
        if first_energy is None:
            first_energy = energy
        if intermediate and (it == 1 or energy > energy_tolerance * first_energy):
            # Test the corrected state with the factor at hand before a new tangent.
            got = _chord_finish(run, x, R, lam, fac, energy_tolerance * first_energy, step, it, stabilised)
            if got is not None:
                return got
        elif energy <= energy_tolerance * first_energy:
            got = _accepted_in_energy(run, x, R, lam, energy, res, ref, step, it)
            if got is not None:
                ev_new, res_new = got
                if energy < settings.energy_tolerance or polish == 0 or res_new < settings.tolerance:
                    return x, R, ev_new, stabilised
                # Small in energy is not yet small in the axial forces of stiff members, which
                # the pre-stressed modes follow: polish with full Newton corrections until one
                # is below the absolute energy floor (a cold-started 3 g strip accepted at a
                # relative residual of 6e-6 had its first frequency 5e-7 off the converged one,
                # and a warm start from a neighbouring design then gave another answer).
                polish -= 1
                accepted, accepted_res = (x, R, ev_new, stabilised), res_new
        ev = system.evaluate(x, R, lam, assemble=False, reference=reference if it == 1 and not predicted else None)
    return accepted


def _accepted_in_energy(run: _Run, x, R, lam: float, energy: float, res: float, ref: float, step: int,
                        it: int) -> tuple[Evaluation, float] | None:
    """The state corrected to below the relative energy tolerance, checked without a tangent:
    (its evaluation, its residual) when the residual did not grow (or, for a correction below the
    absolute energy floor, stayed within round-off: at most doubled), else None."""
    settings = run.settings
    ev = run.system.evaluate(x, R, lam, tangent=False)
    res_new = np.linalg.norm(ev.internal - ev.external) / ref
    if np.isfinite(res_new) and (res_new <= max(res, settings.tolerance)
                                 or (energy < settings.energy_tolerance and res_new <= 2 * res)):
        run.history.append(IterationRecord(step, lam, it, res_new, 0.0, 0.0))
        return ev, res_new
    return None


def _stagnated(run: _Run, x, R, ev: Evaluation, lam: float, delta: np.ndarray, res: float, ref: float, step: int,
               it: int, stabilised: bool, accepted, accepted_res: float):
    """Newton's end where the correction's energy is below the absolute floor and the residual has
    stagnated: apply the correction at hand and keep it where the residual does not grow. A thin
    member's residual may stall for one iteration (its axial forces second order in the last
    bending correction) and then fall to round-off (4.7e-4, 2.6e-4, then 1e-7 on a warm-started
    loaded strip). The state thrown away with it carried axial forces off by ~1e-3 of the load and
    its first frequency by 1e-5. Otherwise the state polished so far, if its residual is lower,
    else the state as it stands."""
    system = run.system
    xc, Rc = system.update(x, R, _limit_rotation(delta, system))
    evc = system.evaluate(xc, Rc, lam, tangent=False)
    res_c = np.linalg.norm(evc.internal - evc.external) / ref
    if np.isfinite(res_c) and res_c <= res:
        run.history.append(IterationRecord(step, lam, it + 1, res_c, 0.0, 0.0))
        return xc, Rc, evc, stabilised
    return accepted if accepted is not None and accepted_res < res else (x, R, ev, stabilised)


def _chord_finish(run: _Run, x, R, lam: float, fac: _Factor, energy_limit: float, step: int, it: int,
                  stabilised: bool):
    """Finish an intermediate increment with the last factor (modified Newton, no new tangent).

    A state is accepted once the energy of its correction with that factor is below the limit
    (the correction itself is not applied: the test is on the state's remaining error); up to
    ``settings.chord_steps`` corrections are applied before that while each cuts the energy
    tenfold. Returns None if that fails (the caller goes on with Newton from its own x, R).
    """
    system, settings = run.system, run.settings
    last = np.inf
    for done in range(settings.chord_steps + 1):
        ev = system.evaluate(x, R, lam, tangent=False)
        r = ev.internal - ev.external
        ref = run.reference(ev, lam)
        res = np.linalg.norm(r) / ref
        delta = -fac.solve(r)
        energy = run.energy(delta, r, ref)
        if not (np.isfinite(res) and np.isfinite(energy)):
            return None
        run.history.append(IterationRecord(step, lam, it + done, res, energy, fac.stabilisation))
        if energy <= energy_limit:
            return x, R, ev, stabilised
        if done == settings.chord_steps or energy > 0.1 * last:
            return None
        x, R = system.update(x, R, _limit_rotation(delta, system))
        last = energy
    return None


def _predict(run: _Run, x, R, lam: float, target: float, previous) -> tuple[np.ndarray, np.ndarray]:
    """Secant predictor: the last converged increment extrapolated to the target load factor
    (none for the first increment). Extrapolating along rotating members stretches them by
    O(rotation increment^2); the stiff axial terms turn that into forces far above the load
    (~1e4-1e5 times for a thin strip), so Newton's first tangent from the predicted state takes
    the converged state's beam forces in its stress-dependent part (see _newton). With the
    predicted state's own ones the first correction left 25-7,000 times more error energy
    (1,000-element strip under self-weight) and 3 of 20 increments needed two more tangents.
    A quadratic predictor stretches less but amplifies the intermediate states' looser
    convergence (tried: more iterations, and divergence with looser intermediate tolerances)."""
    if previous is None or previous[2] >= lam:
        return x, R
    system = run.system
    xp, Rp, lp = previous
    delta = scaled_increment(x, R, xp, Rp, system.dof_map, (target - lam) / (lam - lp))
    if not np.all(np.isfinite(delta)):
        return x, R
    return system.update(x, R, _limit_rotation(delta, system))


def check_state(state: State, settings: StaticSettings) -> State:
    """The state with its cautions (a FlexGVTWarning for each), the signs of a linear model driven far
    outside its range (the X-HALE under 30 g hung 92 m below its anchors, its cords 190 times their
    unstretched length, without a word):
    - a cord stretched beyond its design length (the anchor-to-attachment distance on the undeformed
      structure, or its unstretched length if longer) by more than settings.cord_strain_limit times
      its unstretched length. The design stretch is left out: a cord standing for a spring-and-pulley
      line keeps a short unstretched length and takes the weight in its rate (the X-HALE lab: 633 %
      at 1 g by design);
    - a displacement larger than twice the structure's own size (the diagonal of its undeformed
      bounding box: a cantilever rolled into a full circle moves its tip by its length, one folded
      back onto itself by twice that) plus the longest cord's reach (a compact block on long bungees
      may sag more than its size).
    """
    system, notes = state.system, []
    name = state.configuration.name
    reach = 0.0
    if len(state.cord_length):
        l0 = system.cord_l0_at(state.load_factor)
        design = np.maximum(system.cord_lgeom, l0)
        extra = (state.cord_length - design) / l0
        over = np.flatnonzero(extra > settings.cord_strain_limit)
        reach = float(system.cord_lgeom.max())
        if len(over):
            k = int(over[np.argmax(extra[over])])
            notes.append(f"configuration '{name}': {len(over)} cord(s) stretched beyond their design length by more "
                         f"than {settings.cord_strain_limit:.0%} of their unstretched length (cord {k} at node "
                         f"{system.cm.node_ids[system.cord_nodes[k]]}: {state.cord_length[k]:.4g} m long for "
                         f"{design[k]:.4g} m from anchor to attachment and {l0[k]:.4g} m unstretched, "
                         f"{extra[k]:.0%} more): a linear cord is far outside any real spring's range there. Check the "
                         "cords' stiffness and the loads (gravity factor), or raise StaticSettings.cord_strain_limit "
                         "for a cord made to stretch that far")
    xyz = system.cm.xyz
    size = float(np.linalg.norm(np.ptp(xyz, axis=0))) if len(xyz) else 0.0
    u = np.linalg.norm(state.positions - xyz, axis=1)
    k = int(np.argmax(u)) if len(u) else 0
    if size + reach > 0 and u[k] > 2 * size + reach:
        notes.append(f"configuration '{name}': node {state.node_ids[k]} moves {u[k]:.4g} m, more than twice the "
                     f"structure's own size ({size:.4g} m, the diagonal of its undeformed bounding box)"
                     + (f" plus its longest cord ({reach:.4g} m)" if reach else "")
                     + ": check the supports, springs, cords and loads; a displacement that large is rarely the "
                     "intended equilibrium")
    units = unit_system_caution(state.model, size)
    if units:
        notes.append(f"configuration '{name}': {units}")
    for note in notes:
        warnings.warn(note, FlexGVTWarning, stacklevel=3)
    return dataclasses.replace(state, cautions=tuple(notes)) if notes else state


def unit_system_caution(model: Model, size: float) -> str:
    """Why the model's values look like another unit system read as SI (mm-t-s or in-lbf-s values
    taken as m-kg-s: a 2 m beam read from an mm deck is 2 km long and sags by hundreds of metres
    under 1 g), or '' when they look like SI: a structure over 1 km across, a density below
    0.01 kg/m^3 (t/mm^3 and lbf s^2/in^4 values are 1e-9 and 1e-4; a stiffness-defined beam's
    equivalent density, 0.75 kg/m^3 for the HALE wing, stays above) or a Young's modulus below
    1 MPa (no structural material has them)."""
    seen = []
    if size > 1000.0:
        seen.append(f"it is {size:.4g} m across")
    for g in model.beams:
        mat = g.material
        if 0 < mat.rho < 1e-2 or 0 < mat.E < 1e6:
            seen.append(f"material '{mat.name}' has E = {mat.E:.4g} Pa and rho = {mat.rho:.4g} kg/m^3")
            break
    if not seen:
        return ""
    return ("the model's values look like another unit system read as SI (" + "; ".join(seen) + "). A deck in "
            "mm-t-s (mm, tonne, s: E in N/mm^2, rho in t/mm^3) or in-lbf-s needs its units: flexgvt solve "
            "--units mm-t-s, or units = \"mm-t-s\" under [model] in a project")


def _prescribed_forces(system: System, model: Model, configuration: Configuration) -> np.ndarray:
    """K_fp u_p: the forces on the free DOFs from the prescribed motion, exact in the linear sense.
    The prescribed DOFs are freed in a companion system whose undeformed tangent holds the coupling."""
    fixed = {node: "".join(str(d + 1) for d in parse_dofs(spec, "fixed")
                           if d + 1 not in configuration.prescribed.get(node, {}))
             for node, spec in configuration.fixed.items()}
    loose = System(model, dataclasses.replace(configuration, prescribed={},
                                              fixed={n: s for n, s in fixed.items() if s}))
    x, R = loose.undeformed
    K = loose.evaluate(x, R, 0.0).tangent
    u = np.zeros(loose.n_free)
    u[loose.dof_map[system.prescribed_dofs]] = system.prescribed_values
    free_full = np.flatnonzero(system.dof_map >= 0)
    free_full = free_full[np.argsort(system.dof_map[free_full])]
    return (K @ u)[loose.dof_map[free_full]]


@serial_blas
def solve_linear_static(model: Model, configuration: Configuration) -> State:
    """Linear static solution (small displacements) about the undeformed state, with the stiffness of
    the unloaded structure (no load stiffness, as Nastran SOL 101)."""
    t0 = time.perf_counter()
    system = System(model, configuration)
    check_connected(system)
    x, R = system.undeformed
    ev = system.evaluate(x, R, 1.0, tangent=False)
    # The stiffness of the unloaded structure: the load stiffness of the applied loads (weight of
    # offset masses, forces on rigid-link offsets and interpolation references) is second order.
    ev0 = system.evaluate(x, R, 0.0)
    K = ev0.tangent
    _rigid_body_check(system, K, ev.external - ev.internal, x, R)
    M = system.mass_matrix(x, R)
    r = ev.internal - ev.external
    if system.has_prescribed:
        r = r + _prescribed_forces(system, model, configuration)
        x, R = system.impose(x, R, 1.0)
    ref = max(np.linalg.norm(ev.external), np.linalg.norm(r), 1e-300)
    fac = _Factor(system, ev0, M, ref)
    delta = -fac.solve(r, refine=4) if np.any(r) else np.zeros_like(r)
    if np.linalg.norm(K @ delta + r) > 1e-6 * ref:
        raise SingularModelError(f"configuration '{configuration.name}': the stiffness matrix is singular and "
                                 "the loads excite the mechanism. Add constraints, springs or cords, or use "
                                 "solve_static for a suspended structure that needs its sagged equilibrium.")
    x, R = system.update(x, R, delta)
    rec = IterationRecord(1, 1.0, 0, float(np.linalg.norm(r) / ref), 0.0, 0.0)
    ev1 = system.evaluate(x, R, 1.0, tangent=False)
    return check_state(State(model, configuration, system.cm.node_ids, x, R, 1.0, (rec,), ev1.axial_forces,
                             ev1.cord_tension, ev1.cord_length, False, time.perf_counter() - t0, system),
                       StaticSettings())
