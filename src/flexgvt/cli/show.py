"""`flexgvt show model TARGET`: what a deck, a project or a built-in case holds, by the names and ids
projects, design variables and results use: beam and shell groups, masses, springs, and the
configurations with their supports, loads and cords. SI units throughout (a deck in other units is
converted on reading, --units)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import typer
from rich.console import Console

from ..errors import FlexGVTError
from .tables import print_table

app = typer.Typer(no_args_is_help=True, help="Show what a deck, project or built-in case holds.")

DECKS = (".bdf", ".dat", ".nas", ".blk")


def _g(v: float) -> str:
    return f"{v:.6g}"


def _vec(v) -> str:
    """A vector to 6 digits; round-off below 1e-12 of its largest entry shown as 0 (and no "-0")."""
    v = np.asarray(v, float).ravel()
    v = np.where(np.abs(v) <= 1e-12 * np.abs(v).max(initial=0.0), 0.0, v) + 0.0
    return "(" + ", ".join(_g(x) for x in v) + ")"


def _load(target: str, units: str, allow_unsupported: bool, notes: list[str]):
    """(title, model, configurations {name: (Configuration, role or subcase)}, deck or None)."""
    path = Path(target)
    if path.suffix.lower() == ".toml":
        from ..workflow import load_project
        p = load_project(path)
        roles = {c.name: c.role for c in p.spec.configurations}
        configs = {n: (c, roles.get(n, "")) for n, c in p.configurations.items()}
        configs.update({n: (c, "model (not tested)") for n, c in p.available.items() if n not in configs})
        return f"project {path.name}", p.model, configs, p.deck
    if path.suffix.lower() in DECKS:
        from ..io.nastran import Units, read_bdf
        from ..workflow.units import unit_system
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            deck = read_bdf(path, units=Units(*unit_system(units, "--units")),
                            unsupported="warn" if allow_unsupported else "error")
        notes += [str(w.message) for w in caught]
        configs = {n: (c, f"SUBCASE {deck.subcases.get(n, '')}".strip()) for n, c in deck.configurations.items()}
        return f"deck {path.name}", deck.model, configs, deck
    from ..cases import get
    case = get(target)
    return f"case {case.name}", case.model, {n: (c, "") for n, c in case.configurations.items()}, None


def _beams(console: Console, model, deck) -> None:
    sources = {} if deck is None else dict(deck.beams)
    rows = []
    for k, g in enumerate(model.beams):
        a, b = model.index_of(g.nodes[:, 0]), model.index_of(g.nodes[:, 1])
        length = float(np.linalg.norm(model.xyz[b] - model.xyz[a], axis=1).sum())
        area = g.section.properties().get("A", float("nan"))
        src = sources.get(g.name)
        rows.append([k + 1, g.name, len(g.ids), "" if src is None else f"{src.ptype} {src.pid}",
                     type(g.section).__name__.replace("Section", ""), _g(g.material.E), _g(g.material.rho),
                     _g(area), _g(length), _g(g.material.rho * area * length)])
    print_table(console, f"beam groups ({len(rows)}): address them by name in [[variables]] targets",
                ["#", "name", "elements", "Nastran", "section", "E [Pa]", "rho [kg/m^3]", "A [m^2]", "length [m]",
                 "rho A L [kg]"], rows, key=2,
                justify=["right", "left", "right", "left", "left", "right", "right", "right", "right", "right"])


def _shells(console: Console, model) -> None:
    rows = [[k + 1, g.name, len(g.ids), g.nodes.shape[1], type(g.property).__name__, g.property.name,
             "" if getattr(g.property, "thickness", None) is None else _g(g.property.thickness)]
            for k, g in enumerate(model.shells)]
    if rows:
        print_table(console, f"shell groups ({len(rows)})", ["#", "name", "elements", "nodes each", "property",
                                                             "property name", "thickness [m]"], rows, key=2,
                    justify=["right", "left", "right", "right", "left", "left", "right"])


def _masses(console: Console, masses, sources, title: str) -> None:
    rows = []
    for k, m in enumerate(masses):
        src = sources[k] if k < len(sources) else None
        rows.append([k + 1, m.name, "" if m.id is None else m.id, "" if src is None else f"{src[0]} {src[1]}",
                     m.node, _g(m.mass), _vec(m.offset), _g(float(np.trace(m.inertia)))])
    if rows:
        print_table(console, title, ["#", "name", "id", "Nastran", "node", "mass [kg]", "offset [m]",
                                     "trace I [kg m^2]"], rows, key=3,
                    justify=["right", "left", "right", "left", "right", "right", "right", "right"])


def _springs(console: Console, springs, sources, title: str) -> None:
    rows = []
    for k, s in enumerate(springs):
        src = sources[k] if k < len(sources) else None
        k6, c6 = np.asarray(s.stiffness, float), np.asarray(s.damping, float)
        tabled = ",".join(str(c + 1) for c, t in enumerate(s.tables or ()) if t is not None)
        rows.append([k + 1, s.name, "" if s.id is None else s.id, "" if src is None else f"{src[0]} {src[1]}",
                     f"{s.node_a}-{'ground' if s.node_b is None else s.node_b}", _vec(k6[:3]), _vec(k6[3:]),
                     _vec(c6[:3]) if np.any(c6[:3]) else "", _vec(c6[3:]) if np.any(c6[3:]) else "", tabled])
    if not rows:
        return
    heads = ["#", "name", "id", "Nastran", "nodes", "K 1-3 [N/m]", "K 4-6 [N m/rad]", "C 1-3 [N s/m]",
             "C 4-6 [N m s/rad]", "table components (K at zero)"]
    justify = ["right", "left", "right", "left", "left", "right", "right", "right", "right", "left"]
    if not any(r[-1] for r in rows):
        rows, heads, justify = [r[:-1] for r in rows], heads[:-1], justify[:-1]
    print_table(console, title, heads, rows, key=3, justify=justify)


def _configurations(console: Console, configs: dict) -> None:
    rows, loads, cords = [], [], []
    for name, (c, role) in configs.items():
        fixed = ", ".join(f"{n}:{d}" for n, d in list(c.fixed.items())[:4]) + (" ..." if len(c.fixed) > 4 else "")
        rows.append([name, role, _g(c.gravity * c.g) if c.gravity else "0", fixed, len(c.forces) + len(c.distributed),
                     len(c.suspension), len(c.masses), len(c.springs)])
        if c.gravity:
            loads.append([name, "gravity", "all", _vec(np.asarray(c.gravity_direction) * c.gravity * c.g) + " m/s^2"])
        for f in c.forces:
            if np.any(f.force):
                loads.append([name, "force", f"node {f.node}", _vec(f.force) + " N"])
            if np.any(f.moment):
                loads.append([name, "moment", f"node {f.node}", _vec(f.moment) + " N m"])
        for d in c.distributed:
            els = ", ".join(map(str, d.elements[:4])) + (" ..." if len(d.elements) > 4 else "")
            loads.append([name, "distributed", f"elements {els}", _vec(d.per_length) + " N/m"])
        for n, comps in c.prescribed.items():
            loads.append([name, "enforced", f"node {n}", ", ".join(f"{k}: {_g(v)}" for k, v in comps.items())])
        for cd in c.suspension:
            cords.append([name, cd.node, _vec(cd.anchor), _g(cd.stiffness), _g(cd.unstretched_length),
                          _g(cd.damping), _g(cd.mass)])
    print_table(console, f"configurations ({len(rows)})", ["name", "role", "gravity [m/s^2]", "fixed node:DOFs",
                                                            "loads", "cords", "added masses", "added springs"],
                rows, justify=["left", "left", "right", "left", "right", "right", "right", "right"])
    if loads:
        print_table(console, "loads of the configurations (SI units as shown)",
                    ["configuration", "kind", "where", "value"], loads, justify=["left"] * 4)
    if cords:
        print_table(console, "cords (suspension lines) of the configurations",
                    ["configuration", "node", "anchor [m]", "stiffness [N/m]", "unstretched length [m]",
                     "damping [N s/m]", "mass [kg]"], cords, justify=["left"] + ["right"] * 6)
    for name, (c, _) in configs.items():
        _masses(console, c.masses, [], f"masses added in '{name}'")
        _springs(console, c.springs, [], f"springs added in '{name}'")


def register(parent: typer.Typer, console: Console) -> None:
    @app.command("model")
    def show_model(target: str = typer.Argument(..., help="a Nastran deck (.bdf, .dat, .nas, .blk), a project "
                                                "(.toml) or a built-in case (cantilever_strip, strip_366, hale_wing, "
                                                "wingbox, swept_wing, "
                                                "xhale)"),
                   units: str = typer.Option("SI", help="a deck's units: SI (m-kg-s), mm-N-t-s (mm-t-s), in-lbf-s, "
                                             "ft-lbf-s; shown converted to SI"),
                   allow_unsupported: bool = typer.Option(False, help="a deck: warn about unsupported cards "
                                                          "instead of failing")):
        """List a model's beam and shell groups, masses, springs, and configurations with their
        loads and cords: the names and ids projects and design variables address (SI units)."""
        from .workflow import fail
        try:
            notes: list[str] = []
            title, model, configs, deck = _load(target, units, allow_unsupported, notes)
            for note in notes:
                console.print(f"note: {note}", markup=False, highlight=False)
            from ..fem import mass_properties
            mp = mass_properties(model)
            console.print(f"{title}: model '{model.name}', {model.n_nodes} nodes, "
                          f"{sum(len(g.ids) for g in model.beams)} beam elements, "
                          f"{sum(len(g.ids) for g in model.shells)} shell elements, mass {_g(mp.mass)} kg, "
                          f"centre of gravity {_vec(mp.cg)} m (undeformed)", markup=False, highlight=False)
            _beams(console, model, deck)
            _shells(console, model)
            _masses(console, model.masses, [] if deck is None else deck.mass_sources,
                    f"masses ({len(model.masses)}): address them by name or id")
            _springs(console, model.springs, [] if deck is None else deck.spring_sources,
                     f"springs ({len(model.springs)}): address them by name or id")
            _configurations(console, configs)
        except (FlexGVTError, OSError) as exc:
            fail(console, exc)

    parent.add_typer(app, name="show")
