"""Mesh refinement of the real Nastran plate decks, flexgvt against an independent solver.

HA145E, HA145G (15-deg swept plates, corner thicknesses 0 on the tapered edges, COUPMASS, ASET1) and
the crop delta wing (3 x 3 CQUAD4 on one CBAR) of tests/io/test_nastran_plate_decks.py, every CQUAD4
split into n x n (corners and corner thicknesses interpolated bilinearly in the parent), the deck's
constraints carried to the new grids (HA145: R3 everywhere; crop: T1, R3 on every plate grid), the
supports on the same grids (HA145: 12345 at grids 9 and 25 only; crop: the CBAR at grid 10102 only)
and the a-set on the same grids (T3 of the deck's grids: Guyan reduction as Nastran did), at
n = 1, 2, 4, 8. Percentages against the cycles Nastran printed for the deck's own (n = 1) mesh.

flexgvt: the shell family's kernels (MITC4 bending/shear, `shell_matrices`) with the deck's
consistent mass (COUPMASS), each element at a constant section: "mean t" (the mean corner
thickness, as the family reads a deck) or "bilinear t" (mean t, and bending from the mean of t^3
at the 2 x 2 Gauss points of the bilinear thickness). The n = 1 "mean t" rows are what
`solve_deck` gives (docs/shells.md).

Peer (--peer-python, a venv with openseespy): OpenSees' ShellMITC4 (Dvorkin-Bathe), ASDShellQ4
(MITC-type shear, enhanced membrane) and ShellDKGQ (Kirchhoff DKQ bending) on the same meshes and
sections; their stiffness matrices (OpenSees' GimmeMCK + printA) are reduced and solved here with
flexgvt's consistent mass (OpenSees' shell mass is lumped), so only the stiffness formulation
differs. CalculiX (--ccx, HA145 with the deck's supports): S4 and S8R, full model, out-of-plane
modes. Measured output in bench/plate_decks_refine_peers.json (rewritten with --json).

    PYTHONPATH=src python bench/plate_decks_refine.py [--levels 1 2 4 8]
        [--peer-python /work/venv-peer/bin/python --peer-levels 1 2 4 --ccx --json bench/plate_decks_refine_peers.json]
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "bdf" / "pynastran"
PEER_ELEMENTS = ("ShellMITC4", "ASDShellQ4", "ShellDKGQ")
VARIANTS = {"ha145": "variant: root clamped from grid 9 to 25", "crop/": "variant: root edge clamped, no CBAR"}
GAUSS = np.array([-1.0, 1.0]) / np.sqrt(3)


@dataclass
class Plate:
    """A deck's plate: grids (ids, X), quads (node ids, corner thicknesses), material, constraints."""

    name: str
    ids: list[int]
    X: np.ndarray
    quads: np.ndarray          # (n, 4) node ids
    corners: np.ndarray        # (n, 4) corner thicknesses
    E: float
    G: float
    nu: float
    rho: float                 # mass density (rho * WTMASS)
    tst: float
    held: dict[int, tuple[int, ...]]   # grid -> DOFs held (0-5), the deck's supports
    held_everywhere: tuple[int, ...]   # DOFs held on every plate grid (new ones too)
    aset: list[int]            # grids whose T3 is the a-set
    nastran: list[float]
    bar: dict | None = None    # crop: the CBAR's 6 x 6 blocks at its free end
    line: tuple | None = None  # variant: (axis, value, lo, hi, DOFs) every grid on this root segment held


