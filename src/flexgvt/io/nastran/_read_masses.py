"""Masses (CONM1/2, CMASS1/2), springs and dampers (CELAS, CDAMP, CVISC, CBUSH) and rigid links (RBE2, RBAR)."""

from __future__ import annotations

import numpy as np

from ...errors import ModelError
from ._common import coord_axes
from ._read_beams import _frame_from_x


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




class MassesMixin:
    """Part of the bulk data reader (see _read._Reader)."""

    # ----------------------------------------------------------------- masses
    def read_masses(self) -> None:
        bdf, model, u, w = self.bdf, self.model, self.units, self.wtmass
        for eid, elem in sorted(bdf.masses.items()):
            where = self.at(elem.type, eid)
            if elem.type == "CONM2":
                cid = elem.cid
                x = np.asarray(elem.X, float)
                node_xyz = self.xyz_deck[elem.nid]
                if cid == -1:
                    offset, T = x - node_xyz, np.eye(3)
                else:
                    if cid not in (None, 0) and bdf.coords[cid].Type != "R":
                        self.skip("CONM2 (curvilinear CID)", eid)
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
                self.deck.mass_sources.append(("CONM2", int(eid)))
            elif elem.type == "CONM1":
                M = np.asarray(elem.mass_matrix, float)
                M = np.tril(M) + np.tril(M, -1).T
                T = coord_axes(bdf, elem.cid, self.xyz_deck[elem.nid], where)
                T6 = np.zeros((6, 6))
                T6[:3, :3] = T6[3:, 3:] = T
                M = T6 @ M @ T6.T
                got = _rigid_mass(M)
                if got is None:
                    self.skip("CONM1 (not a rigid-body mass matrix)", eid)
                    continue
                m, r, J = got
                model.add_mass(elem.nid, m * u.mass * w, offset=r * u.length, inertia=J * u.inertia * w, id=int(eid))
                self.deck.mass_sources.append(("CONM1", int(eid)))
            elif elem.type in ("CMASS1", "CMASS2"):
                self._scalar_mass(elem, where)
            else:
                self.skip(elem.type, eid)

    def _scalar_mass(self, elem, where: str) -> None:
        """CMASS1/CMASS2 on one grid's rotational component: an inertia m e e^T about that axis of the
        grid's displacement system (CD). A scalar mass on a translational component (mass in one
        direction only) or between two grids has no flexgvt counterpart and is named unsupported."""
        bdf, u, w = self.bdf, self.units, self.wtmass
        n1, n2 = (list(elem.nodes) + [None, None])[:2]
        c1 = int(getattr(elem, "c1", 0) or 0)
        if n2 not in (None, 0) or n1 in (None, 0):
            self.skip(f"{elem.type} (between two grids or on a scalar point)", elem.eid)
            return
        if not 4 <= c1 <= 6:
            self.skip(f"{elem.type} (translational component: a mass in one direction only)", elem.eid)
            return
        m = float(bdf.properties_mass[elem.pid].mass) if elem.type == "CMASS1" else float(elem.mass)
        axis = coord_axes(bdf, bdf.nodes[n1].cd, self.xyz_deck[n1], where)[:, c1 - 4]
        J = m * np.outer(axis, axis) * u.inertia * w
        try:
            self.model.add_mass(n1, 0.0, inertia=J)
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.deck.mass_sources.append((elem.type, int(elem.eid)))

    # ----------------------------------------------------------------- springs and dampers
    def _scalar(self, elem, value_stiff: float, value_damp: float) -> None:
        """CELAS/CDAMP: a scalar spring between (G1, C1) and (G2, C2) in the nodes' displacement axes."""
        bdf, u = self.bdf, self.units
        where = self.at(elem.type, elem.eid)
        n1, n2 = (list(elem.nodes) + [None, None])[:2]
        c1, c2 = int(elem.c1 or 0), int(elem.c2 or 0)
        ends = [(n, c) for n, c in ((n1, c1), (n2, c2)) if n not in (None, 0)]
        if not ends or any(not 1 <= c <= 6 for _, c in ends):
            self.skip(f"{elem.type} (scalar points or component 0)", elem.eid)
            return
        comps = {c for _, c in ends}
        axes = [coord_axes(bdf, bdf.nodes[n].cd, self.xyz_deck[n], where) for n, _ in ends]
        c = ends[0][1]
        if len(comps) > 1 or (len(ends) == 2 and not np.allclose(axes[0][:, (c - 1) % 3], axes[1][:, (c - 1) % 3],
                                                                 atol=1e-9)):
            self.skip(f"{elem.type} (components along different directions)", elem.eid)
            return
        rot = c > 3
        k = np.zeros(6)
        d = np.zeros(6)
        k[c - 1] = value_stiff * (u.moment if rot else u.force / u.length)
        d[c - 1] = value_damp * (u.moment if rot else u.force / u.length)
        a, b = (ends[0][0], ends[1][0]) if len(ends) == 2 else (ends[0][0], None)
        self._add_spring(where, a, b, k, d, axes[0], (elem.type, int(elem.eid)))

    def _add_spring(self, where, a, b, k, d, frame, source) -> None:
        try:
            self.model.add_spring(a, b, stiffness=k, damping=d, frame=frame, id=source[1])
        except ModelError as exc:
            raise ModelError(f"{where}: {exc}") from None
        self.deck.spring_sources.append(source)

    def read_springs(self) -> None:
        bdf, u = self.bdf, self.units
        for eid, elem in sorted(bdf.elements.items()):
            t = elem.type
            where = self.at(t, eid)
            if t in ("CELAS1", "CELAS2"):
                prop = bdf.properties[elem.pid] if t == "CELAS1" else None
                k = prop.k if prop is not None else elem.k
                ge = prop.ge if prop is not None else elem.ge
                if ge:
                    self.notes.append(f"{where}: structural damping GE={ge} is not modelled")
                self._scalar(elem, float(k), 0.0)
            elif t in ("CDAMP1", "CDAMP2"):
                b = bdf.properties[elem.pid].b if t == "CDAMP1" else elem.b
                self._scalar(elem, 0.0, float(b))
            elif t == "CVISC":
                prop = bdf.properties[elem.pid]
                n1, n2 = elem.nodes
                ex = self.xyz[n2] - self.xyz[n1]
                if np.linalg.norm(ex) == 0:
                    raise ModelError(f"{where}: the two nodes of a CVISC coincide; its line of action is undefined")
                frame = _frame_from_x(ex)
                d = np.array([prop.ce * u.force / u.length, 0, 0, (prop.cr or 0.0) * u.moment, 0, 0])
                self._add_spring(where, n1, n2, np.zeros(6), d, frame, ("CVISC", int(eid)))
            elif t == "CBUSH":
                self.read_cbush(elem, where)

    def read_cbush(self, elem, where) -> None:
        bdf, u = self.bdf, self.units
        prop = bdf.properties[elem.pid]
        ga, gb = (list(elem.nodes) + [None])[:2]
        gb = None if gb in (None, 0) else gb
        coincident = gb is None or np.linalg.norm(self.xyz_deck[gb] - self.xyz_deck[ga]) <= 1e-4
        if not coincident and getattr(elem, "ocid", -1) not in (None, -1):
            self.skip("CBUSH (spring location given in OCID)", elem.eid)
            return
        if elem.cid not in (None, -1):
            frame = coord_axes(bdf, elem.cid, self.xyz_deck[ga], where)
        elif coincident:
            raise ModelError(f"{where}: a CBUSH on coincident nodes (or grounded) needs CID; Nastran rejects it too. "
                             "Give CID = 0 for basic axes")
        else:  # element axes: x from GA to GB, y from the orientation vector
            v = None if elem.g0 in (None, 0) and (elem.x is None or any(c is None for c in elem.x)) \
                else self.orientation_vector(elem)
            ex = self.xyz_deck[gb] - self.xyz_deck[ga]
            ex = ex / np.linalg.norm(ex)
            ez = None if v is None else np.cross(ex, v)
            if ez is None or np.linalg.norm(ez) <= 1e-8 * np.linalg.norm(v):
                raise ModelError(f"{where}: a CBUSH between distinct points without CID needs an orientation vector "
                                 "(X1-X3 or G0) off the line GA-GB")
            ez = ez / np.linalg.norm(ez)
            frame = np.column_stack([ex, np.cross(ez, ex), ez])
        if not coincident:  # rigid arms from GA and GB to the spring location, S along GA-GB
            s_loc = 0.5 if getattr(elem, "s", None) is None else float(elem.s)
            at = self.xyz_deck[ga] + s_loc * (self.xyz_deck[gb] - self.xyz_deck[ga])
            ga = self._end_node(int(ga), at, "123456", ("CBUSH", int(elem.eid), "A"))
            gb = self._end_node(int(gb), at, "123456", ("CBUSH", int(elem.eid), "B"))
        def six(values):
            vals = list(values or [])
            return np.array([float(v) if v is not None else 0.0 for v in (vals + [0.0] * 6)[:6]])
        k = six(getattr(prop, "Ki", None))
        b = six(getattr(prop, "Bi", None))
        if any(getattr(prop, "GEi", None) or []):
            if any(v for v in prop.GEi if v):
                self.notes.append(f"{where}: structural damping GE of PBUSH {prop.pid} is not modelled")
        scale = np.r_[[u.force / u.length] * 3, [u.moment] * 3]
        self._add_spring(where, ga, gb, k * scale, b * scale, frame, ("CBUSH", int(elem.eid)))

    # ----------------------------------------------------------------- rigid elements
    def read_rigid(self) -> None:
        """RBE2 -> rigid links (components 123456, or translations with all or none of 456)."""
        links: dict[tuple[int, str], list[int]] = {}
        sources: dict[tuple[int, str], list[int]] = {}
        owner: dict[int, int] = {}
        for eid, elem in sorted(self.bdf.rigid_elements.items()):
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
                    self.skip("RBAR (independent DOFs at both ends)", eid)
                    continue
            elif elem.type == "RBE2":
                gn, cm, gmi = elem.gn, "".join(sorted(set(str(elem.cm)))), elem.Gmi
            else:
                self.skip(elem.type, eid)
                continue
            if set(cm) & set("456") not in (set(), set("456")):
                self.skip(f"{elem.type} (some of the rotations 456 only)", eid)
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
            self.deck.rigid_sources.append(tuple(sources[(ind, cm)]))
