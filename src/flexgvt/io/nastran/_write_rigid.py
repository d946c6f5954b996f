"""Writing rigid links (RBE2), linear constraints (MPC set 1) and interpolations (RBE3); a template
deck keeps its own."""

from __future__ import annotations

from ...errors import ModelError
from ...model import Model
from ._common import Units
from ._read import BdfDeck
from ._write_common import Numbering


def check_rigid(model: Model, deck: BdfDeck) -> None:
    """A template deck is written with its own rigid elements and MPCs: the model must have the same count."""
    if len(model.rigid_links) != len(deck.rigid_sources) or \
            len(model.interpolations) != len(deck.interpolation_sources) or \
            len(model.constraints) != len(deck.constraint_sources):
        raise ModelError("write_bdf: rigid links or interpolations (RBE3) differ from the template; write without "
                         "template=")


def write_rigid(bdf, model: Model, u: Units, ids: Numbering) -> None:
    """RBE2 per rigid link, MPC set 1 per constraint, RBE3 per interpolation (one weight group per weight)."""
    for link in model.rigid_links:
        bdf.add_rbe2(ids.eid, link.independent, link.components, list(link.dependents))
        ids.eid += 1
    for con in model.constraints:  # MPC set 1, selected by every subcase
        nodes, comps, coefs = zip(*con.terms)  # rotation terms scale with the length unit (see the reader)
        bdf.add_mpc(1, list(nodes), [str(c) for c in comps],
                    [a / (u.length if c > 3 else 1.0) for c, a in zip(comps, coefs)])
    for ip in model.interpolations:  # one weight group per distinct weight
        groups: dict[float, list[int]] = {}
        for node, w in zip(ip.nodes, ip.weights):
            groups.setdefault(float(w), []).append(int(node))
        bdf.add_rbe3(ids.eid, ip.reference, ip.components, list(groups), ["123"] * len(groups), list(groups.values()))
        ids.eid += 1
