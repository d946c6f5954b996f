"""Concentrated masses: CONM2, CONM1 (a rigid-body mass matrix), CMASS1/CMASS2 on a rotation."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ...model import Model
from ._deck import Deck, Family, Findings, Parts
from ._grids import coord_axes


def read_masses(deck: Deck, model: Model, log: Findings, parts: Parts) -> Parts:
    """Every mass element as a model mass (offset and inertia in basic axes, SI, PARAM,WTMASS applied)."""
    reader = _Masses(deck, model, log)
    reader.read()
    return Parts(mass_sources=tuple(reader.sources))


def _rigid_mass(M: np.ndarray, rtol: float = 1e-6):
    """(m, offset, inertia about the centre) if M (6x6, basic axes) is a rigid-body mass matrix, else None."""
    m = M[0, 0]
    scale = max(np.abs(M).max(), 1e-300)
    if m <= 0 or not np.allclose(M[:3, :3], m * np.eye(3), atol=rtol * scale):
        return None
    S = -M[:3, 3:] / m  # M_tr = -m skew(r)
    if not np.allclose(S, -S.T, atol=rtol * scale / m):
        return None
    r = np.array([S[2, 1], S[0, 2], S[1, 0]])
    Sr = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    if not np.allclose(M[3:, :3], m * Sr, atol=rtol * scale):
        return None
    J = M[3:, 3:] + m * Sr @ Sr
    return m, r, 0.5 * (J + J.T)


class _Masses:
    """The mass family's reading of one deck."""

    def __init__(self, deck: Deck, model: Model, log: Findings) -> None:
        self.deck, self.model, self.log = deck, model, log
        self.sources: list[tuple[str, int]] = []

    def at(self, name: str, ident) -> str:
        return self.deck.at(name, ident)

    def read(self) -> None:
        deck, model = self.deck, self.model
        bdf, u, w = deck.bdf, deck.units, deck.wtmass
        for eid, elem in sorted(bdf.masses.items()):
            where = self.at(elem.type, eid)
            if elem.type == "CONM2":
                cid = elem.cid
                x = np.asarray(elem.X, float)
                node_xyz = self.deck.xyz_deck[elem.nid]
                if cid == -1:
                    offset, T = x - node_xyz, np.eye(3)
                else:
                    if cid not in (None, 0) and bdf.coords[cid].Type != "R":
                        self.log.skip("CONM2 (curvilinear CID)", eid)
                        continue
                    T = coord_axes(bdf, cid, node_xyz, where)
                    offset = T @ x
                I11, I21, I22, I31, I32, I33 = np.asarray(elem.I, float)
                J = np.array([[I11, -I21, -I31], [-I21, I22, -I32], [-I31, -I32, I33]])
                J = T @ J @ T.T
                try:
                    model.add_mass(elem.nid, float(elem.mass) * u.mass * w, offset=offset * u.length,
                                   inertia=J * u.inertia * w, id=int(eid))
                except ModelError as exc:
                    raise ModelError(f"{where}: {exc}") from None
                self.sources.append(("CONM2", int(eid)))
            elif elem.type == "CONM1":
                M = np.asarray(elem.mass_matrix, float)
                M = np.tril(M) + np.tril(M, -1).T
                T = coord_axes(bdf, elem.cid, self.deck.xyz_deck[elem.nid], where)
                T6 = np.zeros((6, 6))
                T6[:3, :3] = T6[3:, 3:] = T
                M = T6 @ M @ T6.T
                got = _rigid_mass(M)
                if got is None:
                    self.log.skip("CONM1 (not a rigid-body mass matrix)", eid)
                    continue
                m, r, J = got
                model.add_mass(elem.nid, m * u.mass * w, offset=r * u.length, inertia=J * u.inertia * w, id=int(eid))
                self.sources.append(("CONM1", int(eid)))
            elif elem.type in ("CMASS1", "CMASS2"):
                self._scalar_mass(elem, where)
            else:
                self.log.skip(elem.type, eid)

    def _scalar_mass(self, elem, where: str) -> None:
        """CMASS1/CMASS2 on one grid's rotational component: an inertia m e e^T about that axis of the
        grid's displacement system (CD). A scalar mass on a translational component (mass in one
        direction only) or between two grids has no flexgvt counterpart and is named unsupported."""
        bdf, u, w = self.deck.bdf, self.deck.units, self.deck.wtmass
        n1, n2 = (list(elem.nodes) + [None, None])[:2]
        c1 = int(getattr(elem, "c1", 0) or 0)
        if n2 not in (None, 0) or n1 in (None, 0):
            self.log.skip(f"{elem.type} (between two grids or on a scalar point)", elem.eid)
            return
        if not 4 <= c1 <= 6:
            self.log.skip(f"{elem.type} (translational component: a mass in one direction only)", elem.eid)
            return
        m = float(bdf.properties_mass[elem.pid].mass) if elem.type == "CMASS1" else float(elem.mass)
        axis = coord_axes(bdf, bdf.nodes[n1].cd, self.deck.xyz_deck[n1], where)[:, c1 - 4]
        J = m * np.outer(axis, axis) * u.inertia * w
        try:
            self.model.add_mass(n1, 0.0, inertia=J)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.sources.append((elem.type, int(elem.eid)))


FAMILY = Family("masses", ("CONM2", "CONM1", "CMASS1", "CMASS2", "PMASS"), read_masses)
