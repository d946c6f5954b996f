"""Benchmark of the linear shell element kernels (src/flexgvt/fem/_shell_kernel.py):

* throughput: stiffness + consistent mass of 10,000 quads and 10,000 triangles (elements/s, warm,
  the minimum over repeats; the first call's compile or cache load is reported apart);
* a peer: the simply supported square plate under uniform pressure (a = 1 m, t = 10 mm, aluminium,
  n x n quads) solved by flexgvt's kernels + a scipy sparse assembly and solve, and by OpenSeesPy's
  ShellMITC4 and ASDShellQ4 on the same mesh and nodal loads (centre deflection and wall time).
  OpenSeesPy runs in a subprocess with the interpreter given by --peer-python (it needs Debian's
  libblas3 / liblapack3; a separate venv keeps it out of flexgvt's environment).

Usage:  python bench/bench_shell.py [--n 10000] [--plate 64 128] [--peer-python PATH] [--no-write]

Prints the tables and rewrites the section "## Benchmarks" of docs/shells.md.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as spla

from flexgvt.fem._shell_elements import assemble, shell_matrices
from flexgvt.fem._shell_section import mat1, pshell, section_arrays

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "shells.md"
SECTION = "## Benchmarks"
E, NU, RHO, T, A, Q = 70e9, 0.3, 2700.0, 0.01, 1.0, 1000.0  # Pa, -, kg/m^3, m, m, Pa


def plate_mesh(n: int, tri: bool = False):
    """Nodes (m, 3) and connectivity of an n x n mesh of the a x a square (two triangles per cell)."""
    s = np.linspace(0.0, A, n + 1)
    X, Y = np.meshgrid(s, s, indexing="ij")
    xyz = np.c_[X.ravel(), Y.ravel(), np.zeros(X.size)]
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    q = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    return xyz, (np.vstack([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]) if tri else q)


def throughput(n: int, repeats: int = 5) -> dict:
    sec = pshell(T, mat1(E, nu=NU, rho=RHO), mat1(E, nu=NU, rho=RHO))
    out = {}
    for kind in ("quad", "triangle"):
        side = int(np.ceil(np.sqrt(n if kind == "quad" else n / 2)))
        xyz, conn = plate_mesh(side, kind == "triangle")
        xyz[:, 2] = 0.01 * np.sin(7 * xyz[:, 0]) * np.cos(5 * xyz[:, 1])  # warped, general frames
        conn = conn[:n]
        C, m = section_arrays([sec], np.zeros(len(conn), int))
        X = xyz[conn]
        t0 = time.perf_counter()
        shell_matrices(X[:300], C[:300], m[:300])  # first call: compile or cache load
        first = time.perf_counter() - t0
        best = np.inf
        for _ in range(repeats):
            t0 = time.perf_counter()
            shell_matrices(X, C, m)
            best = min(best, time.perf_counter() - t0)
        out[kind] = dict(elements=len(conn), seconds=best, per_second=len(conn) / best, first_call=first)
    return out


def plate_fixed(xyz):
    """Hard simple support on the edges, in-plane DOFs held everywhere (a pure plate problem)."""
    x, y = xyz[:, 0], xyz[:, 1]
    onx = np.isclose(x, 0) | np.isclose(x, A)
    ony = np.isclose(y, 0) | np.isclose(y, A)
    fix = [6 * np.arange(len(x)) + k for k in (0, 1, 5)]
    fix += [6 * np.flatnonzero(onx | ony) + 2, 6 * np.flatnonzero(onx) + 3, 6 * np.flatnonzero(ony) + 4]
    return np.unique(np.concatenate(fix))


def nodal_loads(xyz, conn):
    """int N_i q dA on w (quads: a quarter of the element's area per node)."""
    X = xyz[conn]
    area = 0.5 * np.linalg.norm(np.cross(X[:, 2] - X[:, 0], X[:, 3] - X[:, 1]), axis=1)
    f = np.zeros(6 * len(xyz))
    np.add.at(f, 6 * conn + 2, np.repeat(area[:, None] / 4, 4, 1) * Q)
    return f


def flexgvt_plate(n: int) -> dict:
    sec = pshell(T, mat1(E, nu=NU, rho=RHO), mat1(E, nu=NU, rho=RHO))
    xyz, conn = plate_mesh(n)
    t0 = time.perf_counter()
    C, m = section_arrays([sec], np.zeros(len(conn), int))
    r = shell_matrices(xyz[conn], C)
    t1 = time.perf_counter()
    K = assemble(conn, r.K, len(xyz))
    fixed = plate_fixed(xyz)
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    Kf = K[free][:, free].tocsc()
    t2 = time.perf_counter()
    u = np.zeros(K.shape[0])
    u[free] = spla.spsolve(Kf, nodal_loads(xyz, conn)[free])
    t3 = time.perf_counter()
    c = np.argmin(np.sum((xyz - [A / 2, A / 2, 0]) ** 2, axis=1))
    return dict(w=u[6 * c + 2], elements=t1 - t0, assembly=t2 - t1, solve=t3 - t2, total=t3 - t0, dof=len(free))


PEER = textwrap.dedent('''
    import json, sys, time
    import numpy as np
    import openseespy.opensees as ops
    n, kind, E, nu, rho, t, a, q = json.loads(sys.argv[1])
    t0 = time.perf_counter()
    ops.wipe(); ops.model("basic", "-ndm", 3, "-ndf", 6)
    s = np.linspace(0, a, n + 1)
    tag = lambda i, j: i * (n + 1) + j + 1
    for i in range(n + 1):
        for j in range(n + 1):
            ops.node(tag(i, j), s[i], s[j], 0.0)
            onx, ony = i in (0, n), j in (0, n)
            ops.fix(tag(i, j), 1, 1, int(onx or ony), int(onx), int(ony), 1)
    ops.section("ElasticMembranePlateSection", 1, E, nu, t, rho)
    e = 0
    for i in range(n):
        for j in range(n):
            e += 1
            ops.element(kind, e, tag(i, j), tag(i + 1, j), tag(i + 1, j + 1), tag(i, j + 1), 1)
    ops.timeSeries("Constant", 1); ops.pattern("Plain", 1, 1)
    h = a / n
    for i in range(n + 1):
        for j in range(n + 1):
            w = (0.5 if i in (0, n) else 1.0) * (0.5 if j in (0, n) else 1.0)
            ops.load(tag(i, j), 0, 0, w * q * h * h, 0, 0, 0)
    ops.system(sys.argv[2]); ops.numberer("RCM"); ops.constraints("Plain")
    ops.integrator("LoadControl", 1.0); ops.algorithm("Linear"); ops.analysis("Static")
    t1 = time.perf_counter()
    ops.analyze(1)
    t2 = time.perf_counter()
    print(json.dumps(dict(w=ops.nodeDisp(tag(n // 2, n // 2), 3), build=t1 - t0, analyze=t2 - t1, total=t2 - t0)))
''')


def peer_plate(python: str, n: int, kind: str, system: str) -> dict | None:
    args = json.dumps([n, kind, E, NU, RHO, T, A, Q])
    try:
        res = subprocess.run([python, "-c", PEER, args, system], capture_output=True, text=True, timeout=1800)
    except (OSError, subprocess.TimeoutExpired) as err:
        print(f"peer {kind}: {err}")
        return None
    lines = [ln for ln in res.stdout.splitlines() if ln.startswith("{")]
    if res.returncode != 0 or not lines:
        print(f"peer {kind} failed: {res.stderr[-400:]}")
        return None
    return json.loads(lines[-1])


def write_section(text: str) -> None:
    doc = DOC.read_text() if DOC.exists() else "# Shell elements\n"
    pattern = re.compile(rf"^{re.escape(SECTION)}\n.*?(?=^## |\Z)", re.S | re.M)
    block = f"{SECTION}\n\n{text.strip()}\n\n"
    doc = pattern.sub(block, doc) if pattern.search(doc) else doc.rstrip() + "\n\n" + block
    DOC.write_text(doc.rstrip() + "\n")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10000)
    ap.add_argument("--plate", type=int, nargs="+", default=[64, 128])
    ap.add_argument("--peer-python", default=sys.executable)
    ap.add_argument("--peer-system", default="UmfPack", help="OpenSees system of equations")
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()
    import numba
    lines = [f"Machine: {numba.get_num_threads()} numba threads; numpy {np.__version__}.", "",
             "Element kernel throughput (global stiffness + consistent mass, warm, best of 5):", "",
             "| element | elements | time [ms] | elements/s | first call [s] |", "|---|---|---|---|---|"]
    for kind, r in throughput(a.n).items():
        lines.append(f"| {kind} | {r['elements']} | {1e3 * r['seconds']:.1f} | {r['per_second']:,.0f} | "
                     f"{r['first_call']:.2f} |")
    D = E * T**3 / (12 * (1 - NU**2))
    ref = 0.00406235 * Q * A**4 / D
    lines += ["", f"Simply supported square plate, uniform pressure (a = {A} m, t = {T * 1e3:g} mm, "
              f"E = {E / 1e9:g} GPa, q = {Q:g} Pa; Timoshenko w = {ref * 1e3:.5f} mm; Mindlin adds about (t/a)^2):", "",
              "| mesh | code | centre w / Timoshenko | total [s] | split |", "|---|---|---|---|---|"]
    for n in a.plate:
        r = flexgvt_plate(n)
        lines.append(f"| {n} x {n} ({r['dof']} DOF) | flexgvt MITC4 (scipy SuperLU) | {r['w'] / ref:.5f} | "
                     f"{r['total']:.3f} | elements {r['elements']:.3f}, assembly {r['assembly']:.3f}, "
                     f"solve {r['solve']:.3f} |")
        for kind in ("ShellMITC4", "ASDShellQ4"):
            p = peer_plate(a.peer_python, n, kind, a.peer_system)
            if p is not None:
                lines.append(f"| {n} x {n} | OpenSeesPy {kind} ({a.peer_system}) | {p['w'] / ref:.5f} | "
                             f"{p['total']:.3f} | build {p['build']:.3f}, analyze {p['analyze']:.3f}; "
                             f"total x{p['total'] / r['total']:.1f} flexgvt's, analyze "
                             f"x{p['analyze'] / r['total']:.2f} flexgvt's total |")
    text = "\n".join(lines)
    print(text)
    if not a.no_write:
        write_section(text)


if __name__ == "__main__":
    main()
