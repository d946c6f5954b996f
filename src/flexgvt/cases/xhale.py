"""X-HALE-like very flexible flying wing (docs/method.md section 5 case 6); see ``xhale``."""

from __future__ import annotations

import math
from itertools import pairwise
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ModelError
from ..model import (
    CircularTubeSection,
    Configuration,
    Cord,
    GeneralSection,
    Material,
    Model,
    Spring,
)
from ..model.configuration import STANDARD_GRAVITY
from .case import Case

# ---------------------------------------------------------------- published data (xhale_lab_gvt.json)
GROSS_MASS = 11.35  # kg
CHORD = 0.20  # m
DIHEDRAL = math.radians(10.0)
E_WING, G_WING = 4.32e9, 1.71e9  # Pa, initial values of the updating variables
E_BOOM, G_BOOM = 5.0e9, 1.88e9
K_WING_TAIL = 1.0e8  # N/m and N m/rad, the six wing-tail spring components
SUSPENSION = {"left": (17.59, 0.94), "right": (18.01, 1.35)}  # K [N/m], C [N s/m]
BUNGEE_EA = (92.5, 100.0)  # N, left and right
BUNGEE_LENGTH = 20.0  # m
LABELS = ("Plunge", "1 OOP", "2 OOP", "1 T/2 IP", "3 OOP", "2 T/3 IP", "4 OOP", "5 OOP")
MEASURED_HZ = {"outboard": (0.28, 0.99, 2.74, 4.24, 4.53, 6.23, 7.18, 8.10),
               "inboard": (0.28, 0.95, 2.70, 4.75, 4.50, 6.90, 7.35, 8.38)}
ORIGINAL_INITIAL_HZ = {"outboard": (0.27, 0.96, 2.76, 4.30, 4.60, 6.15, 7.77, 8.73),
                       "inboard": (0.28, 0.91, 2.78, 4.77, 4.58, 7.03, 7.79, 8.74)}
# This model's modes matched to LABELS (nominal, n_per_section=8); see the tests.
TUNED_HZ = {"outboard": (0.271, 1.000, 2.685, 4.251, 4.520, 6.267, 7.821, 8.979),
            "inboard": (0.279, 0.925, 2.719, 4.632, 4.570, 7.011, 7.816, 8.563)}
ORIGINAL_UPDATED_HZ = {"outboard": (0.27, 0.99, 2.69, 4.28, 4.46, 6.27, 7.20, 8.26),
                       "inboard": (0.28, 0.95, 2.71, 4.76, 4.44, 7.04, 7.22, 8.26)}

SECTIONS = ("wing_L3", "wing_L2", "wing_L1", "wing_R1", "wing_R2", "wing_R3")
JOINERS = ("joiner_L2", "joiner_L1", "joiner_C", "joiner_R1", "joiner_R2")
JUNCTIONS_Y = (-2.0, -1.0, 0.0, 1.0, 2.0)
BOOM_JUNCTIONS = (-2.0, -1.0, 1.0, 2.0)  # y of the pods that carry a tail boom

