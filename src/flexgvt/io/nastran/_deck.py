"""The parsed deck and what the card families share: Deck (the cards, where each sits, the deck's
units and mass settings, the grid positions), Findings (notes and unsupported cards), Parts (what
one family hands to the next and to BdfDeck) and Family (one registry entry)."""

from __future__ import annotations

import contextlib
import io
import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ...errors import FlexGVTError, ModelError
from ...model import Material, Model
from ._checks import check_ids_and_values, check_references
from ._common import Units
from ._grids import grid_positions
from ._parse import CardIndex, check_duplicates, exception_text, parse_bdf, where_prefix

# PARAMs that change the structure in Nastran but not in flexgvt: named in a note when present.
STRUCTURAL_PARAMS_IGNORED = {"G": "structural damping (PARAM,G) is not modelled",
                             "W3": "PARAM,W3 (structural damping reference) is not modelled",
                             "W4": "PARAM,W4 (element damping reference) is not modelled"}


@dataclass(frozen=True)
class Deck:
    """A parsed, checked and cross-referenced bulk data deck: read-only input of every card family.

    bdf: pyNastran's BDF (cards by type: bdf.nodes, .elements, .properties, .materials, .masses,
    .rigid_elements, .loads, .spcs, ...); index: file and line of every card (for messages);
    units, wtmass (PARAM,WTMASS), mass ('lumped' or 'consistent', from COUPMASS or read_bdf's
    mass=), rotary_inertia and cbar_torsional_inertia: read_bdf's options; grid_ids and positions
    [m]: the grids in id order; xyz and xyz_deck: grid id -> basic position in m and in deck length units;
    notes: what parsing noted (a repeated BEGIN BULK, GRDSET defaults, ignored PARAMs).
    """

    path: Path
    bdf: object
    index: CardIndex
    units: Units
    wtmass: float
    mass: str
    rotary_inertia: bool
    cbar_torsional_inertia: bool
    grid_ids: tuple[int, ...]
    positions: np.ndarray
    xyz: dict[int, np.ndarray]
    xyz_deck: dict[int, np.ndarray]
    notes: tuple[str, ...] = ()

    def at(self, name: str, ident) -> str:
        """'file:line: NAME id' of a card (or 'NAME id' when the index has no line for it)."""
        return where_prefix(self.index, name, ident)

    def param(self, name: str, default):
        """The first value of PARAM ``name``, or ``default``."""
        return _param(self.bdf, name, default)


class Findings:
    """What a read noted (approximations, cards ignored on purpose) and the cards, or card features,
    it could not represent (description -> ids); read_bdf reports both in one place."""

    def __init__(self, notes=()) -> None:
        self.notes: list[str] = list(notes)
        self.unsupported: dict[str, list] = {}

    def note(self, text: str) -> None:
        self.notes.append(text)

    def skip(self, what: str, ident) -> None:
        """Record card (feature) ``what`` with id ``ident`` as not read."""
        self.unsupported.setdefault(what, []).append(ident)


# (grid, end node, components, source): a node a family added at a beam offset, pin or bush location,
# tied to its grid by a rigid link once the deck's RBE2s are known (see _rigid).
EndLink = tuple[int, int, str, tuple]


@dataclass(frozen=True)
class Parts:
    """What card families have read so far, beyond what they added to the Model: the bookkeeping
    that write_bdf and later families need. Each family returns its own Parts; read_bdf merges
    them in registry order (dicts updated, sequences concatenated).

    materials: MAT1 id -> Material; beams: beam group name -> BeamSource; element_ids: Nastran
    element id -> flexgvt element id; mass_sources / spring_sources / rigid_sources /
    interpolation_sources: the card behind each model entry, in model order; end_nodes: (card,
    element id, end) -> added node; end_links: EndLinks waiting for the rigid family; shells: shell
    group name -> ShellSource; options: deck settings kept for the solver (PARAM,K6ROT; the Guyan
    reduction sets 'ASET' and 'OMIT', see _reduction).
    """

    materials: dict[int, Material] = field(default_factory=dict)
    beams: dict = field(default_factory=dict)
    element_ids: dict[int, int] = field(default_factory=dict)
    mass_sources: tuple[tuple[str, int], ...] = ()
    spring_sources: tuple[tuple[str, int], ...] = ()
    rigid_sources: tuple[tuple, ...] = ()
    interpolation_sources: tuple[int, ...] = ()
    end_nodes: dict[tuple[str, int, str], int] = field(default_factory=dict)
    end_links: tuple[EndLink, ...] = ()
    shells: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)

    def merged(self, other: Parts) -> Parts:
        """These parts followed by ``other``'s."""
        values = {}
        for f in fields(self):
            a, b = getattr(self, f.name), getattr(other, f.name)
            values[f.name] = {**a, **b} if isinstance(a, dict) else tuple(a) + tuple(b)
        return Parts(**values)


