"""What flexgvt's shell kernels give on the real plate decks, before the shell family solves them.

The decks of tests/io/test_nastran_plate_decks.py assembled by hand from the fem kernels
(`shell_matrices`: MITC4 + Allman/Hughes-Brezzi quads) with each deck's constraints, and for HA145E/G
and the crop wing the Guyan reduction to their ASET, as Nastran did. Corner thicknesses are not in
the kernels: each element takes a mean section, either the mean thickness ("mean t") or the
bilinear thickness's mean t and mean t^3 at 2 x 2 Gauss points ("bilinear t"). Prints the
percentages against the cycles Nastran printed (docs/shells.md, "Real Nastran plate decks").

    PYTHONPATH=src python bench/plate_decks_estimate.py
"""

import json
import warnings
from pathlib import Path

import numpy as np
import scipy.linalg as sl
from pyNastran.bdf.bdf import read_bdf

from flexgvt.fem._shell_elements import assemble, shell_matrices
from flexgvt.fem._shell_section import mat1, pshell, section_arrays

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "bdf" / "pynastran"
F06 = json.loads((DATA / "eigenvalues_f06.json").read_text())


def load(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        b = read_bdf(DATA / name, debug=None, xref=True)
    nids = sorted(b.nodes)
    ix = {n: i for i, n in enumerate(nids)}
    return b, nids, ix, np.array([b.nodes[n].get_position() for n in nids])


def hz(K, M, n=None):
    w = sl.eigh(K, M, eigvals_only=True, subset_by_index=None if n is None else [0, n - 1])
    return np.sqrt(np.abs(w)) / (2 * np.pi)


def guyan(K, M, a):
    o = [k for k in range(len(K)) if k not in set(a)]
    T = np.vstack([np.eye(len(a)), -np.linalg.solve(K[np.ix_(o, o)], K[np.ix_(o, a)])])
    P = np.array(list(a) + o)
    return T.T @ K[np.ix_(P, P)] @ T, T.T @ M[np.ix_(P, P)] @ T


def percent(f, ref):
    return " ".join(f"{100 * (x / r - 1):+.2f}" for x, r in zip(f, ref))


def goland():
    b, nids, ix, X = load("goland/goland_final_test.bdf")
    mat = b.materials[1]
    m = mat1(mat.e, mat.g, mat.nu, mat.rho)
    quads = [e for e in b.elements.values() if e.type == "CQUAD4"]
    conn = np.array([[ix[n] for n in e.node_ids] for e in quads])
    C, mass = section_arrays([pshell(b.properties[e.pid].t, m, None) for e in quads], np.arange(len(quads)))
    sm = shell_matrices(X[conn], C, mass, lumped=True)
    K, M = assemble(conn, sm.K, len(nids)).toarray(), assemble(conn, sm.M, len(nids)).toarray()
    for e in (e for e in b.elements.values() if e.type == "CROD"):
        p, (a, c) = b.properties[e.pid], (ix[n] for n in e.node_ids)
        d = X[c] - X[a]
        L = np.linalg.norm(d)
        k = mat.e * p.A / L * np.outer(d, d) / L**2
        for i, j, s in ((a, a, 1), (c, c, 1), (a, c, -1), (c, a, -1)):
            K[6 * i:6 * i + 3, 6 * j:6 * j + 3] += s * k
        for i in (a, c):
            M[6 * i:6 * i + 3, 6 * i:6 * i + 3] += np.eye(3) * mat.rho * p.A * L / 2
    for e in b.masses.values():
        M[6 * ix[e.nid]:6 * ix[e.nid] + 3, 6 * ix[e.nid]:6 * ix[e.nid] + 3] += np.eye(3) * e.mass
    root = set(range(10000, 10006))
    ref = F06["goland/goland_final_test.bdf"]["cycles_hz"]
    held = [6 * ix[n] + d for n in nids if n not in root for d in range(3)]
    f = hz(K[np.ix_(held, held)], M[np.ix_(held, held)], 1)
    print(f"Goland, every rotation held: {f[0]:.4f} Hz ({percent(f, ref)} %)")
    dk = np.diag(K)
    free = [6 * ix[n] + d for n in nids if n not in root for d in range(6)
            if d < 3 or dk[6 * ix[n] + d] > 1e-9 * dk.max()]
    t = [k for k, d in enumerate(free) if d % 6 < 3]
    Kc, Mc = guyan(K[np.ix_(free, free)], M[np.ix_(free, free)], t)  # the massless drilling DOFs condensed
    f = hz(Kc, Mc, 1)
    print(f"Goland, drilling rotations free: {f[0]:.4f} Hz ({percent(f, ref)} %); Nastran {ref[0]} Hz")


def ha145(name):
    b, nids, ix, X = load(name)
    wt, mat = b.params["WTMASS"].values[0], b.materials[1]
    m = mat1(mat.e, mat.g, mat.nu, mat.rho * wt)
    els = [b.elements[e] for e in sorted(b.elements)]
    conn = np.array([[ix[n] for n in e.node_ids] for e in els])
    g = np.array([-1.0, 1.0]) / np.sqrt(3)
    ref = np.array(F06[name]["cycles_hz"][:8])
    for label in ("mean t", "bilinear t"):
        secs = []
        for e in els:
            t = np.array([e.T1, e.T2, e.T3, e.T4], float) if e.T1 is not None else np.full(4, 0.041)
            ts = np.array([np.dot([(1 - a) * (1 - c), (1 + a) * (1 - c), (1 + a) * (1 + c), (1 - a) * (1 + c)], t) / 4
                           for a in g for c in g])
            bmir = 1.0 if label == "mean t" else np.mean(ts**3) / np.mean(ts) ** 3
            secs.append(pshell(np.mean(ts), m, m, bmir=bmir, mid3=m))
        C, mass = section_arrays(secs, np.arange(len(els)))
        sm = shell_matrices(X[conn], C, mass, lumped=False)
        K, M = assemble(conn, sm.K, len(nids)).toarray(), assemble(conn, sm.M, len(nids)).toarray()
        fixed = {6 * ix[n] + 5 for n in nids} | {6 * ix[n] + d for n in (9, 25) for d in range(5)}
        free = [d for d in range(6 * len(nids)) if d not in fixed]
        a = [free.index(6 * ix[n] + 2) for n in nids if n not in (9, 17, 25)]
        f = hz(*guyan(K[np.ix_(free, free)], M[np.ix_(free, free)], a))
        print(f"{name} ({label}, consistent mass, Guyan to ASET), modes 1-8 against Nastran [%]: {percent(f, ref)}")


def crop_bar(E: float, rho: float) -> tuple[np.ndarray, np.ndarray]:
    """The crop wing's CBAR 1010 (grid 10102 to the clamped grid 20000; PBAR A 100, I 1000, J 500,
    L 30, G = E / 2.6, local x = -X basic): the 6 x 6 stiffness and coupled mass blocks of its free
    end in basic axes (the clamped end's do not enter). rho: mass density times WTMASS."""
    G, A, Ib, J, L = E / 2.6, 100.0, 1000.0, 500.0, 30.0
    mu = rho * A
    kl, ml = np.zeros((6, 6)), np.zeros((6, 6))
    kl[0, 0], kl[3, 3], ml[0, 0] = E * A / L, G * J / L, mu * L / 3
    for w, th, s in ((1, 5, 1), (2, 4, -1)):
        kl[w, w], kl[th, th], kl[w, th] = 12 * E * Ib / L**3, 4 * E * Ib / L, s * 6 * E * Ib / L**2
        ml[w, w], ml[th, th], ml[w, th] = 156 * mu * L / 420, 4 * mu * L**3 / 420, s * 22 * mu * L**2 / 420
        kl[th, w], ml[th, w] = kl[w, th], ml[w, th]
    T = np.kron(np.eye(2), np.diag([-1.0, -1.0, 1.0]))
    return T @ kl @ T.T, T @ ml @ T.T


def crop():
    b, nids, ix, X = load("crop/crop.bdf")
    wt, mat = 0.00259, b.materials[1100]
    m = mat1(mat.e, None, mat.nu, mat.rho * wt)
    quads = [e for e in b.elements.values() if e.type == "CQUAD4"]
    conn = np.array([[ix[n] for n in e.node_ids] for e in quads])
    C, mass = section_arrays([pshell(1.5, m, m)], np.zeros(len(quads), int))
    sm = shell_matrices(X[conn], C, mass, lumped=False)
    K, M = assemble(conn, sm.K, len(nids)).toarray(), assemble(conn, sm.M, len(nids)).toarray()
    kb, mb = crop_bar(mat.e, mat.rho * wt)
    i = ix[10102]
    K[6 * i:6 * i + 6, 6 * i:6 * i + 6] += kb
    M[6 * i:6 * i + 6, 6 * i:6 * i + 6] += mb
    fixed = {6 * ix[n] + d for n in nids if n != 20000 for d in (0, 5)} | {6 * ix[20000] + d for d in range(6)}
    free = [d for d in range(6 * len(nids)) if d not in fixed]
    a = [free.index(6 * ix[n] + 2) for n in nids if n != 20000]
    ref = F06["crop/crop.bdf"]["cycles_hz"]
    f = hz(*guyan(K[np.ix_(free, free)], M[np.ix_(free, free)], a))
    print(f"crop (consistent mass, Guyan to ASET), modes 1-5 against Nastran [%]: {percent(f, ref)}")


def flutter_plate():
    """Rigid 1 x 10 m plate (280 kg) on plunge and pitch springs of 1e5 about its leading edge."""
    Mt, S = 280.0, 140.0
    ref = F06["flutter_2mode/0012_flutter.bdf"]["cycles_hz"]
    for label, inertia in (("lumped (Nastran's default)", (1 / 27 + 4 / 27 + 1 / 6) * Mt), ("consistent", Mt / 3)):
        f = hz(np.diag([1e5, 1e5]), np.array([[Mt, -S], [-S, inertia]]))
        print(f"2-mode flutter plate, {label} plate mass: {f.round(5)} Hz ({percent(f, ref)} %)")


if __name__ == "__main__":
    goland()
    for deck in ("ha145/ha145e.bdf", "ha145/ha145g.bdf"):
        ha145(deck)
    crop()
    flutter_plate()