def load(name: str, variant: str = "deck") -> Plate:
    """The deck's plate; variant "line": the root held along a segment instead of at points (a
    support that converges under refinement; not Nastran's model)."""
    from pyNastran.bdf.bdf import read_bdf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        b = read_bdf(DATA / name, debug=None, xref=True)
    f06 = json.loads((DATA / "eigenvalues_f06.json").read_text())[name]["cycles_hz"]
    ids = sorted(b.nodes)
    X = np.array([b.nodes[n].get_position() for n in ids])
    quads = [b.elements[e] for e in sorted(b.elements) if b.elements[e].type == "CQUAD4"]
    prop = b.properties[quads[0].pid]
    mat = prop.mid1_ref
    t0 = prop.t
    corners = np.array([[t0 if t is None else t for t in (q.T1, q.T2, q.T3, q.T4)] for q in quads], float)
    wt = b.params["WTMASS"].values[0]
    common = dict(name=name, ids=ids, X=X, quads=np.array([q.node_ids for q in quads]), corners=corners,
                  E=mat.e, G=mat.g, nu=mat.nu, rho=mat.rho * wt, tst=prop.tst, nastran=f06)
    if name.startswith("ha145"):
        # variant: the root (y = 0) clamped from grid 9 to grid 25 (grid 17 too)
        line = (1, 0.0, X[ids.index(9), 0], X[ids.index(25), 0], (0, 1, 2, 3, 4)) if variant == "line" else None
        return Plate(**common, held={9: (0, 1, 2, 3, 4), 25: (0, 1, 2, 3, 4)}, held_everywhere=(5,),
                     aset=[n for n in ids if n not in (9, 17, 25)], line=line)
    if variant == "line":  # crop variant: the root edge x = 30 clamped, no CBAR
        return Plate(**common, held={20000: tuple(range(6))}, held_everywhere=(0, 5),
                     aset=[n for n in ids if n != 20000 and X[ids.index(n), 0] > 30.0 + 1e-6],
                     line=(0, 30.0, 0.0, 100.0, (1, 2, 3, 4)))
    # crop: CBAR 1010 from 10102 to 20000 (clamped): its free end's blocks, as plate_decks_estimate
    from plate_decks_estimate import crop_bar
    kb, mb = crop_bar(mat.e, mat.rho * wt)
    bar = {"grid": 10102, "K": kb, "M": mb}
    return Plate(**common, held={20000: tuple(range(6))}, held_everywhere=(0, 5),
                 aset=[n for n in ids if n != 20000], bar=bar)


@dataclass
class Mesh:
    ids: list[int]             # grid ids (the deck's first, new ones after)
    X: np.ndarray
    conn: np.ndarray           # (m, 4) rows of X
    corners: np.ndarray        # (m, 4) corner thicknesses


def refine(p: Plate, n: int) -> Mesh:
    """Every quad split into n x n, corners and thicknesses bilinear in the parent; shared grids merged."""
    scale = np.ptp(p.X, axis=0).max()
    key = {tuple(np.round(x / scale * 1e7).astype(int)): k for k, x in enumerate(p.X)}
    ids, X = list(p.ids), list(p.X)
    index = {g: k for k, g in enumerate(p.ids)}
    s = np.linspace(0.0, 1.0, n + 1)
    conn, corners = [], []
    for q, tq in zip(p.quads, p.corners):
        P = p.X[[index[g] for g in q]]
        grid = np.empty((n + 1, n + 1), int)
        tg = np.empty((n + 1, n + 1))
        for i, a in enumerate(s):
            for j, c in enumerate(s):
                w = np.array([(1 - a) * (1 - c), a * (1 - c), a * c, (1 - a) * c])
                x = w @ P
                k = key.setdefault(tuple(np.round(x / scale * 1e7).astype(int)), len(X))
                if k == len(X):
                    X.append(x)
                    ids.append(max(ids) + 1)
                grid[i, j], tg[i, j] = k, w @ tq
        for i in range(n):
            for j in range(n):
                c4 = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
                conn.append([grid[c] for c in c4])
                corners.append([tg[c] for c in c4])
    return Mesh(ids, np.array(X), np.array(conn), np.array(corners))


def thickness(corners: np.ndarray, treatment: str) -> tuple[np.ndarray, np.ndarray]:
    """Per element: the thickness of the section and 12I/T^3 (bending from mean t^3 at the Gauss points)."""
    w = np.array([[(1 - a) * (1 - c), (1 + a) * (1 - c), (1 + a) * (1 + c), (1 - a) * (1 + c)]
                  for a in GAUSS for c in GAUSS]) / 4
    tg = corners @ w.T                                  # (m, 4) thickness at the Gauss points
    t = tg.mean(axis=1)
    bmir = np.ones_like(t) if treatment == "mean t" else (tg**3).mean(axis=1) / t**3
    return t, bmir


def flexgvt_matrices(p: Plate, mesh: Mesh, treatment: str):
    import scipy.sparse as sp

    from flexgvt.fem._shell_elements import assemble, shell_matrices
    from flexgvt.fem._shell_section import mat1, pshell, section_arrays

    m = mat1(p.E, p.G, p.nu, p.rho)
    t, bmir = thickness(mesh.corners, treatment)
    secs = [pshell(tk, m, m, bmir=bk, mid3=m if p.name.startswith("ha145") else None, tst=p.tst)
            for tk, bk in zip(t, bmir)]
    C, mass = section_arrays(secs, np.arange(len(secs)))
    sm = shell_matrices(mesh.X[mesh.conn], C, mass, lumped=False)
    nn = len(mesh.ids)
    return assemble(mesh.conn, sm.K, nn).tocsr(), assemble(mesh.conn, sm.M, nn).tocsr(), sp


