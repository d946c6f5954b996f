"""Writing configurations as subcases of a compact deck: SPC1, SPCD, GRAV, FORCE/MOMENT, PLOAD1
combined by LOAD, an EIGRL, and the case control selecting them."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import Configuration
from ._common import Units


def write_configurations(bdf, configurations: list[Configuration], u: Units, n_modes: int, elem_nodes,
                          mpc: bool = False) -> None:
    from pyNastran.bdf.case_control_deck import CaseControlDeck

    lines = ["ECHO = NONE", "METHOD = 1"] + (["MPC = 1"] if mpc else [])
    bdf.add_eigrl(1, nd=n_modes)
    for i, cfg in enumerate(configurations, start=1):
        if cfg.suspension or cfg.springs or cfg.masses:
            raise ModelError(f"write_bdf: configuration '{cfg.name}' has cords, springs or masses of its own; bulk "
                             "data has no per-subcase elements. Put them in the model before writing")
        lines += [f"SUBCASE {i}", f"  LABEL = {cfg.name}"]
        by_comp: dict[str, list[int]] = {}
        held = {int(n): set(c) for n, c in cfg.fixed.items()}
        for node, items in cfg.prescribed.items():  # prescribed DOFs are SPC'd, their values are SPCDs
            held.setdefault(int(node), set()).update(str(c) for c in items)
        for node, comps in held.items():
            by_comp.setdefault("".join(sorted(comps)), []).append(int(node))
        for comps, nodes in sorted(by_comp.items()):
            bdf.add_spc1(i, comps, sorted(nodes))
        if by_comp:
            lines.append(f"  SPC = {i}")
        factors, sets = [], []
        if cfg.gravity:
            d = np.asarray(cfg.gravity_direction, float)
            bdf.add_grav(200 + i, cfg.g / u.length, list(d / np.linalg.norm(d)))
            factors.append(cfg.gravity)
            sets.append(200 + i)
        have = False
        for load in cfg.forces:
            f = np.asarray(load.force, float) / u.force
            m = np.asarray(load.moment, float) / u.moment
            if np.any(f):
                bdf.add_force(300 + i, load.node, 1.0, list(f))
                have = True
            if np.any(m):
                bdf.add_moment(300 + i, load.node, 1.0, list(m))
                have = True
        for dist in cfg.distributed:
            w = np.asarray(dist.per_length, float) * u.length / u.force
            for e in dist.elements:
                for k, axis in enumerate("XYZ"):
                    if w[k]:
                        bdf.add_pload1(300 + i, int(e), f"F{axis}", "FR", 0.0, w[k], 1.0, w[k])
                        have = True
        for node, items in cfg.prescribed.items():
            for comp, value in sorted(items.items()):
                bdf.add_spcd(300 + i, [int(node)], [str(comp)], [value / (u.length if comp <= 3 else 1.0)])
                have = True
        if have:
            factors.append(1.0)
            sets.append(300 + i)
        if sets:
            bdf.add_load(100 + i, 1.0, factors, sets)
            lines.append(f"  LOAD = {100 + i}")
    lines.append("BEGIN BULK")
    bdf.case_control_deck = CaseControlDeck(lines, bdf.log)
