"""Where the wingbox's skins buckle (docs/shells.md, "The wingbox case"): the onset of the -1 g and 2.5 g
load paths on fg.cases.wingbox at several mesh sizes, two ways.

- solve_static(..., buckling="continue") as fg.updating.verify solves the reference: what the
  verification reports (flexgvt.updating.verify.Onset; None when the path met no buckling).
- A finer ramp (``scan``): converged increments every ``--step`` g (load_factors), the tangent's
  inertia at each and the tip's deflection per g: where it leaves the fundamental path (its
  deflection per g grows by 0.2 % over the value at ``--start`` g); where an increment is unstable,
  fem.stability's linear buckling estimate between it and the last stable one, with the groups and
  bays its shape deforms (Onset). ``--step 0.1 --start 0.4`` at 0.1 m: 0.5 g stable, 0.6 g unstable,
  0.594 g. (A ramp can leave the fundamental path near the
  bifurcation for a stable post-buckled branch inside one increment, with no converged increment
  unstable: solve_static then finds the onset from the knee of the path, fem.knee, since 27 Nov.)

Beside them the flat-panel closed form: the skin between two ribs (a = rib pitch along the load) and
the two spars (b = chord), simply supported, sigma_cr = k pi^2 D / (b^2 t), k = (b/a + a/b)^2 (one
half-wave each way), against the skin's bending stress at 1 g, M c / I from beam theory at the
bay's middle.

    nice python bench/wingbox_onset.py --sizes 0.25 0.1 0.05
    nice python bench/wingbox_onset.py --sizes 0.1 --no-verify-path --step 0.1 --start 0.4

Measured 2026-11-27 (docs/shells.md, "Where the wingbox's skins buckle, by mesh").
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time
import warnings

import numpy as np

import flexgvt as fg
from flexgvt.fem.stability import negative_eigenvalues
from flexgvt.fem.static import StaticSettings
from flexgvt.updating.verify import Onset

G = 9.80665


def closed_form(case, bay: int) -> dict:
    """The flat-panel buckling stress of a skin bay and the beam-theory skin stress at 1 g there."""
    from flexgvt.cases.wingbox import CHORD, DEPTH, E, NU, SKIN, SKIN_NSM, SPAN, SPAR, RHO
    pitch = SPAN / case.references["bays"]
    a, b, t = pitch, CHORD, SKIN
    D = E * t**3 / (12 * (1 - NU**2))
    k = (b / a + a / b) ** 2
    sigma_cr = k * np.pi**2 * D / (b**2 * t)
    mass = fg.mass_properties(case.model).mass
    w = mass * G / SPAN  # [N/m] (the ribs smeared)
    y = (bay - 0.5) * pitch
    moment = w * (SPAN - y) ** 2 / 2
    inertia = 2 * CHORD * SKIN * (DEPTH / 2) ** 2 + 2 * SPAR * DEPTH**3 / 12
    sigma = moment * (DEPTH / 2) / inertia
    del RHO, SKIN_NSM
    return {"bay": bay, "k": k, "sigma_cr_MPa": sigma_cr / 1e6, "sigma_1g_MPa": sigma / 1e6,
            "onset_g": sigma_cr / sigma}


def _located(state, prev, ramp, g_max: float) -> dict:
    """fem.stability's linear buckling estimate between the last stable increment ``prev`` and the
    unstable ``state`` (both on the fundamental path), with the elements its shape moves (Onset)."""
    from flexgvt.fem.stability import Instability, _linearised, _unit, _where
    if prev is None:
        return {}
    a = (prev.load_factor, prev.positions, prev.rotations)
    critical, shape = _linearised(state.system, a, (state.load_factor, state.positions, state.rotations))
    if critical is None:
        return {"located_g": None}
    event = Instability(float(critical), "bifurcation", 0.0, _unit(shape), _where(state.system, shape),
                        (prev.load_factor, state.load_factor))
    return {"located_g": critical * g_max,
            "onset": Onset.of(dataclasses.replace(state, instability=event, configuration=ramp), 0.5)}


def scan(case, name: str, g_max: float, step: float, start: float, departure: float = 0.002) -> dict:
    """The ramp to ``g_max`` g with converged increments every ``step`` g (load_factors), the tangent's
    inertia at each from ``start`` g and the tip's deflection per g: the first unstable increment, and
    the first whose deflection per g exceeds the one at ``start`` by ``departure`` (the path leaving the
    fundamental one for a wrinkled branch)."""
    cfg = case.configurations[name]
    ramp = dataclasses.replace(cfg, gravity=g_max)
    tip = case.references["tip_spar_nodes"][0]
    t0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        state = fg.solve_static(case.model, ramp, settings=StaticSettings(buckling="ignore"),
                                load_factors=np.arange(step, g_max + 1e-9, step) / g_max)
    rows, base, prev, out = [], None, None, {"unstable_g": None, "departure_g": None}
    for s in state.steps:
        g = s.load_factor * g_max
        per_g = float(s.displacements[s.node(tip), 2]) / g
        if g >= start - 1e-9:
            negative = negative_eigenvalues(s.system, s.positions, s.rotations, s.load_factor)
            base = per_g if base is None else base
            rows.append((round(g, 6), negative, per_g))
            if negative > 0 and out["unstable_g"] is None:
                out["unstable_g"] = round(g, 6)
                out.update(_located(s, prev, ramp, g_max))
            if out["departure_g"] is None and abs(per_g) > abs(base) * (1 + departure):
                out["departure_g"] = round(g, 6)
        prev = s
    out.update(path=rows, cpu_s=time.process_time() - t0)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=float, nargs="+", default=[0.25, 0.1])
    parser.add_argument("--step", type=float, default=0.025, help="scan increment [g]")
    parser.add_argument("--start", type=float, default=0.3, help="first increment estimated from [g]")
    parser.add_argument("--no-verify-path", action="store_true", help="skip the solve_static(continue) run")
    args = parser.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    for h in args.sizes:
        case = fg.cases.wingbox(element_size=h)
        print(f"\nwingbox {h:g} m: {len(case.model.node_ids)} nodes", flush=True)
        for name, g_max in (("minus_1g", 1.0), ("plus_2_5g", 1.2)):
            if not args.no_verify_path:
                t0 = time.process_time()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    state = fg.solve_static(case.model, case.configurations[name],
                                            settings=StaticSettings(buckling="continue"))
                onset = Onset.of(state, 0.5)
                print(f"  {name} as verify solves it ({time.process_time() - t0:.1f} CPU s): "
                      f"{onset.describe() if onset else 'no unstable increment found'}", flush=True)
            found = scan(case, name, g_max, args.step, args.start)
            path = ", ".join(f"{g:.3f} g: {w:+.5f} m/g ({n})" for g, n, w in found["path"])
            print(f"    ramp every {args.step:g} g (tip deflection per g, negative eigenvalues): {path}")
            print(f"  {name} ramp every {args.step:g} g ({found['cpu_s']:.1f} CPU s): first unstable increment at "
                  f"{found['unstable_g']} g, leaves the fundamental path at {found['departure_g']} g", flush=True)
            if found.get("onset") is not None:
                o = found["onset"]
                print(f"  {name} linear buckling between the last stable and the first unstable increment: "
                      f"{found['located_g']:.4f} g, {', '.join(o.groups)}, bays {list(o.bays)}, "
                      f"y {o.span[0]:.2f}-{o.span[1]:.2f} m", flush=True)
    case = fg.cases.wingbox(element_size=0.25)
    for bay in (1, 2, 4):
        c = closed_form(case, bay)
        print(f"closed form, bay {bay}: k {c['k']:.3f}, sigma_cr {c['sigma_cr_MPa']:.2f} MPa, skin stress at 1 g "
              f"{c['sigma_1g_MPa']:.2f} MPa: onset {c['onset_g']:.3f} g")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