def with_bar(p: Plate, mesh: Mesh, K, M):
    import scipy.sparse as sp

    if p.bar is None:
        return K, M
    i = mesh.ids.index(p.bar["grid"])
    rows = np.repeat(np.arange(6 * i, 6 * i + 6), 6)
    cols = np.tile(np.arange(6 * i, 6 * i + 6), 6)
    add = lambda A, B: A + sp.csr_matrix((B.ravel(), (rows, cols)), shape=A.shape)  # noqa: E731
    return add(K, p.bar["K"]), add(M, p.bar["M"])


def frequencies(p: Plate, mesh: Mesh, K, M, reduced: bool, n_modes: int) -> np.ndarray:
    """Cycles [Hz] of the plate with its constraints, Guyan-reduced to the a-set's T3 (reduced) or full."""
    import scipy.linalg as sl
    import scipy.sparse.linalg as sla

    K, M = with_bar(p, mesh, K, M)
    held = np.zeros((len(mesh.ids), 6), bool)
    plate_grids = np.unique(mesh.conn)
    held[np.ix_(plate_grids, p.held_everywhere)] = True
    for g, dofs in p.held.items():
        held[mesh.ids.index(g), list(dofs)] = True
    if p.line is not None:
        axis, value, lo, hi, dofs = p.line
        other = 1 - axis
        tol = 1e-6 * np.ptp(mesh.X, axis=0).max()
        on = (np.abs(mesh.X[:, axis] - value) < tol) & (mesh.X[:, other] > lo - tol) & (mesh.X[:, other] < hi + tol)
        held[np.ix_(np.flatnonzero(on), list(dofs))] = True
    free = np.flatnonzero(~held.ravel())
    K, M = K[free][:, free].tocsc(), M[free][:, free].tocsc()
    if reduced:
        pos = {d: k for k, d in enumerate(free)}
        a = np.array([pos[6 * mesh.ids.index(g) + 2] for g in p.aset if 6 * mesh.ids.index(g) + 2 in pos])
        o = np.setdiff1d(np.arange(len(free)), a)
        lu = sla.splu(K[o][:, o].tocsc())
        T = np.zeros((len(free), len(a)))
        T[a, np.arange(len(a))] = 1.0
        T[o] = -lu.solve(K[o][:, a].toarray())
        w = sl.eigh(T.T @ (K @ T), T.T @ (M @ T), eigvals_only=True)
    elif len(free) < 2500:
        w = sl.eigh(K.toarray(), M.toarray(), eigvals_only=True, subset_by_index=[0, n_modes - 1])
    else:
        w = np.sort(sla.eigsh(K, n_modes, M, sigma=-1.0, which="LM", return_eigenvectors=False))
    return np.sqrt(np.abs(w[:n_modes])) / (2 * np.pi)


def peer_stiffness(peer_python: str, p: Plate, mesh: Mesh, element: str, treatment: str):
    """The global stiffness (6 DOFs per grid, unconstrained) of OpenSees' ``element`` on the mesh."""
    import scipy.sparse as sp

    t, bmir = thickness(mesh.corners, treatment)
    job = {"X": mesh.X.tolist(), "conn": mesh.conn.tolist(), "E": p.E, "nu": p.nu,
           "h": (t * np.cbrt(bmir)).tolist(), "element": element}
    with tempfile.TemporaryDirectory() as d:
        src, out = Path(d) / "job.json", Path(d) / "K.npz"
        src.write_text(json.dumps(job))
        run = subprocess.run([peer_python, __file__, "--peer-worker", str(src), str(out)],
                             capture_output=True, text=True)
        if run.returncode:
            raise SystemExit(f"OpenSees worker failed:\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}")
        z = np.load(out)
        n = 6 * len(mesh.ids)
        K = sp.csr_matrix((z["v"], (z["i"], z["j"])), shape=(n, n))
        return K, float(z["seconds"])


