"""What the line-element families share: BeamSource, the SI scaling of sections, the nodes added
at beam offsets, pins and bush locations, and non-structural mass lumped at element ends."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...model import CircularTubeSection, GeneralSection, Model, RectangularSection, RodSection, TaperedSection
from ._deck import Deck, EndLink, Findings


@dataclass(frozen=True)
class BeamSource:
    """Where a flexgvt beam group came from: one Nastran beam property."""

    name: str
    card: str  # CBAR or CBEAM
    ptype: str  # PBAR, PBARL, PBEAM, PBEAML
    pid: int
    mid: int
    eids: tuple[int, ...]
    principal: tuple[float, float]


def scale_section(section, L: float):
    """Section in SI from deck length units L [m per unit]."""
    if L == 1.0:
        return section
    if isinstance(section, RodSection):
        return RodSection(A=section.A * L**2, J=section.J * L**4)
    if isinstance(section, RectangularSection):
        return replace(section, width=section.width * L, height=section.height * L)
    if isinstance(section, CircularTubeSection):
        return replace(section, outer_radius=section.outer_radius * L, inner_radius=section.inner_radius * L)
    if isinstance(section, TaperedSection):
        return TaperedSection(scale_section(section.end_a, L), scale_section(section.end_b, L))
    assert isinstance(section, GeneralSection)
    s2, s4 = L**2, L**4
    return GeneralSection(A=section.A * s2, Iy=section.Iy * s4, Iz=section.Iz * s4, J=section.J * s4,
                          Ay=None if section.Ay is None else section.Ay * s2,
                          Az=None if section.Az is None else section.Az * s2,
                          Ip=None if section.Ip is None else section.Ip * s4)


class EndNodes:
    """Nodes one family adds to ``model`` (ids after every node already there), each tied to its grid
    by a rigid link that the rigid family adds after the deck's RBE2s (``links``)."""

    def __init__(self, deck: Deck, model: Model) -> None:
        self.deck, self.model = deck, model
        self.next_id = int(model.node_ids.max()) + 1
        self.nodes: dict[tuple[str, int, str], int] = {}
        self.links: list[EndLink] = []
        self.xyz: dict[int, np.ndarray] = {}  # added node -> position [m]

    def add(self, grid: int, position_deck: np.ndarray, components: str, source: tuple) -> int:
        """A new node at position_deck [deck length] tied to ``grid`` with ``components``; source is
        (card, element id, end)."""
        nid, self.next_id = self.next_id, self.next_id + 1
        self.xyz[nid] = np.asarray(position_deck, float) * self.deck.units.length
        self.model.add_nodes([self.xyz[nid]], ids=[nid])
        self.nodes[source] = nid
        self.links.append((grid, nid, components, source))
        return nid

    def position(self, nid: int) -> np.ndarray:
        """Basic position [m] of a grid or of a node added here."""
        return self.xyz[nid] if nid in self.xyz else self.deck.xyz[nid]


def lumped_nsm(deck: Deck, model: Model, log: Findings, xyz, pairs: np.ndarray, nsm: tuple[float, float], card: str,
               ident) -> list[tuple[str, int]]:
    """Non-structural mass per length NSM (deck units) at end A and end B, linear between them, added
    to ``model`` as point masses int NSM N_i dx at the element ends (NSM L / 2 each when uniform).
    xyz(node) -> position [m]. Returns the mass sources."""
    u = deck.units
    na, nb = (v * u.mass / u.length * deck.wtmass for v in nsm)
    ends: dict[int, float] = {}
    for p in pairs:
        L = float(np.linalg.norm(xyz(p[1]) - xyz(p[0])))
        for n, m in zip(p, (L * (na / 3 + nb / 6), L * (na / 6 + nb / 3)) if na != nb else (0.5 * na * L,) * 2):
            ends[int(n)] = ends.get(int(n), 0.0) + m
    sources = []
    for n, m in ends.items():
        model.add_mass(n, m)
        sources.append((f"NSM:{card}", int(ident)))
    if deck.mass == "consistent":
        log.note(f"{deck.at(card, ident)}: NSM={nsm[0] if nsm[0] == nsm[1] else list(nsm)} lumped at the "
                 "element ends (Nastran distributes it consistently under COUPMASS)")
    return sources