@dataclass(frozen=True)
class Family:
    """One card family of the registry.

    name: label; cards: the bulk cards it reads (any other card is reported unsupported);
    read(deck, model, findings, parts so far) -> its Parts, adding its entities to the model;
    needs_property / needs_material: its cards whose PID / MID must name a defined card (checked
    before any family reads).
    """

    name: str
    cards: tuple[str, ...]
    read: Callable[[Deck, Model, Findings, Parts], Parts]
    needs_property: tuple[str, ...] = ()
    needs_material: tuple[str, ...] = ()


def _param(bdf, name: str, default):
    p = bdf.params.get(name)
    if p is None:
        return default
    values = getattr(p, "values", None) or [default]
    return values[0] if values[0] is not None else default


def load_deck(path: Path, units: Units, mass: str | None, rotary_inertia: bool, cbar_torsional_inertia: bool,
              needs_property: frozenset[str], needs_material: frozenset[str]) -> Deck:
    """Parse ``path`` (INCLUDEs followed), check ids, values and references, resolve coordinate
    systems and grids: the Deck every family reads. Raises FileFormatError / ModelError naming
    file, line and card."""
    index = CardIndex(path)
    check_duplicates(path, index)
    notes: list[str] = []
    bdf = parse_bdf(path, index, notes)
    grdset = getattr(bdf, "grdset", None)
    if grdset is not None:  # GRDSET defaults for blank GRID fields (pyNastran reads blanks as 0)
        for node in bdf.nodes.values():
            node.cp = node.cp or (grdset.cp or 0)
            node.cd = node.cd or (grdset.cd or 0)
            node.ps = node.ps or (grdset.ps or "")
        bdf.grdset = None
        notes.append("GRDSET defaults applied to GRID fields that are blank or 0")
    check_ids_and_values(bdf, index, path)
    check_references(bdf, index, path, needs_property, needs_material)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            bdf.cross_reference(xref=True, xref_nodes=True, xref_elements=False, xref_nodes_with_elements=False,
                                xref_properties=False, xref_masses=False, xref_materials=False, xref_loads=False,
                                xref_constraints=False, xref_aero=False, xref_sets=False, xref_optimization=False)
    except FlexGVTError:
        raise
    except Exception as exc:
        text = exception_text(exc)
        raise ModelError(f"{path}: coordinate systems or grids could not be resolved: "
                         f"{text.splitlines()[0] if text else type(exc).__name__}; check CORD/GRID cards") from exc
    wtmass = float(_param(bdf, "WTMASS", 1.0))
    if not (math.isfinite(wtmass) and wtmass > 0):
        raise ModelError(f"{path}: PARAM,WTMASS={wtmass} must be a positive number")
    coupmass = _param(bdf, "COUPMASS", -1)
    if isinstance(coupmass, str):
        coupmass = 1 if coupmass.upper() in ("ON", "YES") else -1
    mass = mass or ("consistent" if coupmass > 0 else "lumped")
    for name, why in STRUCTURAL_PARAMS_IGNORED.items():
        if name in bdf.params:
            notes.append(why)
    nids, xyz = grid_positions(bdf, index, path, units.length)
    by_id = dict(zip(nids, xyz))
    xyz_deck = {n: x / units.length for n, x in by_id.items()}
    return Deck(path, bdf, index, units, wtmass, mass, rotary_inertia, cbar_torsional_inertia, tuple(nids), xyz,
                by_id, xyz_deck, tuple(notes))