def peer_worker(src: str, out: str) -> None:
    """Runs under the peer's python: builds the OpenSees model and writes its stiffness (GimmeMCK)."""
    import openseespy.opensees as ops

    t0 = time.perf_counter()
    job = json.loads(Path(src).read_text())
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for k, x in enumerate(job["X"]):
        ops.node(k + 1, *map(float, x))
    for e, (nodes, h) in enumerate(zip(job["conn"], job["h"])):
        # the shear is E / 2(1 + nu) times 5/6 in OpenSees' section: HA145's G, nu are consistent
        ops.section("ElasticMembranePlateSection", e + 1, job["E"], job["nu"], h, 0.0)
        ops.element(job["element"], e + 1, *[k + 1 for k in nodes], e + 1)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.integrator("GimmeMCK", 0.0, 0.0, 1.0)
    ops.algorithm("Linear")
    ops.analysis("Transient")
    ops.analyze(1, 0.0)  # fails to solve the unconstrained system; the matrix is assembled all the same
    n = 6 * len(job["X"])
    A = np.array(ops.printA("-ret")).reshape(n, n)
    eq = np.array([ops.nodeDOFs(k + 1) for k in range(len(job["X"]))]).ravel()
    P = np.empty(n, int)
    P[eq] = np.arange(n)                               # OpenSees' equation -> grid-major DOF
    i, j = np.nonzero(A)
    np.savez(out, i=P[i], j=P[j], v=A[i, j], seconds=time.perf_counter() - t0)
    ops.wipe()


def ccx_frequencies(p: Plate, mesh: Mesh, element: str, n_modes: int) -> tuple[np.ndarray, str]:
    """CalculiX S4 (expanded to C3D8I) or S8R (C3D20R; mid-side grids added) on the mesh, each element
    at its mean thickness, the deck's point supports (a knot at each held grid), no a-set (CalculiX
    has none; at the decks' meshes the reduction moves nothing): the first n_modes out-of-plane modes
    (most of the kinetic energy in z; the in-plane ones come among them without R3 held)."""
    from ccx_driver import run_ccx, version

    if p.bar is not None:
        raise SystemExit("the CalculiX peer builds HA145 only (the crop's CBAR is not carried over)")
    t, _ = thickness(mesh.corners, "mean t")
    X, conn = mesh.X, mesh.conn
    lines = ["*NODE"] + [f"{k + 1}, {x[0]:.10g}, {x[1]:.10g}, {x[2]:.10g}" for k, x in enumerate(X)]
    nodes = [list(c + 1) for c in conn]
    if element == "S8R":
        mid: dict[tuple[int, int], int] = {}
        for c in conn:
            for a, b in zip(c, np.roll(c, -1)):
                if (min(a, b), max(a, b)) not in mid:
                    mid[min(a, b), max(a, b)] = len(X) + len(mid) + 1
                    x = (X[a] + X[b]) / 2
                    lines.append(f"{len(X) + len(mid)}, {x[0]:.10g}, {x[1]:.10g}, {x[2]:.10g}")
        nodes = [list(c + 1) + [mid[min(a, b), max(a, b)] for a, b in zip(c, np.roll(c, -1))] for c in conn]
    groups: dict[float, list[int]] = {}
    for k, tk in enumerate(np.round(t, 12)):
        groups.setdefault(float(tk), []).append(k + 1)
    for g, els in enumerate(groups.values()):
        lines.append(f"*ELEMENT, TYPE={element}, ELSET=T{g}")
        lines += [", ".join(str(v) for v in [e] + nodes[e - 1]) for e in els]
    lines += ["*MATERIAL, NAME=M", "*ELASTIC", f"{p.E:.10g}, {p.nu:.10g}", "*DENSITY", f"{p.rho:.10g}"]
    for g, tk in enumerate(groups):
        lines += [f"*SHELL SECTION, ELSET=T{g}, MATERIAL=M", f"{tk:.10g}"]
    lines.append("*BOUNDARY")
    lines += [f"{mesh.ids.index(g) + 1}, {min(d) + 1}, {max(d) + 1}" for g, d in p.held.items()]
    lines += ["*STEP", "*FREQUENCY", str(2 * n_modes), "*NODE FILE", "U", "*END STEP"]
    run = run_ccx("\n".join(lines) + "\n", f"plate{element}", threads=1, nice=10)
    shapes = np.array([run.shapes[k] for k in sorted(run.shapes)])         # (grids, modes, 3)
    oop = (shapes[:, :, 2] ** 2).sum(axis=0) / (shapes**2).sum(axis=(0, 2)) > 0.5
    return run.frequencies_hz[oop][:n_modes], version()