# ---------------------------------------------------------------- tuned equivalent properties
NOMINAL = {
    # wing sections, per unit length (tuned)
    "EI_oop": 102.0,  # N m^2, flatwise bending
    "EI_ip": 7060.0,  # N m^2, chordwise bending
    "GJ": 191.0,  # N m^2, torsion
    "mu_wing": 0.48,  # kg/m
    "it_wing": 0.0015,  # kg m, torsional inertia per length (radius of gyration 56 mm)
    "area_wing": 2.0e-4,  # m^2, equivalent area (sets EA = 0.86 MN and the equivalent density)
    # joiners: aluminium joiner inside the wing, 'joiner_stiffening' times the wing's section
    "joiner_half": 0.04,  # m (joiners 0.08 m long, centred on the junctions)
    "joiner_stiffening": 2.1,
    "mu_joiner": 1.2,  # kg/m (96 g per joiner)
    # pods (motor, electronics, landing wheels) below and ahead of the junctions
    "pod_mass_centre": 3.40,  # kg (battery and avionics); the other four share what the budget leaves
    "pod_offset_z": -0.05,  # m; the x offset puts the aircraft's cg on the wing reference line
    "pod_inertia": (0.010, 0.0024, 0.006),  # kg m^2 about the pod's own cg (roll, pitch, yaw) for 0.99 kg
    # tail booms (fibreglass tubes) and horizontal tails
    "boom_length": 0.78,  # m
    "boom_radius": (0.020, 0.0185),  # m, outer and inner
    "boom_rho": 1900.0,  # kg/m^3
    "tail_mass": 0.032,  # kg, horizontal tail with elevator
    "tail_span": 0.45,  # m
    "tail_chord": 0.12,  # m
    # suspension
    "pendulum_length": 3.0,  # m, Kevlar string from the ceiling pulley to the adapter
    # the free-flying test's bungees (EA and length published; their mass not): an assumed 20 g/m
    # (0.4 kg per 20 m cord: a 6 mm braided shock cord), distributed over 10 members in the
    # *_heavy configurations
    "bungee_mass_per_length": 0.02,  # kg/m (assumed)
    "bungee_segments": 10,
}


def _points(a, b, n):
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    return np.asarray(a, float) * (1 - t) + np.asarray(b, float) * t


