"""Built-in structures of docs/method.md section 5, each with its model and named configurations:
cantilever_strip, strip_366, hale_wing, the X-HALE-like flying wing xhale (module xhale) and the
built-up shell wingbox (module wingbox) and the A3TB-WT-like swept wing swept_wing (module swept_wing).

    case = flexgvt.cases.cantilever_strip()
    case.model, case.configurations["self_weight"], case.references
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..model import (
    Configuration,
    Cord,
    GeneralSection,
    Material,
    Model,
    RectangularSection,
)
from .case import Case
from .xhale import match_modes as xhale_match_modes
from .swept_wing import swept_wing
from .wingbox import wingbox
from .xhale import xhale

__all__ = ["BUILTIN", "Case", "cantilever_strip", "get", "hale_wing", "strip_366", "swept_wing", "wingbox", "xhale",
           "xhale_match_modes"]


def _line(model: Model, start, end, n: int) -> np.ndarray:
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    return model.add_nodes(np.asarray(start, float) * (1 - t) + np.asarray(end, float) * t)


def cantilever_strip(n_elements: int = 150, E: float = 70e9, rho: float = 2700.0) -> Case:
    """Aluminium strip 1.5 m x 50 mm x 3 mm clamped at y = 0, in three equal regions (docs/method.md section 5 case 3).

    Span along y, width along x (chord), thickness along z; gravity along -z bends it flatwise.
    Bending rotary inertia is left out as the thin-strip reference solutions do.
    Configurations: unloaded, self_weight (1 g), flatwise_2g, flatwise_3g.
    """
    if n_elements % 3:
        raise ModelError("cantilever_strip: n_elements must be a multiple of 3 (three equal regions)")
    model = Model("cantilever strip")
    ids = _line(model, (0, 0, 0), (0, 1.5, 0), n_elements)
    k = n_elements // 3
    for r in range(3):
        mat = Material(f"Al region {r + 1}", E=E, nu=0.33, rho=rho)
        model.add_beams(np.c_[ids[r * k:(r + 1) * k], ids[r * k + 1:(r + 1) * k + 1]], mat,
                        RectangularSection(width=0.05, height=0.003), orientation=(0, 0, 1),
                        rotary_inertia=False, name=f"region{r + 1}")
    clamp = {int(ids[0]): "123456"}
    configs = {name: Configuration(name, fixed=clamp, gravity=g)
               for name, g in (("unloaded", 0.0), ("self_weight", 1.0), ("flatwise_2g", 2.0), ("flatwise_3g", 3.0))}
    return Case("cantilever_strip", model, configs, cantilever_strip.__doc__ or "",
                references={"tip_node": int(ids[-1]), "root_node": int(ids[0])})


# Accelerometer assumed for the 3.66 m strip: 2.5 g each with its cable share, on the top surface.
ACCELEROMETER_MASS = 0.0025
ACCELEROMETER_CHORD_OFFSET = 0.020


def strip_366(n_elements: int = 122, accelerometers: bool = True) -> Case:
    """Very flexible aluminium strip 3.66 m x 50.8 mm x 3.20 mm, 1.60 kg, E 68.9 GPa (docs/method.md section 5 case 2).

    Span along y centred at 0, chord along x, thickness along z. 26 accelerometers in 13 span
    stations, two per station at +-20 mm chordwise on the top surface (2.5 g each, assumed).
    Configurations: free_free (no gravity, no supports), outboard (cords 0.31 m from the ends),
    inboard (cords 1.22 m from the ends); suspension points as characterised in docs/method.md section 2:
    left K = 5.06 N/m, C = 0.28 N s/m; right K = 5.19 N/m, C = 0.45 N s/m; anchors 3 m above.
    """
    L, b, t, mass = 3.66, 0.0508, 0.0032, 1.60
    rho = mass / (L * b * t)
    model = Model("3.66 m strip")
    ys = np.linspace(-L / 2, L / 2, n_elements + 1)
    stations = np.linspace(-L / 2 + L / 26, L / 2 - L / 26, 13)
    at = {}
    for y in np.r_[stations, -L / 2 + 0.31, L / 2 - 0.31, -L / 2 + 1.22, L / 2 - 1.22]:
        k = int(np.argmin(np.abs(ys - y)))
        at[round(float(y), 6)] = k
        ys[k] = y
    ids = model.add_nodes(np.c_[np.zeros_like(ys), ys, np.zeros_like(ys)])
    al = Material("Al 3.66 m strip", E=68.9e9, nu=0.33, rho=rho)
    model.add_beams(np.c_[ids[:-1], ids[1:]], al, RectangularSection(width=b, height=t), orientation=(0, 0, 1),
                    rotary_inertia=False, name="strip")
    sensors = {}
    if accelerometers:
        for s, y in enumerate(stations):
            node = int(ids[at[round(float(y), 6)]])
            for side, dx in (("LE", -ACCELEROMETER_CHORD_OFFSET), ("TE", ACCELEROMETER_CHORD_OFFSET)):
                model.add_mass(node, ACCELEROMETER_MASS, offset=(dx, 0.0, t / 2), name=f"S{s + 1:02d}{side}")
                sensors[f"S{s + 1:02d}{side}"] = (node, (dx, 0.0, t / 2), (0.0, 0.0, 1.0))

    def hang(y_left, y_right):
        height = 3.0
        cords = []
        for y, k_s, c_s in ((y_left, 5.06, 0.28), (y_right, 5.19, 0.45)):
            node = int(ids[at[round(float(y), 6)]])
            share = 0.5 * (mass + (26 * ACCELEROMETER_MASS if accelerometers else 0.0)) * 9.80665
            cords.append(Cord(node=node, anchor=(0.0, float(y), height), stiffness=k_s, damping=c_s,
                              unstretched_length=height - share / k_s))
        return tuple(cords)

    configs = {
        "free_free": Configuration("free_free"),
        "outboard": Configuration("outboard", suspension=hang(-L / 2 + 0.31, L / 2 - 0.31), gravity=1.0),
        "inboard": Configuration("inboard", suspension=hang(-L / 2 + 1.22, L / 2 - 1.22), gravity=1.0),
    }
    return Case("strip_366", model, configs, strip_366.__doc__ or "", references={
        "free_free_first_bending_hz": 1.23, "end_nodes": (int(ids[0]), int(ids[-1])),
        "mid_node": int(ids[np.argmin(np.abs(ys))])}, sensors=sensors)


def hale_wing(n_elements: int = 32) -> Case:
    """HALE wing benchmark (Patil, Hodges & Cesnik 2001): 16 m cantilever along y, 0.75 kg/m,
    torsional inertia 0.1 kg m, EI flap 2e4, EI edge 4e6, GJ 1e4 N m^2; no gravity.

    The section is given by its stiffness: E = 1 GPa with A, I, J chosen to give the products.
    """
    E, G = 1.0e9, 0.5e9
    section = GeneralSection(A=1.0, Iy=2e4 / E, Iz=4e6 / E, J=1e4 / G, Ip=0.1 / 0.75)
    mat = Material("HALE wing (stiffness-defined)", E=E, G=G, rho=0.75)
    model = Model("HALE wing")
    ids = _line(model, (0, 0, 0), (0, 16.0, 0), n_elements)
    model.add_beams(np.c_[ids[:-1], ids[1:]], mat, section, orientation=(0, 0, 1), rotary_inertia=False,
                    name="wing")
    configs = {"unloaded": Configuration("unloaded", fixed={int(ids[0]): "123456"}),
               "gravity": Configuration("gravity", fixed={int(ids[0]): "123456"}, gravity=1.0)}
    # Frequencies [rad/s] as tabulated by Patil, Hodges & Cesnik, J. Aircraft 38(1), 2001.
    return Case("hale_wing", model, configs, hale_wing.__doc__ or "", references={
        "published_rad_s": {"1 OOP": 2.247, "2 OOP": 14.606, "3 OOP": 44.012, "1 T": 31.146, "1 IP": 31.739},
        "tip_node": int(ids[-1])})


BUILTIN = {"cantilever_strip": cantilever_strip, "strip_366": strip_366, "hale_wing": hale_wing, "xhale": xhale,
           "wingbox": wingbox, "swept_wing": swept_wing}


def get(name: str, **kwargs) -> Case:
    """A built-in case by name."""
    try:
        return BUILTIN[name](**kwargs)
    except KeyError:
        raise ModelError(f"no built-in case '{name}'; choose one of {sorted(BUILTIN)}") from None