def percent(f, ref) -> str:
    return " ".join(f"{100 * (x / r - 1):+6.2f}" for x, r in zip(f, ref))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--levels", type=int, nargs="+", default=[1, 2, 4, 8])
    ap.add_argument("--decks", nargs="+", default=["ha145/ha145e.bdf", "ha145/ha145g.bdf", "crop/crop.bdf"])
    ap.add_argument("--variants", nargs="+", default=["deck", "line"], choices=["deck", "line"])
    ap.add_argument("--peer-python")
    ap.add_argument("--peer-levels", type=int, nargs="+", default=[1, 2, 4])
    ap.add_argument("--ccx", action="store_true", help="CalculiX S4 and S8R on HA145 (deck supports) too")
    ap.add_argument("--json", type=Path)
    ap.add_argument("--peer-worker", nargs=2)
    args = ap.parse_args()
    if args.peer_worker:
        peer_worker(*args.peer_worker)
        return
    load_average = " ".join(Path("/proc/loadavg").read_text().split()[:3])
    record = {"machine": f"{platform.node()} ({platform.machine()}), load average {load_average}",
              "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "decks": {}}
    for name in args.decks:
        for variant in args.variants:
            p = load(name, variant)
            n_modes = 8 if name.startswith("ha145") else 5
            if variant == "deck":
                ref = p.nastran[:n_modes]
                print(f"\n{name}, the deck's supports: Nastran printed (deck's mesh) "
                      f"{', '.join(f'{x:.6g}' for x in ref)} Hz; % against them")
            else:  # no Nastran figures for this model: % against flexgvt's finest mesh
                top = max(args.levels)
                ref = frequencies(p, refine(p, top), *flexgvt_matrices(p, refine(p, top), "mean t")[:2], True, n_modes)
                print(f"\n{name}, {VARIANTS[name[:5]]}: flexgvt at n = {top} (mean t, a-set) "
                      f"{', '.join(f'{x:.6g}' for x in ref)} Hz; % against them")
            print(f"{'solver':<36}{'n':>3}{'grids':>7}{'s':>7}  modes 1-{n_modes} [%]")
            entry = record["decks"].setdefault(name, {"nastran_hz": p.nastran[:n_modes], "rows": []})
            if variant != "deck":
                entry[f"{variant}_reference_hz"] = [round(float(x), 5) for x in ref]
            rows = entry["rows"]

            def show(solver, n, nodes, t0, f):
                seconds = time.perf_counter() - t0
                print(f"{solver:<36}{n:>3}{nodes:>7}{seconds:>7.1f}  {percent(f, ref)}")
                rows.append({"variant": variant, "solver": solver, "n": n, "grids": nodes,
                             "seconds": round(seconds, 2), "hz": [round(float(x), 5) for x in f]})
                sys.stdout.flush()

            for n in args.levels:
                mesh = refine(p, n)
                for treatment in ("mean t", "bilinear t") if name.startswith("ha145") else ("mean t",):
                    t0 = time.perf_counter()
                    K, M, _ = flexgvt_matrices(p, mesh, treatment)
                    show(f"flexgvt MITC4, {treatment}, a-set", n, len(mesh.ids), t0,
                         frequencies(p, mesh, K, M, True, n_modes))
                    if treatment == "mean t" and variant == "deck":
                        t0 = time.perf_counter()
                        show(f"flexgvt MITC4, {treatment}, full", n, len(mesh.ids), t0,
                             frequencies(p, mesh, K, M, False, n_modes))
                if args.peer_python and n in args.peer_levels:
                    _, M, _ = flexgvt_matrices(p, mesh, "mean t")
                    for element in PEER_ELEMENTS:
                        t0 = time.perf_counter()
                        K, _ = peer_stiffness(args.peer_python, p, mesh, element, "mean t")
                        show(f"OpenSees {element}, mean t, a-set", n, len(mesh.ids), t0,
                             frequencies(p, mesh, K, M, True, n_modes))
                if args.ccx and n in args.peer_levels and variant == "deck" and p.bar is None:
                    for element in ("S4", "S8R"):
                        t0 = time.perf_counter()
                        f, record["ccx"] = ccx_frequencies(p, mesh, element, n_modes)
                        show(f"CalculiX {element}, mean t, full", n, len(mesh.ids), t0, f)
    if args.json:
        record["command"] = "python bench/plate_decks_refine.py " + " ".join(sys.argv[1:])
        if args.peer_python:
            record["peer"] = subprocess.run(
                [args.peer_python, "-c", "import importlib.metadata as m, platform; "
                 "print('openseespy', m.version('openseespy'), 'python', platform.python_version())"],
                capture_output=True, text=True).stdout.strip()
        text = json.dumps(record, indent=1)
        for row in (r for d in record["decks"].values() for r in d["rows"]):  # one line per row
            text = text.replace(json.dumps(row, indent=1).replace("\n", "\n    "), json.dumps(row), 1)
        args.json.write_text(text + "\n")


if __name__ == "__main__":
    main()
