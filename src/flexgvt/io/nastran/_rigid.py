"""Rigid elements: RBE2 and RBAR (rigid links, chains hung on their root), the rigid links of the
nodes other families added at beam offsets, pins and bush locations, and RBE3 (interpolation)."""

from __future__ import annotations

import math

from ...errors import ModelError
from ...model import Model
from ._deck import Deck, Family, Findings, Parts


def read_rigid(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """RBE2/RBAR links, then the end links of the families read before (in their order), then RBE3s."""
    reader = _Rigid(deck, model, log)
    reader.read_links()
    reader.attach_end_nodes(parts.end_links)
    reader.read_interpolations()
    return Parts(rigid_sources=tuple(reader.sources), interpolation_sources=tuple(reader.interpolation_sources))


class _Rigid:
    """The rigid family's reading of one deck."""

    def __init__(self, deck: Deck, model: Model, log: Findings) -> None:
        self.deck, self.model, self.log = deck, model, log
        self.sources: list[tuple] = []
        self.interpolation_sources: list[int] = []
        self.rbe3: list[tuple] = []  # (eid, reference, REFC, {node: weight}) for read_interpolations

    def at(self, name: str, ident) -> str:
        return self.deck.at(name, ident)

    def read_links(self) -> None:
        """RBE2 -> rigid links (components 123456, or translations with all or none of 456)."""
        links: dict[tuple[int, str], list[int]] = {}
        sources: dict[tuple[int, str], list[int]] = {}
        owner: dict[int, int] = {}
        for eid, elem in sorted(self.deck.bdf.rigid_elements.items()):
            if elem.type == "RBE3":
                self._pending_rbe3(elem)
                continue
            if elem.type == "RBAR":  # all six DOFs of one end independent: an RBE2 with one dependent
                norm = {k: "".join(sorted(set(str(getattr(elem, k) or "").strip())))
                        for k in ("cna", "cnb", "cma", "cmb")}
                if norm["cna"] == "123456" and not norm["cnb"] and not norm["cma"] and norm["cmb"]:
                    gn, cm, gmi = elem.ga, norm["cmb"], [elem.gb]
                elif norm["cnb"] == "123456" and not norm["cna"] and not norm["cmb"] and norm["cma"]:
                    gn, cm, gmi = elem.gb, norm["cma"], [elem.ga]
                else:
                    self.log.skip("RBAR (independent DOFs at both ends)", eid)
                    continue
            elif elem.type == "RBE2":
                gn, cm, gmi = elem.gn, "".join(sorted(set(str(elem.cm)))), elem.Gmi
            else:
                self.log.skip(elem.type, eid)
                continue
            if set(cm) & set("456") not in (set(), set("456")):
                self.log.skip(f"{elem.type} (some of the rotations 456 only)", eid)
                continue
            deps = [int(n) for n in gmi]
            for d in deps:
                if d in owner:
                    raise ModelError(f"{self.at(elem.type, eid)}: node {d} is already a dependent of rigid element "
                                     f"{owner[d]}; a node can depend on one rigid element only "
                                     "(Nastran rejects this too)")
                owner[d] = eid
            key = (int(gn), cm)
            links[key] = links.get(key, []) + deps
            sources.setdefault(key, []).append(int(eid))
        # Chains (an independent node that is a dependent of a full RBE2) hang on the chain's root:
        # a node that moves rigidly with the root carries its dependents' offsets along.
        changed = True
        while changed:
            changed = False
            for key in list(links):
                parent = next((p for p, deps in links.items() if key[0] in deps and p[0] != key[0]), None)
                if parent is None:
                    continue
                if parent[1] != "123456":
                    raise ModelError(f"RBE2 {sources[key]}: its independent node {key[0]} is a dependent of RBE2 "
                                     f"{sources[parent]} with components {parent[1]}; chains through partial RBE2s "
                                     "are not supported. Make the first RBE2 depend on the chain's root directly")
                new = (parent[0], key[1])
                links[new] = links.get(new, []) + links.pop(key)
                sources[new] = sources.get(new, []) + sources.pop(key)
                changed = True
                break
        for (ind, cm), deps in links.items():
            if ind in deps:
                raise ModelError(f"RBE2 {sources[(ind, cm)]}: the rigid elements form a loop through node {ind}")
            self.model.add_rigid_link(ind, deps, components=cm)
            self.sources.append(tuple(sources[(ind, cm)]))

    def _pending_rbe3(self, elem) -> None:
        """Check an RBE3 and keep it for read_interpolations (after the rigid links exist)."""
        eid = int(elem.eid)
        if elem.Gmi:
            self.log.skip("RBE3 (UM dependent DOFs)", eid)
            return
        refc = "".join(sorted(set(str(elem.refc))))
        if refc not in ("123", "123456"):
            self.log.skip("RBE3 (REFC other than 123456 or 123)", eid)
            return
        if any("".join(sorted(set(str(c)))) != "123" for c in elem.comps):
            self.log.skip("RBE3 (independent components other than 123)", eid)
            return
        weights: dict[int, float] = {}
        for wt, nodes in zip(elem.weights, elem.Gijs):
            if wt is None or not math.isfinite(float(wt)) or float(wt) <= 0:
                raise ModelError(f"{self.at('RBE3', eid)}: weight {wt!r} must be a positive number")
            for n in nodes:
                weights[int(n)] = weights.get(int(n), 0.0) + float(wt)
        self.rbe3.append((eid, int(elem.refgrid), refc, weights))

    def read_interpolations(self) -> None:
        """RBE3 (C = 123 at the nodes) -> interpolation links."""
        for eid, ref, refc, weights in self.rbe3:
            try:
                self.model.add_interpolation(ref, list(weights), list(weights.values()), components=refc)
            except ModelError as exc:
                raise ModelError(f"{self.at('RBE3', eid)}: {exc}") from None
            self.interpolation_sources.append(eid)

    def attach_end_nodes(self, end_links) -> None:
        """Rigid links of the beam-end and bush-location nodes, on the root of any RBE2 chain."""
        owner = {d: link for link in self.model.rigid_links for d in link.dependents}
        for grid, nid, components, source in end_links:
            root = grid
            if grid in owner:
                link = owner[grid]
                if link.components != "123456":
                    raise ModelError(f"{source[0]} {source[1]}: end {source[2]} sits on node {grid}, a dependent of an "
                                     f"RBE2 with components {link.components}; an offset, pin or bush location cannot "
                                     "hang on a partial RBE2. Use a full RBE2 or attach the element to its independent")
                root = link.independent
            self.model.add_rigid_link(root, [nid], components=components)
            self.sources.append(source)


FAMILY = Family("rigid", ("RBE2", "RBE3", "RBAR"), read_rigid)
