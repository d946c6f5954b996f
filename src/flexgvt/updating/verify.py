"""The numerical verification protocol of docs/method.md section 4.

A reference model is mistuned (each design variable scaled by a seeded uniform factor within
+-5 %) to make the initial model; the reference's frequencies, shapes at the sensors, mass
properties and static deflections in the training configurations are the surrogate test data;
the initial model is updated with +-10 % bounds and +-10 % mass-property constraints; then the
design-variable and frequency errors, the MAC matrices, and the prediction of an unseen load case
by single-configuration against multi-configuration updating are reported.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError
from .settings import OptimiserSettings, renamed
from ..fem import mass_properties, solve_modes, solve_static
from .runner import update
from .targets import MassTarget, Measured, Objective
from ..fem.stability import corner_spread
from ..fem.static import StaticSettings
from .variables import Parametrisation, beam, shell, shell_property

CASES = ("cantilever", "wingbox", "wingbox_local")
_MOVES_MOST = 0.5  # an element "deforms most" in a buckling shape at this fraction of the largest element's
LOCAL_BAY = "skin_bottom_bay01"  # the local study's bay: the bottom skin next to the root
LOCAL_FACTOR = 0.8  # its skin thickness in the reference against the others' (20 % thinner)


@dataclass(frozen=True)
class Onset:
    """Where the reference's load path in a configuration lost stability (from its State.instability).

    load_factor: the critical fraction of the configuration's loads; g: the same as a multiple of g
    (load_factor x the configuration's gravity magnitude; None without gravity); bracket: the converged
    load factors either side; groups: the shell (or beam) groups of the elements the buckling shape
    deforms most (the rms spread of an element's corner translations about their mean, at least half
    the largest: a wrinkle, not the global motion a shape may carry with it), most elements first;
    span: the y range [m] of those elements (along the wingbox's span); bays: the wingbox's rib bays
    their centres lie in (1 at the root; empty for other models); continued: the path was followed
    onto its post-buckled branch with a geometric imperfection in the buckling shape of largest
    offset ``imperfection`` [m] (0 when not continued); recovered: the solver left the unstable path
    by itself (no imperfection chosen)."""

    configuration: str
    load_factor: float
    g: float | None
    bracket: tuple[float, float]
    groups: tuple[str, ...]
    span: tuple[float, float]
    bays: tuple[int, ...]
    continued: bool
    imperfection: float
    recovered: bool

    @classmethod
    def of(cls, state, rib_pitch: float | None = None) -> Onset | None:
        """The onset of a solved State (None when its path met no instability); rib_pitch [m]: name the
        wingbox's bays (y / rib_pitch, numbered from 1 at the root)."""
        event = state.instability
        if event is None:
            return None
        model, cfg = state.model, state.configuration
        row = {int(n): k for k, n in enumerate(state.node_ids)}
        u = np.asarray(event.shape)[:, :3]
        xyz = model.xyz
        motion, names, ys = [], [], []
        for group in (*model.shells, *model.beams):
            rows = np.vectorize(row.__getitem__, otypes=[int])(group.nodes)
            motion.append(corner_spread(u, rows))
            names.append(np.full(len(rows), group.name, dtype=object))
            ys.append(xyz[rows, 1])
        if not motion:  # no elements: the nodes it moves most
            u = np.linalg.norm(u, axis=1)
            top = np.flatnonzero(u >= _MOVES_MOST * u.max())
            groups, y = (), xyz[top, 1]
        else:
            motion, names = np.concatenate(motion), np.concatenate(names)
            y = np.concatenate([np.asarray(a, float) for a in ys])
            top = np.flatnonzero(motion >= _MOVES_MOST * motion.max())
            found, counts = np.unique(names[top].astype(str), return_counts=True)
            groups = tuple(str(found[k]) for k in np.argsort(-counts, kind="stable"))
            y = y[top]
        centre = y.mean(axis=1) if y.ndim == 2 else y
        bays = () if not rib_pitch else tuple(sorted({int(c // rib_pitch) + 1 for c in centre}))
        offsets = np.array(list(cfg.imperfection.values()), float).reshape(-1, 3)
        size = float(np.linalg.norm(offsets, axis=1).max()) if len(offsets) else 0.0
        return cls(cfg.name, float(event.load_factor), float(event.load_factor * cfg.gravity) if cfg.gravity else None,
                   tuple(float(b) for b in event.bracket), groups, (float(y.min()), float(y.max())), bays,
                   size > 0.0, size, bool(event.recovered))

    def location(self) -> str:
        """Where along the span: 'rib bays 2-6, y 0.50-3.00 m'."""
        bays = (f"rib bay{'s' if len(self.bays) > 1 else ''} {_ranges(self.bays)}, " if self.bays else "")
        return f"{bays}y {self.span[0]:.2f}-{self.span[1]:.2f} m"

    def describe(self) -> str:
        """One line: load factor, g, groups, where along the span, continued or not."""
        g = f" = {self.g:.3g} g" if self.g is not None else ""
        then = (f"continued with a {1e3 * self.imperfection:.2g} mm imperfection in the buckling shape"
                if self.continued else "left by itself for a stable branch" if self.recovered else "not continued")
        return (f"buckles at load factor {self.load_factor:.4g}{g}: {', '.join(self.groups) or 'nodes'} "
                f"({self.location()}); {then}")


def _ranges(values) -> str:
    """1, 2, 3, 5 -> '1-3, 5'."""
    out, run = [], []
    for v in values:
        if run and v != run[-1] + 1:
            out.append(f"{run[0]}-{run[-1]}" if len(run) > 1 else f"{run[0]}")
            run = []
        run.append(v)
    if run:
        out.append(f"{run[0]}-{run[-1]}" if len(run) > 1 else f"{run[0]}")
    return ", ".join(out)


@dataclass
class Verification:
    """Outcome of the protocol; ``to_dict()`` is the documented --json layout."""

    case: str
    seed: int
    mistuning: np.ndarray  # x of the initial model relative to the reference
    multi: object  # UpdateResult on every training configuration
    single: object  # UpdateResult on the first training configuration only
    variable_errors_percent: dict  # initial / multi / single: (n_var,) errors against the reference
    prediction: dict  # unseen configuration: reference, multi, single frequencies and errors
    seconds: float
    configurations: dict = field(default_factory=dict)  # {name: reference, initial, multi, single Hz and errors}
    names: list = field(default_factory=list)  # the design variables, in the order of the errors
    onsets: dict = field(default_factory=dict)  # {loaded configuration: the reference's Onset, None if stable}

    def to_dict(self) -> dict:
        """A JSON-ready dictionary (the documented --json layout of `flexgvt verify`)."""
        from .result import jsonable
        return jsonable({"case": self.case, "seed": self.seed, "seconds": self.seconds,
                "mistuning": self.mistuning.tolist(),
                "variable_errors_percent": {k: v.tolist() for k, v in self.variable_errors_percent.items()},
                "variables": self.names, "prediction": self.prediction, "configurations": self.configurations,
                "onsets": {k: None if o is None else dataclasses.asdict(o) for k, o in self.onsets.items()},
                "multi": self.multi.to_dict(),
                "single": {"configurations": self.single.tables, "variables": self.single.variables,
                           "seconds": self.single.seconds, "history": self.single.history,
                           "message": self.single.message}})

    def as_dict(self) -> dict:
        """Deprecated: to_dict()."""
        renamed("Verification.as_dict()", "Verification.to_dict()")
        return self.to_dict()

    def summary(self) -> str:
        e = self.variable_errors_percent
        p = self.prediction
        lines = [
            f"verification '{self.case}', seed {self.seed} ({self.seconds:.1f} s)",
            f"  design variables, max |error|: initial {np.abs(e['initial']).max():.2f} %, multi-configuration "
            f"{np.abs(e['multi']).max():.3f} %, single-configuration {np.abs(e['single']).max():.3f} %",
            self.multi.summary()]
        for name, row in self.configurations.items():
            seen = "unseen" if row["unseen"] else ("seen by both" if "single" in row["seen_by"] else
                                                    "seen by multi only")
            lines.append(f"  '{name}' ({seen}), max |frequency error|: initial {_worst(row['initial_error_percent'])}, "
                         f"multi-configuration {_worst(row['multi_error_percent'])}, single-configuration "
                         f"{_worst(row['single_error_percent'])}")
        for name, row in self.configurations.items():
            for r in row.get("static", []):
                lines.append(f"  '{name}' static reading {_reading(r)}: reference {r['reference']:.5g}, error "
                             f"initial {r['initial_error_percent']:+.3g} %, multi-configuration "
                             f"{r['multi_error_percent']:+.3g} %, single-configuration "
                             f"{r['single_error_percent']:+.3g} %")
        for name, onset in self.onsets.items():
            lines.append(f"  '{name}': the reference " + (onset.describe() if onset is not None else
                                                        "found no unstable increment along its load path"))
        if not self.configurations:
            lines.append(f"  unseen '{p['configuration']}', max |frequency error|: multi-configuration "
                         f"{_worst(p['multi_error_percent'])}, single-configuration "
                         f"{_worst(p['single_error_percent'])}")
        return "\n".join(lines)


def _reading(row: dict) -> str:
    """'node 12 z [m]' for a static reading's row (component 1-6: x, y, z translations, rx, ry, rz rotations)."""
    c = row["component"]
    return f"node {row['node']} {('x', 'y', 'z', 'rx', 'ry', 'rz')[c - 1]} [{'m' if c <= 3 else 'rad'}]"


def _worst(errors) -> str:
    """The largest |error| [%] of a list, with how many modes found no partner (NaN)."""
    e = np.asarray(errors, float)
    lost = int(np.isnan(e).sum())
    head = f"{np.nanmax(np.abs(e)):.3f} %" if lost < len(e) else "-"
    return head + (f" ({lost} unpaired)" if lost else "")


def _cantilever_setup():
    from ..cases import cantilever_strip
    from ..correlation import Sensors
    case = cantilever_strip()
    ids = case.model.node_ids
    stations = ids[10::10]  # 15 stations, 0.1 m apart
    # Two flatwise sensors across the chord (bending and torsion) and one edgewise per station.
    z = Sensors.uniaxial(np.repeat(stations, 2), (0.0, 0.0, 1.0),
                         offsets=np.tile([[-0.02, 0.0, 0.0], [0.02, 0.0, 0.0]], (len(stations), 1)))
    x = Sensors.uniaxial(stations, (1.0, 0.0, 0.0))
    sensors = Sensors(list(z) + list(x))
    variables = [beam(f"{a}_region{r}", f"region{r}", a, bounds=(0.9, 1.1))
                 for r in (1, 2, 3) for a in ("rho", "E", "width", "thickness")]
    train = [case.configurations[n] for n in ("unloaded", "self_weight", "flatwise_3g")]
    unseen = case.configurations["flatwise_2g"]
    return case, sensors, variables, train, unseen, int(case.references["tip_node"])


def _wingbox_model(element_size: float = 0.2, local: float | None = None, bay: str = LOCAL_BAY,
                   rib_pitch: float = 0.5):
    """The shell wingbox (fg.cases.wingbox): 5 variables (density, E, rib, skin and spar thickness),
    training configurations unloaded, -1 g and 2.5 g, unseen the combined case. The loaded cases are
    post-buckled: each carries the imperfection in its buckling shape that takes the reference onto
    its post-buckled path (solve_static's buckling='continue'), as a test article has its own.
    Sensors: vertical accelerometers at both spars' top corners every 2 m and chordwise ones at the
    front spar, as a GVT of a wing instruments it. With ``local`` (a factor): the reference's skin
    in rib bay ``bay`` is that factor of the others' thickness, and a sixth variable, that bay's
    skin thickness, joins the five (the skins' variable takes every other bay)."""
    from ..cases import wingbox
    from ..correlation import Sensors
    case = wingbox(element_size=element_size, rib_pitch=rib_pitch, skin_bays=local is not None)
    model = case.model
    xyz = model.xyz
    top = xyz[:, 2] > 0.079
    stations = np.arange(2.0, 16.01, 2.0)
    pick = [int(np.argmin(np.where(top, np.hypot(xyz[:, 0] - x, xyz[:, 1] - y), np.inf)))
            for y in stations for x in (0.0, 1.0)]
    corners = model.node_ids[pick]
    z = Sensors.uniaxial(corners, (0.0, 0.0, 1.0))
    x = Sensors.uniaxial(corners[::2], (1.0, 0.0, 0.0))
    sensors = Sensors(list(z) + list(x))
    skins: str | list[str] = "skin_*"
    if local is not None:
        names = [g.name for g in model.shells]
        if bay not in names:
            raise ModelError(f"verify: no skin bay '{bay}' in the wingbox; name one of "
                             f"{[n for n in names if n.startswith('skin_')][:3]} ... (skin_top_bayNN or "
                             "skin_bottom_bayNN, numbered from the root)")
        skins = [n for n in names if n.startswith("skin_") and n != bay]
        k = names.index(bay)
        prop = model.shells[k].property
        model.set_shell_group(k, property=shell_property(prop, {"thickness": prop.thickness * local}))
    variables = [shell("rho", "*", "rho"), shell("E", "*", "E"), shell("t_ribs", "ribs", "thickness"),
                 shell("t_skins", skins, "thickness"), shell("t_spars", "spar_*", "thickness")]
    if local is not None:
        variables.append(shell(f"t_{bay}", bay, "thickness"))
    return case, sensors, variables


def _wingbox_setup(element_size: float = 0.2, local: float | None = None, bay: str = LOCAL_BAY,
                   rib_pitch: float = 0.5):
    """_wingbox_model's case, sensors and variables with the training configurations (the loaded
    ones on their post-buckled paths), the unseen one and the tip node of the static readings."""
    return _wingbox_paths(element_size, local, bay, rib_pitch)[:6]


def _wingbox_paths(element_size: float, local: float | None, bay: str, rib_pitch: float):
    """_wingbox_setup's, the reference's equilibria {loaded configuration: State} and its buckling
    onsets {loaded configuration: Onset or None}."""
    case, sensors, variables = _wingbox_model(element_size, local, bay, rib_pitch)
    model = case.model
    train, states, onsets = [], {}, {}
    for name in ("unloaded", "minus_1g", "plus_2_5g", "combined"):
        cfg = case.configurations[name]
        if cfg.gravity:
            state = solve_static(model, cfg, settings=StaticSettings(buckling="continue"))
            if local is not None and state.instability is None and name != "combined":
                state = _with_uniform_imperfection(model, state, bay, local)
            cfg, onsets[name] = state.configuration, Onset.of(state, rib_pitch)
            states[name] = state
        train.append(cfg)
    unseen = train.pop()
    return case, sensors, variables, train, unseen, int(case.references["tip_spar_nodes"][0]), states, onsets


def _bay_like_other_skins(model, bay: str, local: float) -> None:
    """Set ``model``'s skin bay ``bay``, ``local`` times the other skins' thickness, back to theirs."""
    k = [g.name for g in model.shells].index(bay)
    prop = model.shells[k].property
    model.set_shell_group(k, property=shell_property(prop, {"thickness": prop.thickness / local}))


def _with_uniform_imperfection(model, state, bay: str, local: float):
    """The local reference's loaded configuration when its own path found no loss of stability (its
    thin bay wrinkles smoothly under the skins' own weight): the models the updating tries, whose bay
    is as thick as the other skins, do lose stability there, and without an imperfection their
    equilibria past the bifurcation depend on where each solve starts (a warm start from an unstable
    flat-path state stays on it). So the configuration takes the imperfection that follows the
    uniform box onto its post-buckled path, and the reference is solved again with it: the
    reference and every trial model then follow the same imperfect paths. Unchanged when the
    uniform box does not buckle either."""
    uniform = model.copy("uniform skins")
    _bay_like_other_skins(uniform, bay, local)
    probe = solve_static(uniform, state.configuration, settings=StaticSettings(buckling="continue"))
    if probe.instability is None or not probe.configuration.imperfection:
        return state
    cfg = dataclasses.replace(state.configuration, imperfection=dict(probe.configuration.imperfection))
    return solve_static(model, cfg, settings=StaticSettings(buckling="continue"))


def _surrogate(model, configs, sensors, n_modes, tip, onsets: dict | None = None, states: dict | None = None):
    """The reference's Measured in each configuration; onsets: a dict to which each loaded configuration's
    Onset (None: no loss of stability found) is added, unless it holds that configuration already;
    states: equilibria {configuration name: State} of ``model`` in those very configurations (a
    post-buckled path's, solved from zero load with its imperfection), used instead of solving again."""
    data = []
    for cfg in configs:
        state = (states or {}).get(cfg.name)
        if state is None or state.configuration is not cfg or state.model is not model:
            state = solve_static(model, cfg)
        if onsets is not None and (cfg.gravity or cfg.forces) and cfg.name not in onsets:
            onsets[cfg.name] = Onset.of(state)
        modes = solve_modes(state, n_modes)
        S = sensors.matrix(state.node_ids, state)
        shapes = np.asarray(S @ modes.matrix()).T
        static = {(tip, 3): float(state.displacements[state.node(tip), 2])} if cfg.gravity else {}
        data.append(Measured(cfg.name, modes.frequencies_hz, shapes, sensors, static=static,
                             labels=tuple(modes.labels)))
    return data


@dataclass
class Protocol:
    """What every seed of a case shares (``verification_protocol(...)``): the reference case, sensors, variables
    (bounds not yet set), training configurations (the loaded ones with their imperfections), the
    unseen one, the surrogate data of both and the reference's mass properties."""

    case: str
    reference: object  # flexgvt.cases.Case
    sensors: object
    variables: list
    train: list
    unseen: object
    data: list  # Measured per training configuration
    unseen_data: Measured
    mass_target: MassTarget
    n_modes: int
    local: float | None
    onsets: dict = field(default_factory=dict)  # {loaded configuration: the reference's Onset or None}


def verification_protocol(case: str = "cantilever", n_modes: int = 8, element_size: float = 0.2,
                          local: float = LOCAL_FACTOR, rib_pitch: float = 0.5) -> Protocol:
    """The seed-independent part of verify(): the reference, its post-buckled training configurations
    and its surrogate data; pass it to verify(protocol=...) to run several seeds on one reference
    (the reference's static solves and buckling continuations are most of a coarse wingbox's set-up).
    rib_pitch: the wingbox's [m] (0.5 m, the original work's; a coarser pitch is a different box)."""
    if case not in CASES:
        raise ModelError(f"verify: unknown case '{case}'; choose one of {CASES}")
    local = local if case == "wingbox_local" else None
    ref, sensors, variables, train, unseen, tip, states, onsets = (
        (*_cantilever_setup(), {}, {}) if case == "cantilever" else _wingbox_paths(element_size, local, LOCAL_BAY,
                                                                                   rib_pitch))
    data = _surrogate(ref.model, [*train, unseen], sensors, n_modes, tip, onsets, states)
    mp = mass_properties(ref.model)
    target = MassTarget(mass=mp.mass, cg=tuple(mp.cg), inertia=tuple(np.diag(mp.inertia)))
    onsets = {cfg.name: onsets[cfg.name] for cfg in [*train, unseen] if cfg.name in onsets}  # in load-case order
    return Protocol(case, ref, sensors, variables, train, unseen, data[:-1], data[-1], target, n_modes, local,
                    onsets)


def verify(case: str = "cantilever", seed: int = 1, n_modes: int = 8, method: str = "least_squares",
           mistuning: float = 0.05, bounds: float = 0.10, element_size: float = 0.2, local: float = LOCAL_FACTOR,
           local_bounds: float = 0.30, tolerance: float | None = None, protocol: Protocol | None = None,
           bay_variable: bool = True) -> Verification:
    """Run the protocol on a built-in case ('cantilever': docs/method.md section 5 case 3, 150 beams, 12 variables,
    training configurations unloaded, self-weight and 3 g, unseen 2 g; 'wingbox': the shell box of case 4
    meshed at ``element_size`` [m], 5 variables, training unloaded, -1 g and 2.5 g, unseen the combined case;
    'wingbox_local': the wingbox whose reference has the bottom skin of the root bay at ``local`` times the
    others' thickness, which the model does not know: a sixth variable (that bay's skin) with
    +-``local_bounds``, started where the skins' variable is). tolerance: the optimiser's (its default when
    None); protocol: a verification_protocol(...) of this case to reuse (then n_modes, element_size and local are
    its); bay_variable=False: 'wingbox_local' with the five variables only (the skins' one takes the bay too),
    the model unable to represent the local difference.
    Every model (initial, multi, single) is also judged in every configuration
    (Verification.configurations)."""
    t0 = time.perf_counter()
    OptimiserSettings(method=method, tolerance=OptimiserSettings.tolerance if tolerance is None else tolerance)
    if protocol is None:  # (the settings checked first: the reference's solves take a while)
        if case == "wingbox_local" and not (0 < local and abs(local - 1.0) < local_bounds):
            raise ModelError(f"verify: the local factor {local:g} must be positive and within the local bounds "
                             f"1 +- {local_bounds:g}; widen local_bounds or choose a smaller difference")
        protocol = verification_protocol(case, n_modes, element_size, local)
    elif protocol.case != case:
        raise ModelError(f"verify: the protocol given is case '{protocol.case}', not '{case}'; build it with "
                         f"flexgvt.updating.verification_protocol('{case}', ...)")
    elif protocol.local is not None and abs(protocol.local - 1.0) >= local_bounds:
        raise ModelError(f"verify: the protocol's local factor {protocol.local:g} lies outside the local bounds "
                         f"1 +- {local_bounds:g}; widen local_bounds")
    ref, sensors, variables, train, unseen = (protocol.reference, protocol.sensors, protocol.variables,
                                              protocol.train, protocol.unseen)
    data, target, local = protocol.data, protocol.mass_target, protocol.local
    if local is not None and not bay_variable:
        variables = [shell("t_skins", "skin_*", "thickness") if v.name == "t_skins" else v for v in variables[:-1]]
    span = [local_bounds if v.name == f"t_{LOCAL_BAY}" else bounds for v in variables]
    variables = [type(v)(v.name, v.kind, v.attribute, v.targets, (1 - b, 1 + b)) for v, b in zip(variables, span)]
    rng = np.random.default_rng(seed)
    x_m = 1.0 + rng.uniform(-mistuning, mistuning, len(variables))
    if local is not None and bay_variable:  # the model's bay is like its other skins: relative to the reference's
        x_m[-1] = x_m[3] / local
    initial = ref.model.copy("initial (mistuned)")
    Parametrisation(ref.model, train, variables).apply(initial, x_m)
    if local is not None and not bay_variable:
        _bay_like_other_skins(initial, LOCAL_BAY, local)
    objective = Objective(frequency=1.0, mac=0.1, static=0.1, mass_limits=0.10)
    options = {} if tolerance is None else {"tolerance": tolerance}
    multi = update(initial, train, data, variables, mass_target=target, objective=objective, method=method,
                   **options)
    single = update(initial, train[:1], data[:1], variables, mass_target=target, objective=objective,
                    method=method, **options)
    truth = 1.0 / x_m  # the reference, in the initial model's normalisation
    errors = {"initial": 100 * (1.0 / truth - 1.0), "multi": 100 * (multi.x / truth - 1.0),
              "single": 100 * (single.x / truth - 1.0)}
    reference = protocol.unseen_data
    models = {"initial": initial, "multi": multi.model, "single": single.model}
    # The multi-configuration update's first point is the initial model solved from zero load in
    # every training configuration, its final point the updated model continued there from it
    # along the design points (and the single-configuration update's likewise in the unloaded one):
    # their own predictions there, where the first point's path met no instability.
    solved = {"initial": multi.initial.configurations, "multi": _continued(multi), "single": _continued(single)}
    configurations = {}
    for cfg, meas in zip([*train, unseen], [*data, reference]):
        seen_by = [] if cfg is unseen else ["multi", "single"] if cfg is train[0] else ["multi"]
        row = {"reference_hz": meas.frequencies_hz.tolist(), "labels": list(meas.labels), "seen_by": seen_by,
               "unseen": cfg is unseen}
        static = {}
        for key, model in models.items():
            f, static[key] = _predicted(model, cfg, meas, sensors, protocol.n_modes,
                                        solved.get(key, {}).get(cfg.name))
            row[f"{key}_hz"] = f.tolist()
            row[f"{key}_error_percent"] = (100 * (f - meas.frequencies_hz) / meas.frequencies_hz).tolist()
        row["static"] = [_static_row(k, v, static) for k, v in meas.static.items()]
        configurations[cfg.name] = row
    u = configurations[unseen.name]
    prediction = {"configuration": unseen.name, "reference_hz": u["reference_hz"], "labels": u["labels"]}
    prediction.update({k: u[k] for k in ("multi_hz", "multi_error_percent", "single_hz", "single_error_percent",
                                         "static")})
    return Verification(case, seed, x_m, multi, single, errors, prediction, time.perf_counter() - t0,
                        configurations, [v.name for v in variables], dict(protocol.onsets))


def verify_seeds(case: str = "cantilever", seeds=(1, 2, 3), processes: int | None = None,
                 protocol: Protocol | None = None, n_modes: int = 8, element_size: float = 0.2,
                 local: float = LOCAL_FACTOR, **options) -> list[dict]:
    """verify() for each of ``seeds`` on one protocol (verification_protocol, built once unless
    given): each seed's Verification.to_dict(), in the order of ``seeds``, with "cpu_seconds" (the
    process time its seed took). processes: run the seeds in that many spawned worker processes,
    each single-threaded (numba and BLAS), the protocol sent to them once per seed; None runs them
    here, one after the other. The workers start while the protocol is built. options: verify()'s
    (method, mistuning, bounds, local_bounds, tolerance, bay_variable)."""
    seeds = [int(s) for s in seeds]
    if processes is not None and int(processes) < 1:
        raise ModelError(f"verify_seeds: processes={processes} must be at least 1 (or None: in this process)")
    if processes is None:
        protocol = protocol or verification_protocol(case, n_modes, element_size, local)
        return [_seed_summary(case, seed, protocol, options) for seed in seeds]
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    workers = min(int(processes), len(seeds))
    with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        ready = [pool.submit(_ready) for _ in range(workers)]  # they import flexgvt meanwhile
        protocol = protocol or verification_protocol(case, n_modes, element_size, local)
        for f in ready:
            f.result()
        jobs = [pool.submit(_seed_in_worker, case, seed, protocol, options) for seed in seeds]
        return [job.result() for job in jobs]


def _ready() -> bool:
    return True


def _seed_summary(case: str, seed: int, protocol: Protocol, options: dict) -> dict:
    t0 = time.process_time()
    out = verify(case, seed=seed, protocol=protocol, **options).to_dict()
    out["cpu_seconds"] = time.process_time() - t0
    return out


def _seed_in_worker(case: str, seed: int, protocol: Protocol, options: dict) -> dict:
    """One seed in a worker process: one numba and one BLAS thread (the workers share the cores)."""
    from .parallel import single_threaded
    return single_threaded(_seed_summary)(case, seed, protocol, options)


def _static_row(key: tuple, reference: float, static: dict) -> dict:
    """One static reading of a configuration: the reference's and each model's value [m or rad] and errors [%]."""
    node, component = key
    row = {"node": int(node), "component": int(component), "reference": float(reference)}
    for model, values in static.items():
        row[model] = values[key]
        row[f"{model}_error_percent"] = 100 * (values[key] - reference) / reference if reference else float("nan")
    return row


def _continued(result) -> dict:
    """{configuration: the final ConfigurationPoint of an UpdateResult} where the update's first point
    (solved from zero load) met no instability on its path there: the final equilibrium is the
    first one continued along the design points, on the same branch."""
    first = result.initial.configurations
    return {name: p for name, p in result.final.configurations.items()
            if name in first and first[name].state is not None and first[name].state.instability is None}


def _predicted(model, cfg, meas: Measured, sensors, n_modes: int, point=None) -> tuple[np.ndarray, dict]:
    """The frequencies [Hz] of ``model`` in ``cfg`` paired (MAC at the sensors) with the measured modes,
    NaN where a measured mode finds no partner, and its static readings {(node, component): value} at
    the measured ones (Measured.static) of the same equilibrium. A model whose load path loses stability where the
    reference's did not is followed onto its own post-buckled path (the reference's rule): the
    primary path's equilibrium past a bifurcation is unstable and its frequencies predict nothing.
    point: an updating ConfigurationPoint of this model in ``cfg`` (an update's first point, solved from
    zero load, or its final one, continued from that), whose modes are taken where its path found no
    instability and the equilibrium is stable (the lowest eigenvalue positive; the same equilibrium;
    its lowest n_modes + 4 modes)."""
    from ..correlation import pair
    state = None if point is None else point.state
    if (state is not None and state.instability is None and len(point.eigenvalues) >= n_modes + 4
            and np.min(point.eigenvalues) > 0):
        modes = _first(point.modes(label=False), n_modes + 4)
    else:
        state = solve_static(model, cfg, settings=StaticSettings(buckling="continue"))
        modes = solve_modes(state, n_modes + 4, label=False)  # the pairing reads shapes and frequencies only
    pairing = pair(_as_modal_set(meas), modes, sensors=sensors)
    f = np.full(len(meas.frequencies_hz), np.nan)
    f[pairing.measured] = modes.frequencies_hz[pairing.analytical]
    u = state.displacements
    return f, {(n, c): float(u[state.node(n), c - 1]) for n, c in meas.static}


def _first(modes, k: int):
    """The lowest k of fem Modes."""
    from dataclasses import replace
    cut = {f: getattr(modes, f)[:k] for f in ("frequencies_hz", "damping_ratio", "damped_frequencies_hz", "shapes",
                                               "labels", "complex_shapes", "eigenvalues", "energy_fractions")
           if getattr(modes, f) is not None}
    return replace(modes, **cut)


def _as_modal_set(meas: Measured):
    from ..ema.polymax import ModalSet
    n = len(meas.frequencies_hz)
    return ModalSet(meas.frequencies_hz, np.zeros(n), meas.shapes, np.zeros((n, 0)), np.zeros((n, 0, 0)))
