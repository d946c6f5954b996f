"""Read a Nastran bulk data deck into a flexgvt Model and one Configuration per subcase.

The read is three steps: parse (pyNastran's card parser, with the file and line of every card),
check and resolve into a Deck (_deck.load_deck), then translate family by family (_registry):
each family takes the Deck and the parts read before it, adds its entities to the Model and
returns its own Parts. Cards no family reads are sorted out in one place (_unsupported).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

from ...errors import FileFormatError, ModelError
from ...model import Configuration, Material, Model
from ._common import EigenMethod, Units, UnsupportedCardsError, get_units
from ._deck import Findings, Parts, load_deck
from ._elements import BeamSource
from ._registry import FAMILIES, NEEDS_MATERIAL, NEEDS_PROPERTY, READ_CARDS
from ._subcases import read_subcases
from ._unsupported import list_other_cards, unsupported_hints


@dataclass
class BdfDeck:
    """A bulk data deck read into flexgvt.

    model: the structural model; configurations: one per SUBCASE (or one named after the file);
    bdf: the pyNastran BDF object (kept for writing back); units: the deck's unit system; wtmass:
    PARAM,WTMASS; mass: 'lumped' or 'consistent' (PARAM,COUPMASS); beams: beam group name ->
    BeamSource; element_ids: Nastran beam element id -> flexgvt element id; mass_sources and
    spring_sources: (card, id) per entry of model.masses / model.springs; rigid_sources: RBE2 ids
    per model.rigid_links, or (card, element id, end) for the link of an end node; end_nodes:
    (card, element id, end 'A'/'B') -> the node flexgvt added for a CBAR/CBEAM offset or pin
    flag, or the CBUSH end's arm to the spring location (ids above the deck's grids);
    interpolation_sources: RBE3 id per model.interpolations; constraint_sources: MPC set id per
    model.constraints (the one set all subcases select); n_modes: configuration -> EIGRL ND of its METHOD (None if
    not given);
    methods: configuration -> its EigenMethod (EIGRL/EIGR: ND, window, normalisation) or None;
    subcases: configuration -> subcase id; unsupported: card (feature) -> ids that were not read;
    notes: things read with an approximation or ignored on purpose; shells: shell group name ->
    ShellSource (element card, property card and id, Nastran element ids; element_ids maps shell
    element ids too); options: deck settings kept for the solver: 'K6ROT' (PARAM,K6ROT), 'ASET' and
    'OMIT' (the Guyan reduction sets of ASET/ASET1 and OMIT/OMIT1: {grid id: components in basic axes},
    applied by solve_deck and by solve_modes(..., reduction=deck.options)).
    """

    path: Path
    model: Model
    configurations: dict[str, Configuration]
    bdf: object
    units: Units
    wtmass: float
    mass: str
    beams: dict[str, BeamSource] = field(default_factory=dict)
    element_ids: dict[int, int] = field(default_factory=dict)
    mass_sources: list[tuple[str, int]] = field(default_factory=list)
    spring_sources: list[tuple[str, int]] = field(default_factory=list)
    rigid_sources: list[tuple] = field(default_factory=list)
    end_nodes: dict[tuple[str, int, str], int] = field(default_factory=dict)
    interpolation_sources: list[int] = field(default_factory=list)
    constraint_sources: list[int] = field(default_factory=list)
    materials: dict[int, Material] = field(default_factory=dict)
    n_modes: dict[str, int | None] = field(default_factory=dict)
    methods: dict[str, EigenMethod | None] = field(default_factory=dict)
    subcases: dict[str, int] = field(default_factory=dict)
    unsupported: dict[str, list] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    shells: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        return (f"BdfDeck('{self.path.name}': {self.model!r}, configurations={list(self.configurations)}, "
                f"units={self.units.name}, wtmass={self.wtmass}, mass='{self.mass}')")


def _read(path: Path, units: Units, mass: str | None, rotary_inertia: bool,
          cbar_torsional_inertia: bool) -> BdfDeck:
    """Parse and check the deck, run the card families in registry order, sort out the cards none
    read, then the subcases (they need the whole model)."""
    deck = load_deck(path, units, mass, rotary_inertia, cbar_torsional_inertia, NEEDS_PROPERTY, NEEDS_MATERIAL)
    log = Findings(deck.notes)
    model = Model(path.stem)
    model.add_nodes(deck.positions, ids=list(deck.grid_ids))
    parts = Parts()
    for family in FAMILIES:
        parts = parts.merged(family.read(deck, model, log, parts))
    list_other_cards(deck, log, READ_CARDS)
    cases = read_subcases(deck, model, log, parts)
    return BdfDeck(path, model, cases.configurations, deck.bdf, deck.units, deck.wtmass, deck.mass,
                   beams=parts.beams, element_ids=parts.element_ids, mass_sources=list(parts.mass_sources),
                   spring_sources=list(parts.spring_sources), rigid_sources=list(parts.rigid_sources),
                   end_nodes=parts.end_nodes, interpolation_sources=list(parts.interpolation_sources),
                   constraint_sources=list(cases.constraint_sources), materials=parts.materials,
                   n_modes=cases.n_modes, methods=cases.methods, subcases=cases.subcases,
                   unsupported=log.unsupported, notes=log.notes, shells=parts.shells, options=parts.options)


def read_bdf(path: str | Path, *, units: str | Units = "SI", unsupported: str = "error", mass: str | None = None,
             rotary_inertia: bool = False, cbar_torsional_inertia: bool = False) -> BdfDeck:
    """Read a Nastran bulk data deck into a flexgvt Model and Configurations.

    path: .bdf/.dat/.nas file (INCLUDEs followed; executive and case control optional).
    units: the deck's consistent unit system ('SI', 'mm-N-t-s', 'in-lbf-s' or a Units); everything
    is converted to SI. PARAM,WTMASS scales every mass (density, CONM1/2, NSM).
    unsupported: 'error' raises UnsupportedCardsError listing every card (or card feature) that
    has no flexgvt counterpart, with ids; 'warn' reads the rest and lists them in one warning.
    mass: 'lumped' or 'consistent' beam mass; default from PARAM,COUPMASS (lumped unless > 0).
    'consistent' is Nastran's coupled mass: cubic bending, linear axial for CBAR, lumped axial and
    torsional for CBEAM (group mass 'consistent-bending').
    rotary_inertia: include bending rotary inertia of beams (Nastran's CBAR leaves it out, so the
    default False matches Nastran; torsional inertia: see cbar_torsional_inertia).
    cbar_torsional_inertia: the default False reproduces Nastran's CBAR, whose mass (lumped or
    COUPMASS) has no torsional inertia (measured on the Simcenter beam_modes and MSC pt145 f06);
    True adds the physical rho*Ip to CBARs (torsion modes drop; CBEAM always has it).
    Returns a BdfDeck with .model and .configurations (one per SUBCASE, named 'subcase_<id>', or
    one named after the file when there are no subcases).
    """
    path = Path(path)
    if not path.is_file():
        raise FileFormatError(f"{path}: no such file; give the path of a Nastran bulk data deck")
    if unsupported not in ("error", "warn"):
        raise ModelError(f"read_bdf: unsupported={unsupported!r} must be 'error' or 'warn'")
    if mass not in (None, "lumped", "consistent"):
        raise ModelError(f"read_bdf: mass={mass!r} must be None (from COUPMASS), 'lumped' or 'consistent'")
    deck = _read(path, get_units(units), mass, rotary_inertia, cbar_torsional_inertia)
    if deck.unsupported:
        listing = "; ".join(f"{card}: {', '.join(map(str, ids[:8]))}{', ...' if len(ids) > 8 else ''}"
                            for card, ids in sorted(deck.unsupported.items()))
        message = (f"{path}: {sum(len(v) for v in deck.unsupported.values())} card(s) have no flexgvt counterpart "
                   f"and were not read: {listing}{unsupported_hints(deck.unsupported)}")
        if unsupported == "error":
            raise UnsupportedCardsError(message + ". Remove or replace them, or call read_bdf(..., "
                                        "unsupported='warn') to read the rest", deck.unsupported)
        warnings.warn(message, stacklevel=2)
    if deck.notes:
        warnings.warn(f"{path}: read with these approximations: " + "; ".join(deck.notes), stacklevel=2)
    return deck