def _build(p: dict, n_per_section: int, factors: dict | None = None, mass_factors: dict | None = None):
    """The model and the node ids the configurations and sensors need."""
    factors = factors or {}
    mass_factors = mass_factors or {}
    model = Model("X-HALE-like flying wing")
    h = p["joiner_half"]
    c, s = math.cos(DIHEDRAL), math.sin(DIHEDRAL)
    junction = {y: np.array([0.0, y, 0.0]) for y in JUNCTIONS_Y}
    out_l, out_r = np.array([0.0, -c, s]), np.array([0.0, c, s])
    tip_l, tip_r = junction[-2.0] + out_l, junction[2.0] + out_r
    inward = np.array([0.0, 1.0, 0.0])

    def jpts(y):  # joiner start, junction, end (left to right)
        a = junction[y] - h * (-out_l if y == -2.0 else inward)
        b = junction[y] + h * (out_r if y == 2.0 else inward)
        return a, junction[y], b

    # Wing chain from the left tip to the right tip: (group, start, end, elements)
    segs = []
    prev = tip_l
    for k, (sec, y) in enumerate(zip(SECTIONS[:5], JUNCTIONS_Y)):
        a, m, b = jpts(y)
        segs.append((sec, prev, a, n_per_section))
        segs.append((JOINERS[k], a, m, 1))
        segs.append((JOINERS[k], m, b, 1))
        prev = b
    segs.append((SECTIONS[5], prev, tip_r, n_per_section))

    E0, G0 = E_WING, G_WING
    wing_ids = {}
    chain = [int(model.add_nodes([tip_l])[0])]
    group_pairs: dict[str, list] = {}
    for name, a, b, n in segs:
        ids = model.add_nodes(_points(a, b, n)[1:])
        nodes = [chain[-1], *ids.tolist()]
        chain.extend(ids.tolist())
        group_pairs.setdefault(name, []).extend(pairwise(nodes))
        wing_ids.setdefault(name, []).extend(nodes)
    xyz = dict(zip(model.node_ids.tolist(), model.xyz))

    def node_at(point):
        ids = np.array(chain)
        d = np.linalg.norm(np.array([xyz[i] for i in ids]) - point, axis=1)
        return int(ids[np.argmin(d)])

    junction_node = {y: node_at(junction[y]) for y in JUNCTIONS_Y}

    A = p["area_wing"]
    for name in SECTIONS + JOINERS:
        fe, fg = factors.get(f"E_{name}", 1.0), factors.get(f"G_{name}", 1.0)
        if name in SECTIONS:
            mu, stiff, it = p["mu_wing"], 1.0, p["it_wing"]
        else:
            mu, stiff, it = p["mu_joiner"], p["joiner_stiffening"], p["it_wing"] * p["mu_joiner"] / p["mu_wing"]
        rho = mu / A * mass_factors.get(name, 1.0)
        section = GeneralSection(A=A, Iy=stiff * p["EI_oop"] / E0, Iz=stiff * p["EI_ip"] / E0,
                                 J=stiff * p["GJ"] / G0, Ip=it / (mu / A))
        mat = Material(f"{name} foam-filled fibreglass (equivalent)", E=E0 * fe, G=G0 * fg, rho=rho)
        model.add_beams(np.array(group_pairs[name]), mat, section, orientation=(0, 0, 1), rotary_inertia=False,
                        name=name)

    # Tail booms (aft from the pods) and their wing-tail springs
    n_boom = max(2, n_per_section // 2)
    ro, ri = p["boom_radius"]
    boom = CircularTubeSection(ro, ri, shear=False)
    boom_mass = p["boom_rho"] * math.pi * (ro**2 - ri**2) * p["boom_length"]
    tail_nodes = {}
    for y in BOOM_JUNCTIONS:
        root = junction[y]
        ids = model.add_nodes(_points(root, root + np.array([p["boom_length"], 0, 0]), n_boom))
        name = f"tail_boom_{'L' if y < 0 else 'R'}{int(abs(y))}"
        mat = Material(f"{name} (E 5.0 GPa)", E=E_BOOM * factors.get("E_tail_boom", 1.0),
                       G=G_BOOM * factors.get("G_tail_boom", 1.0),
                       rho=p["boom_rho"] * mass_factors.get(name, 1.0))
        model.add_beams(np.c_[ids[:-1], ids[1:]], mat, boom, orientation=(0, 0, 1), rotary_inertia=False, name=name)
        kf = np.array([factors.get(f"k{i}_wing_tail", 1.0) for i in range(1, 7)])
        model.add_spring(junction_node[y], int(ids[0]), stiffness=K_WING_TAIL * kf, name=f"wing_{name}")
        mt = p["tail_mass"] * mass_factors.get(name, 1.0)
        b, ch = p["tail_span"], p["tail_chord"]
        model.add_mass(int(ids[-1]), mt, inertia=(mt * b * b / 12, mt * ch * ch / 12, mt * (b * b + ch * ch) / 12),
                       name=name.replace("_boom", ""))
        tail_nodes[name] = int(ids[-1])

    # Pods: what the budget leaves after wing, joiners, booms and tails, centre pod heavier
    wing_mass = p["mu_wing"] * (4 * (1 - 2 * h) + 2 * (1 - h)) + p["mu_joiner"] * 10 * h
    rest = GROSS_MASS - wing_mass - len(BOOM_JUNCTIONS) * (boom_mass + p["tail_mass"])
    pod_mass = {y: (p["pod_mass_centre"] if y == 0.0 else (rest - p["pod_mass_centre"]) / 4) for y in JUNCTIONS_Y}
    if min(pod_mass.values()) <= 0:
        raise ModelError("xhale: the mass budget leaves nothing for the pods")
    # Pod cg ahead of the wing so that the aircraft's cg lies on the wing's reference line (x = 0)
    moment_aft = len(BOOM_JUNCTIONS) * (boom_mass * p["boom_length"] / 2 + p["tail_mass"] * p["boom_length"])
    pod_x = -moment_aft / sum(pod_mass.values())
    for y in JUNCTIONS_Y:
        m = pod_mass[y] * mass_factors.get(f"pod_{y:+.0f}", 1.0)
        model.add_mass(junction_node[y], m, offset=(pod_x, 0.0, p["pod_offset_z"]),
                       inertia=np.array(p["pod_inertia"]) * m / pod_mass[y], name=f"pod_{y:+.0f}")
    return model, {"junction": junction_node, "tail": tail_nodes, "chain": chain, "groups": wing_ids,
                   "pod_x": pod_x, "pod_mass": pod_mass}


def _configurations(model: Model, info: dict, p: dict) -> dict[str, Configuration]:
    weight = GROSS_MASS * STANDARD_GRAVITY
    xyz = dict(zip(model.node_ids.tolist(), model.xyz))

    def lab(y):
        """Spring-and-pulley suspension: a cord of the line's rate K (its stretch takes the weight) and a
        grounded lateral spring that makes the pendulum arm the string below the pulley."""
        cords, springs = [], []
        for side, yy in (("left", -y), ("right", y)):
            k, c = SUSPENSION[side]
            node = info["junction"][yy]
            T = 0.5 * weight
            # anchor such that at least 0.5 m of unstretched cord remains; a pendulum longer than
            # that is the cord itself
            height = max(T / k + 0.5, p["pendulum_length"])
            cords.append(Cord(node=node, anchor=tuple(xyz[node] + np.array([0.0, 0.0, height])), stiffness=k,
                              damping=c, unstretched_length=height - T / k))
            k_lat = T * (1.0 / p["pendulum_length"] - 1.0 / height)
            if k_lat > 0:
                springs.append(Spring.make(node, None, stiffness=[k_lat, k_lat, 0, 0, 0, 0]))
        return tuple(cords), tuple(springs)

    def bungee(y, mu=0.0, segments=0):
        """The free-flying test's 20 m bungees from a crane; with mu [kg/m] and segments, each one's
        own mass distributed over that many members (its surge and string modes in the solve), the
        crane that much higher that the aircraft hangs where the massless cords hold it."""
        cords = []
        for EA, yy in zip(BUNGEE_EA, (-y, y)):
            node = info["junction"][yy]
            k = EA / BUNGEE_LENGTH
            T = 0.5 * weight
            m = mu * BUNGEE_LENGTH
            height = BUNGEE_LENGTH + (T + 0.5 * m * STANDARD_GRAVITY) / k  # stretch under the end load and own weight
            cords.append(Cord(node=node, anchor=tuple(xyz[node] + np.array([0.0, 0.0, height])), stiffness=k,
                              unstretched_length=BUNGEE_LENGTH, mass=m, segments=segments))
        return tuple(cords)

    out = {"free_free": Configuration("free_free")}
    for name, y in (("outboard", 2.0), ("inboard", 1.0)):
        cords, springs = lab(y)
        out[name] = Configuration(name, suspension=cords, springs=springs, gravity=1.0)
    for name, y in (("bungee_outboard", 2.0), ("bungee_inboard", 1.0)):
        out[name] = Configuration(name, suspension=bungee(y), gravity=1.0)
        heavy = f"{name}_heavy"
        out[heavy] = Configuration(heavy, suspension=bungee(y, p["bungee_mass_per_length"], p["bungee_segments"]),
                                   gravity=1.0)
    return out


def _design_variables() -> list[tuple]:
    """The original work's 30 updating variables as (name, kind, targets, attribute, bounds)."""
    out = []
    for name in SECTIONS + JOINERS:
        for attr in ("E", "G"):
            out.append((f"{attr}_{name}", "beam", (name,), attr, (0.75, 1.25)))
    booms = tuple(f"tail_boom_{'L' if y < 0 else 'R'}{int(abs(y))}" for y in BOOM_JUNCTIONS)
    for attr in ("E", "G"):
        out.append((f"{attr}_tail_boom", "beam", booms, attr, (0.75, 1.25)))
    springs = ("wing_tail_boom_*",)  # the wing-tail springs
    for i in range(1, 7):
        out.append((f"k{i}_wing_tail", "spring", springs, f"k{i}", (0.5, 2.0)))
    return out


def _as_built_factors(seed: int) -> tuple[dict, dict]:
    """Seeded differences of the 'real airframe': stiffness factors the 30 variables can recover
    (E, G per wing group +-8 %, the booms' E, G +-8 %, wing-tail springs x 0.7) and mass factors
    they cannot (density of each wing group and boom, each pod mass, +-2 %)."""
    rng = np.random.default_rng(seed)
    factors = {}
    for name in SECTIONS + JOINERS:
        factors[f"E_{name}"], factors[f"G_{name}"] = rng.uniform(0.92, 1.08, 2)
    factors["E_tail_boom"], factors["G_tail_boom"] = rng.uniform(0.92, 1.08, 2)
    for i in range(1, 7):
        factors[f"k{i}_wing_tail"] = 0.7
    booms = [f"tail_boom_{'L' if y < 0 else 'R'}{int(abs(y))}" for y in BOOM_JUNCTIONS]
    pods = [f"pod_{y:+.0f}" for y in JUNCTIONS_Y]
    masses = dict(zip(list(SECTIONS + JOINERS) + booms + pods,
                      rng.uniform(0.98, 1.02, len(SECTIONS) + len(JOINERS) + len(booms) + len(pods))))
    return {k: float(v) for k, v in factors.items()}, {k: float(v) for k, v in masses.items()}


def _sensors(model: Model, info: dict) -> dict:
    """Accelerometers: normal to the wing at the leading and trailing edge (+-60 mm chordwise) at
    1/6, 1/2 and 5/6 of each section, fore-aft (x) at mid-section, vertical on each tail."""
    xyz = dict(zip(model.node_ids.tolist(), model.xyz))
    normal_out = {"L": (0.0, math.sin(DIHEDRAL), math.cos(DIHEDRAL)),
                  "R": (0.0, -math.sin(DIHEDRAL), math.cos(DIHEDRAL))}
    sensors = {}
    for sec in SECTIONS:
        nodes = info["groups"][sec]
        pts = np.array([xyz[n] for n in nodes])
        arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
        tag = sec[5:]
        normal = normal_out[tag[0]] if tag[1] == "3" else (0.0, 0.0, 1.0)
        # number the stations from the root outwards
        order = (1 / 6, 1 / 2, 5 / 6) if tag[0] == "R" else (5 / 6, 1 / 2, 1 / 6)
        for k, frac in enumerate(order, start=1):
            node = int(nodes[int(np.argmin(np.abs(arc - frac * arc[-1])))])
            for side, dx in (("LE", -0.06), ("TE", 0.06)):
                sensors[f"{tag}_{k}{side}"] = (node, (dx, 0.0, 0.0), normal)
            if k == 2:
                sensors[f"{tag}_{k}X"] = (node, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0))
    for name, node in info["tail"].items():
        sensors[f"tail_{name[-2:]}"] = (node, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    return sensors


def _properties(overrides: dict | None) -> dict:
    """NOMINAL with ``overrides`` (same keys, numbers of the same shape) checked."""
    p = dict(NOMINAL)
    unknown = sorted(set(overrides or {}) - set(p))
    if unknown:
        raise ModelError(f"xhale: unknown properties {unknown}; choose from {sorted(p)}")
    for key, value in (overrides or {}).items():
        default = np.atleast_1d(np.asarray(p[key], float))
        try:
            given = np.atleast_1d(np.asarray(value, float))
        except (TypeError, ValueError):
            given = None
        if given is None or given.shape != default.shape or not np.all(np.isfinite(given)) or (
                isinstance(p[key], int) and not float(given[0]).is_integer()):
            raise ModelError(f"xhale: property {key}={value!r} must be {default.size} finite number(s) like the "
                             f"default {p[key]!r}")
        p[key] = tuple(given.tolist()) if isinstance(p[key], tuple) else type(p[key])(given[0])
    if not 0.0 < p["joiner_half"] < 0.5:
        raise ModelError(f"xhale: joiner_half={p['joiner_half']} m must lie between 0 and 0.5 m (half a joiner's "
                         "length inside a 1 m section)")
    if p["pendulum_length"] <= 0.5:
        raise ModelError(f"xhale: pendulum_length={p['pendulum_length']} m must be a length above 0.5 m (the cord "
                         "below the pulley)")
    return p


def xhale(n_per_section: int = 8, as_built: bool = False, seed: int = 0, properties: dict | None = None) -> Case:
    """X-HALE-like very flexible flying wing on its lab suspension (docs/method.md section 5 case 6). SI units.

    Axes: x chordwise aft, y spanwise right, z up, gravity -z. Six 1 m wing sections (beam groups
    wing_L3 ... wing_R3, y from -3 to 3, outer two at 10 deg dihedral, tips at y = +-2.985 m,
    z = 0.174 m) joined by 0.08 m joiner groups joiner_L2 ... joiner_R2 at y = -2, -1, 0, 1, 2.
    Equivalent beam properties on E = 4.32 GPa, G = 1.71 GPa (one Material per group: the
    updating variables' initial values); joiners the same moduli with a section 2.1 times
    stiffer (the aluminium joiner inside). Wing 0.48 kg/m, EI flatwise 102, chordwise 7060,
    GJ 191 N m^2; bending rotary inertia off, torsional inertia 0.0015 kg m/m on.
    Five pods (3.40 kg centre, 0.92 kg others) 50 mm below and ahead of the junctions with
    inertia; four tail booms (tail_boom_L2, _L1, _R1, _R2: 0.78 m fibreglass tubes, E 5.0 GPa,
    G 1.88 GPa) aft from the pods at y = +-1, +-2 with a 32 g horizontal tail (mass and inertia)
    at the end, each joined to the wing by a 6-component spring of 1e8 N/m, N m/rad between
    coincident nodes (springs named wing_tail_boom_L2 ... _R2; the pods' masses pod_-2 ... pod_+2,
    the tails' tail_L2 ... tail_R2). Gross mass 11.35 kg, cg at x = y = 0.

    Configurations: outboard / inboard (cords at the junctions y = +-2 / +-1 m, 1 g): left
    K = 17.59 N/m, C = 0.94 N s/m, right K = 18.01 N/m, C = 1.35 N s/m, each carrying half the
    weight; the spring-and-pulley line is a cord of rate K plus a grounded spanwise/fore-aft spring
    that makes the pendulum arm the Kevlar string below the pulley (properties['pendulum_length'],
    3 m; not published: the lab fit and the predictions against it in docs/updating.md); a pendulum
    longer than the cord's 3.7 m is the cord itself, anchored that high. free_free (no
    suspension, no gravity). bungee_outboard / bungee_inboard: two bungees of 20 m unstretched,
    EA 92.5 N (left) and 100 N (right), k = EA / 20 m, from a crane, 1 g (stretched to 31 m).
    bungee_outboard_heavy / bungee_inboard_heavy: the same bungees with their own mass (assumed
    0.02 kg/m, 0.4 kg each; not published) distributed over 10 members (fg.Cord(segments=10)), so
    their surge (1.77 Hz) and string (1.06 Hz, ...) modes are in the modal solve.

    Tuned (section properties, pod and tail masses, boom length) to the original work's initial
    FE model (references['original_initial_fem_hz']): every listed mode within 4.2 %, 15 of 16
    within 3 % (table in the tests and in references['tuned_hz']).
    as_built=True: the 'real airframe' for synthetic GVTs, deterministic per seed: E, G of each
    wing group and of the booms (one factor for all) x U(0.92, 1.08), wing-tail springs x 0.7
    (references['as_built_factors'] are the 30 variables' true values), plus densities and pod
    masses x U(0.98, 1.02), a model-form error the variables cannot recover.
    properties: values of NOMINAL to change (chosen dimensions the publication does not give, e.g.
    {"pendulum_length": 6.0, "joiner_half": 0.06, "pod_offset_z": -0.1}; references['properties']
    lists them all).
    """
    if int(n_per_section) < 2:
        raise ModelError("xhale: n_per_section must be at least 2")
    p = _properties(properties)
    factors, mass_factors = _as_built_factors(seed) if as_built else ({}, {})
    model, info = _build(p, int(n_per_section), factors, mass_factors)
    if as_built:
        model.name = f"X-HALE-like flying wing, as built (seed {seed})"
    configs = _configurations(model, info, p)
    variables = _design_variables()
    truth = {v[0]: factors.get(v[0], 1.0) for v in variables}
    references = {
        "labels": LABELS,
        "measured_hz": dict(MEASURED_HZ),
        "original_initial_fem_hz": dict(ORIGINAL_INITIAL_HZ),
        "original_updated_fem_hz": dict(ORIGINAL_UPDATED_HZ),
        "tuned_hz": dict(TUNED_HZ),
        "gross_mass_kg": GROSS_MASS,
        "suspension_nodes": {name: tuple(c.node for c in cfg.suspension) for name, cfg in configs.items()
                             if cfg.suspension},
        "junction_nodes": dict(info["junction"]),
        "tail_nodes": dict(info["tail"]),
        "suspension": {"left": SUSPENSION["left"], "right": SUSPENSION["right"],
                       "pendulum_length_m": p["pendulum_length"], "bungee_EA_N": BUNGEE_EA,
                       "bungee_length_m": BUNGEE_LENGTH,
                       "bungee_mass_per_length_kg_per_m": p["bungee_mass_per_length"],
                       "bungee_segments": p["bungee_segments"]},
        "design_variables": variables,
        "as_built_factors": truth,
        "as_built_mass_factors": dict(mass_factors),
        "properties": p,
    }
    return Case("xhale", model, configs, xhale.__doc__ or "", references=references,
                   sensors=_sensors(model, info))


def match_modes(modes: Any, targets_hz: ArrayLike, labels: Sequence[str] = LABELS) -> list[int]:
    """Indices of the modes of ``modes`` that pair with the listed modes ``labels`` at ``targets_hz``.

    By shape class first, frequency second: 'Plunge' pairs with the rigid-body/suspension modes
    labelled 'RB plunge'; a label with T or IP (e.g. '1 T/2 IP') with the elastic modes whose
    strain energy is mostly torsion or in-plane bending; an 'OOP' label with those mostly
    out-of-plane bending. Within a class the pairing minimises the summed |log(f / target)|
    (one model mode per listed mode), so a mode out of order still finds its partner.
    """
    from scipy.optimize import linear_sum_assignment
    f = np.asarray(modes.frequencies_hz)
    fr = modes.energy_fractions
    rigid = np.array([lab.startswith("RB") or "bungee" in lab for lab in modes.labels])  # a cord's own: no partner
    main = np.argmax(fr[:, :4], axis=1)
    pools = {"plunge": np.flatnonzero(np.array([lab == "RB plunge" for lab in modes.labels])),
             "oop": np.flatnonzero(~rigid & (main == 0)),
             "tip": np.flatnonzero(~rigid & ((main == 1) | (main == 2)))}

    def pool(label):
        if label.lower() == "plunge":
            return "plunge"
        return "tip" if ("T" in label.split() or "IP" in label or "/T" in label) else "oop"

    out = [-1] * len(labels)
    for key, cand in pools.items():
        rows = [i for i, lab in enumerate(labels) if pool(lab) == key]
        if not rows:
            continue
        if len(cand) < len(rows):
            raise ModelError(f"match_modes: {len(rows)} listed '{key}' modes but only {len(cand)} such model modes; "
                             "compute more modes")
        cost = np.abs(np.log(np.maximum(f[cand][None, :], 1e-9) / np.asarray(targets_hz, float)[rows][:, None]))
        r, c = linear_sum_assignment(cost)
        for i, j in zip(r, c):
            out[rows[i]] = int(cand[j])
    return out
