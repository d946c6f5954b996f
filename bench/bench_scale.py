"""The solver at wingbox scale (issue 30, "Scale"): flexgvt's nonlinear static solution to -1 g plus
15 modes about it, and the unloaded modes, on the built-up box of bench/box_mesh.py, against
CalculiX S8R on the same plates in the same run; where the time goes; the sparse factorisation
backends on the box's matrices.

    python bench/bench_scale.py profile --divisions 18 3 288      # flexgvt split of time (CPU and wall)
    python bench/bench_scale.py backends --divisions 10 2 160     # PARDISO, CHOLMOD, cholespy, MUMPS, SuperLU
    python bench/bench_scale.py compare --divisions 18 3 288 --runs 3 --json out.json   # flexgvt vs CalculiX
    python bench/bench_scale.py modes --element-size 0.1 --runs 2  # shift-invert and inertia: PARDISO vs SuperLU

Timings are CPU seconds of the process (all its threads) and of CalculiX's process, besides wall
time: on this shared 2-core machine the wall clock mostly measures the other users. Peak memory:
run under /usr/bin/time -v.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from box_mesh import box, flexgvt_model, s8r_input  # noqa: E402
from ccx_driver import run_ccx  # noqa: E402

import flexgvt as fg  # noqa: E402

N_MODES = 15


def clocks() -> tuple[float, float]:
    return time.perf_counter(), time.process_time()


# ----------------------------------------------------------------------------- CalculiX
def calculix(mesh, gravity: bool, n_modes: int = N_MODES) -> dict:
    """One CalculiX run (OMP_NUM_THREADS=2): frequencies, tip sag, wall and CPU seconds."""
    name = "minus_1g" if gravity else "unloaded"
    r = run_ccx(s8r_input(mesh, n_modes, gravity), name, shapes_of=[])
    out = {"wall_s": r.wall_s, "cpu_s": r.cpu_s, "peak_rss_mb": r.peak_rss_mb,
           "frequencies_hz": r.frequencies_hz.tolist()}
    if gravity:
        out["tip_w_m"] = float(np.mean([u[2] for u in r.displacements.values()]))
    return out


# ----------------------------------------------------------------------------- flexgvt, with a split of time
class Split:
    """Exclusive CPU and wall time of wrapped functions (nested calls subtracted)."""

    def __init__(self):
        self.cpu = defaultdict(float)
        self.wall = defaultdict(float)
        self.calls = defaultdict(int)
        self._stack = []
        self._patches = []

    def wrap(self, owner, name, key):
        fn = getattr(owner, name)
        split = self

        def timed(*a, **k):
            split._stack.append([0.0, 0.0])
            w, c = clocks()
            try:
                return fn(*a, **k)
            finally:
                dw, dc = time.perf_counter() - w, time.process_time() - c
                iw, ic = split._stack.pop()
                split.wall[key] += dw - iw
                split.cpu[key] += dc - ic
                split.calls[key] += 1
                if split._stack:
                    split._stack[-1][0] += dw
                    split._stack[-1][1] += dc

        setattr(owner, name, timed)
        self._patches.append((owner, name, fn))

    def __enter__(self):
        from flexgvt.fem import _pardiso, _shell_corotational, eigen, linsolve, modes, static, system
        from flexgvt.fem.families import shell

        self.wrap(system.System, "__init__", "set-up (System: DOF map, loads, pattern, shell frames)")
        self.wrap(_shell_corotational, "cr_kernel", "shell kernel (numba: corotational forces + tangent)")
        self.wrap(shell.ShellFamily, "terms", "shell terms: rest (frames, reference forces)")
        self.wrap(shell.ShellFamily, "mass_values", "mass matrix (element masses, corotated)")
        self.wrap(system.System, "evaluate", "evaluate: rest (scatter of forces, loads, reduce)")
        self.wrap(linsolve, "scatter_add_symmetric", "Newton matrix scattered into the analysed pattern")
        self.wrap(linsolve.CholmodCache, "_analyse", "symbolic analysis (ordering)")
        self.wrap(linsolve.CholmodCache, "_refactor", "numeric factorisation")
        self.wrap(linsolve.CholmodCache, "factor", "assembled matrix onto the analysed pattern")
        self.wrap(linsolve.spla, "splu", "SuperLU factorisation")
        self.wrap(_pardiso.PardisoLDL, "solve_A", "triangular solves (PARDISO)")
        self.wrap(static._Factor, "solve", "triangular solves (Newton)")
        self.wrap(static, "_stable", "stability check at the end (lowest eigenvalue)")
        self.wrap(static, "_rigid_body_check", "rigid-body check")
        self.wrap(system.System, "update", "state update (nodal spins)")
        self.wrap(eigen.spla, "eigsh", "eigsh (ARPACK Lanczos, without its solves)")
        self.wrap(modes, "check_matrix", "matrix checks")
        self.wrap(eigen, "rigid_count", "rigid-body count")
        self.wrap(shell.ShellFamily, "strain_energies", "mode labelling (strain energies)")
        return self

    def __exit__(self, *exc):
        for owner, name, fn in reversed(self._patches):
            setattr(owner, name, fn)

    def rows(self, total_cpu: float, total_wall: float):
        keys = sorted(self.cpu, key=lambda k: -self.cpu[k])
        out = [(k, self.cpu[k], self.wall[k], self.calls[k]) for k in keys]
        out.append(("Python driver (Newton loop, predictor, eigen post-processing)",
                    total_cpu - sum(self.cpu.values()), total_wall - sum(self.wall.values()), 0))
        return out


def flexgvt_case(model, fixed, gravity: float, split: Split | None = None, settings=None) -> dict:
    cfg = fg.Configuration("minus_1g" if gravity else "unloaded", fixed=fixed, gravity=gravity)
    w0, c0 = clocks()
    state = fg.solve_static(model, cfg, settings=settings)
    w1, c1 = clocks()
    modes = fg.solve_modes(state, N_MODES, cholmod=True if settings is None else settings.cholmod)
    w2, c2 = clocks()
    tip = np.isclose(model.xyz[:, 1], model.xyz[:, 1].max())
    sag = float(np.mean(state.positions[tip, 2] - model.xyz[tip, 2]))
    return {"static_wall_s": w1 - w0, "static_cpu_s": c1 - c0, "modes_wall_s": w2 - w1, "modes_cpu_s": c2 - c1,
            "wall_s": w2 - w0, "cpu_s": c2 - c0, "increments": len({h.step for h in state.history}),
            "iterations": len(state.history),
            "tip_w_m": sag, "frequencies_hz": modes.frequencies_hz.tolist()}


def warm_up():
    """Compile (or load from numba's cache) every kernel on a small box, outside the timings."""
    model, fixed = flexgvt_model(box(2, 2, 32))
    for g in (0.0, 1.0):
        fg.solve_modes(fg.solve_static(model, fg.Configuration("w", fixed=fixed, gravity=g)), 3)


def backend_info() -> dict:
    from flexgvt.fem import linsolve
    import scipy
    return {"backends": list(linsolve.BACKENDS), "default": linsolve.BACKENDS[0] if linsolve.BACKENDS else "superlu",
            "numpy": np.__version__, "scipy": scipy.__version__, "load_average": os.getloadavg()}


def cmd_profile(args):
    mesh = box(*args.divisions)
    model, fixed = flexgvt_model(mesh)
    warm_up()
    print(f"box {args.divisions}: {mesh.n_nodes} nodes, {6 * mesh.n_nodes} DOF; {backend_info()}")
    result = {}
    for gravity in (0.0, 1.0):
        with Split() as split:
            r = flexgvt_case(model, fixed, gravity, split)
        name = "minus_1g" if gravity else "unloaded"
        print(f"\n{name}: static {r['static_cpu_s']:.2f} s CPU ({r['static_wall_s']:.2f} s wall), modes "
              f"{r['modes_cpu_s']:.2f} s CPU ({r['modes_wall_s']:.2f} s wall); {r['increments']} increments; "
              f"tip {r['tip_w_m']:.4f} m")
        print("| part | CPU [s] | share | wall [s] | calls |\n|---|---:|---:|---:|---:|")
        rows = split.rows(r["cpu_s"], r["wall_s"])
        for key, cpu, wall, calls in rows:
            print(f"| {key} | {cpu:.2f} | {100 * cpu / r['cpu_s']:.0f} % | {wall:.2f} | {calls} |")
        r["split"] = rows
        result[name] = r
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1))


def cmd_compare(args):
    mesh = box(*args.divisions)
    have_ccx = shutil.which("ccx") is not None
    info = {"divisions": list(args.divisions), "nodes": mesh.n_nodes, "dof": 6 * mesh.n_nodes, **backend_info()}
    print(info)
    model, fixed = flexgvt_model(mesh)
    warm_up()
    out = {"info": info, "flexgvt": {"unloaded": [], "minus_1g": []}, "calculix": {"unloaded": [], "minus_1g": []}}
    for run in range(args.runs):
        for gravity in (0.0, 1.0):
            name = "minus_1g" if gravity else "unloaded"
            r = flexgvt_case(model, fixed, gravity)
            out["flexgvt"][name].append(r)
            print(f"flexgvt {name} run {run + 1}: {r['cpu_s']:.2f} s CPU ({r['wall_s']:.2f} s wall), static "
                  f"{r['static_cpu_s']:.2f} s, modes {r['modes_cpu_s']:.2f} s, tip {r['tip_w_m']:.4f} m", flush=True)
            if have_ccx and run < args.ccx_runs:
                c = calculix(mesh, bool(gravity))
                out["calculix"][name].append(c)
                print(f"CalculiX {name} run {run + 1}: {c['cpu_s']:.1f} s CPU ({c['wall_s']:.1f} s wall)", flush=True)
            if args.json:
                Path(args.json).write_text(json.dumps(out, indent=1))
    if not have_ccx:
        print("CalculiX (ccx) is not installed: apt-get install calculix-ccx")
        return
    for name in ("unloaded", "minus_1g"):
        f_cpu = np.array([r["cpu_s"] for r in out["flexgvt"][name]])
        c_cpu = np.array([r["cpu_s"] for r in out["calculix"][name]])
        f_wall = np.array([r["wall_s"] for r in out["flexgvt"][name]])
        c_wall = np.array([r["wall_s"] for r in out["calculix"][name]])
        fr = np.array(out["flexgvt"][name][0]["frequencies_hz"])
        cr = np.array(out["calculix"][name][0]["frequencies_hz"])
        k = min(len(fr), len(cr))
        print(f"{name}: CalculiX / flexgvt CPU {c_cpu.mean() / f_cpu.max():.1f}-{c_cpu.mean() / f_cpu.min():.1f}x "
              f"(flexgvt {f_cpu.min():.2f}-{f_cpu.max():.2f} s, CalculiX {c_cpu.min():.1f}-{c_cpu.max():.1f} s); wall "
              f"{c_wall.mean() / f_wall.max():.1f}-{c_wall.mean() / f_wall.min():.1f}x; frequency differences "
              f"{np.round(100 * (fr[:k] / cr[:k] - 1), 2).tolist()} %")


def cmd_backends(args):
    """Each backend in its own process on the box's -1 g Newton matrix (K + alpha M), the
    shift-invert matrix K - sigma M (sigma just below zero) and an indefinite K - (2 pi 20 Hz)^2 M."""
    mesh = box(*args.divisions)
    model, fixed = flexgvt_model(mesh)
    import scipy.sparse as sp
    state = fg.solve_static(model, fg.Configuration("minus_1g", fixed=fixed, gravity=1.0))
    system, x, R = state.system, state.positions, state.rotations
    M = system.mass_matrix(x, R)
    K = system.newton_matrix(system.evaluate(x, R, 1.0, assemble=False), M, 0.0)
    with tempfile.TemporaryDirectory() as tmp:
        sp.save_npz(f"{tmp}/K.npz", K.tocsc())
        sp.save_npz(f"{tmp}/M.npz", M.tocsc())
        rows = []
        for matrix in ("newton", "shift_invert", "indefinite"):
            for backend in args.only or ("superlu", "cholmod-simplicial", "cholmod-supernodal", "cholespy", "pardiso",
                                         "mumps"):
                p = subprocess.run([sys.executable, __file__, "_one_backend", backend, tmp, matrix],
                                   capture_output=True, text=True)
                line = p.stdout.strip().splitlines()[-1] if p.stdout.strip() else json.dumps(
                    {"backend": backend, "matrix": matrix, "error": p.stderr[-300:]})
                rows.append(json.loads(line))
                print(line, flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps({"info": {"divisions": list(args.divisions), "n": K.shape[0]},
                                               "rows": rows}, indent=1))


def one_backend(which: str, folder: str, matrix: str) -> None:
    """Analysis, factorisation, refactorisation on the same analysis, 1 and 20 right-hand sides; CPU and wall."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla
    K, M = sp.load_npz(f"{folder}/K.npz").tocsc(), sp.load_npz(f"{folder}/M.npz").tocsc()
    shift = {"newton": -(2 * np.pi * 1e-3) ** 2, "shift_invert": -(2 * np.pi * 0.01) ** 2,
             "indefinite": (2 * np.pi * 20.0) ** 2}[matrix]
    A = (K - shift * M).tocsc()
    A.eliminate_zeros()
    A.sort_indices()
    n = A.shape[0]
    b = np.random.default_rng(0).standard_normal(n)
    B = np.random.default_rng(1).standard_normal((n, 20))
    out = {"backend": which, "matrix": matrix, "n": n, "nnz": int(A.nnz),
           "rss_before_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}

    def lap(key, t):
        out[key] = [time.perf_counter() - t[0], time.process_time() - t[1]]

    try:
        if which == "superlu":
            t = clocks()
            lu = spla.splu(A, permc_spec="COLAMD", options={"SymmetricMode": True})
            lap("factor", t)
            solve = lu.solve
            out["factor_nnz"] = int(lu.L.nnz + lu.U.nnz)
        elif which.startswith("cholmod"):
            from sksparse import cholmod
            t = clocks()
            f = cholmod.analyze(A, mode=which.split("-")[1])
            lap("analyse", t)
            t = clocks()
            f.cholesky_inplace(A)
            lap("factor", t)
            t = clocks()
            f.cholesky_inplace(A)
            lap("refactor", t)
            solve = f.solve_A
            if which.endswith("simplicial"):
                out["negative_pivots"] = int((f.D() < 0).sum())
        elif which == "cholespy":
            from cholespy import CholeskySolverD, MatrixType
            args = (n, A.indptr.astype(np.int32), A.indices.astype(np.int32), A.data.copy(), MatrixType.CSC)
            t = clocks()
            s = CholeskySolverD(*args)
            lap("factor", t)  # analysis and factorisation in one call; no refactorisation on a kept analysis

            def solve(r):
                r = np.ascontiguousarray(r, dtype=float)
                x = np.empty_like(r)
                s.solve(r, x)
                return x
        elif which == "pardiso":
            from flexgvt.fem._pardiso import PardisoLDL
            t = clocks()
            f = PardisoLDL(A.indptr, A.indices, n)
            lap("analyse", t)
            t = clocks()
            if not f.refactor(A.data):
                raise RuntimeError("perturbed pivots")
            lap("factor", t)
            t = clocks()
            f.refactor(A.data)
            lap("refactor", t)
            out["negative_pivots"] = f.inertia[1]
            out["factor_nnz"] = f.factor_nnz
            solve = f.solve_A
        elif which == "mumps":
            import mumps
            ctx = mumps.Context()
            t = clocks()
            ctx.set_matrix(sp.triu(A, format="coo"), symmetric=True)
            ctx.analyze(ordering="auto")
            lap("analyse", t)
            t = clocks()
            ctx.factor(reuse_analysis=True)
            lap("factor", t)
            t = clocks()
            ctx.factor(reuse_analysis=True)
            lap("refactor", t)
            out["negative_pivots"] = int(ctx.mumps_instance.infog[12])
            out["factor_nnz"] = int(ctx.mumps_instance.infog[29])
            out["ordering"] = ctx.analysis_stats.ordering
            solve = ctx.solve
        t = clocks()
        x = solve(b)
        lap("solve_1", t)
        t = clocks()
        X = np.asarray(solve(B)).reshape(n, -1)
        lap("solve_20", t)
        out["residual"] = float(np.linalg.norm(A @ x - b) / np.linalg.norm(b))
        out["residual_20"] = float(np.linalg.norm(A @ X - B) / np.linalg.norm(B))
    except Exception as exc:  # a backend refusing the matrix (not positive definite) is a result
        out["error"] = f"{type(exc).__name__}: {exc}"[:160]
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(out))


def cmd_modes(args):
    """The modes' shift-invert through PARDISO against SuperLU (same process, alternating rounds) and
    the stability check's negative eigenvalue count (PARDISO's inertia against SuperLU's diagonal
    pivots) on fg.cases.wingbox(element_size) at -1 g and unloaded, or on the box with --divisions."""
    from flexgvt.fem.linsolve import inertia
    from flexgvt.fem.stability import _matrices, shifted, superlu_negative_pivots

    if args.box:
        model, fixed = flexgvt_model(box(*args.divisions))
        configs = {name: fg.Configuration(name, fixed=fixed, gravity=g) for name, g in (("unloaded", 0.0),
                                                                                      ("minus_1g", 1.0))}
        what = f"box {args.divisions}"
    else:
        case = fg.cases.wingbox(args.element_size)
        model, configs = case.model, {k: case.configurations[k] for k in ("unloaded", "minus_1g")}
        what = f"wingbox {args.element_size} m"
    warm_up()
    out = {"info": {"model": what, **backend_info()}}
    for name, config in configs.items():
        state = fg.solve_static(model, config)
        s, x, R = state.system, state.positions, state.rotations
        row = {"dof": int(s.n_free)}
        times = {"pardiso": [], "superlu": []}
        freqs = {}
        for _ in range(args.runs):
            for key, fast in (("pardiso", True), ("superlu", False)):
                t = clocks()
                modes = fg.solve_modes(state, N_MODES, damped=False, cholmod=fast, label=False)
                times[key].append([time.perf_counter() - t[0], time.process_time() - t[1]])
                freqs[key] = modes.frequencies_hz
        row["modes_wall_cpu_s"] = {k: np.min(v, axis=0).round(3).tolist() for k, v in times.items()}
        row["modes_max_rel_diff"] = float(np.max(np.abs(freqs["pardiso"] / freqs["superlu"] - 1)))
        row["f_hz"] = freqs["pardiso"][:6].round(4).tolist()
        K, M = _matrices(s, x, R, state.load_factor)
        A = shifted(s, K, M)
        t = clocks()
        counts = inertia(A)
        row["inertia_pardiso"] = counts
        row["inertia_pardiso_cpu_s"] = round(time.process_time() - t[1], 3)
        t = clocks()
        row["negative_superlu"] = superlu_negative_pivots(A)
        row["negative_superlu_cpu_s"] = round(time.process_time() - t[1], 3)
        out[name] = row
        print(name, json.dumps(row), flush=True)
    out["info"]["load_average_end"] = os.getloadavg()
    print(json.dumps(out["info"]))
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))


def main(argv=None):
    if argv is None and len(sys.argv) > 1 and sys.argv[1] == "_one_backend":
        return one_backend(*sys.argv[2:5])
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("command", choices=("profile", "compare", "backends", "modes"))
    parser.add_argument("--divisions", type=int, nargs=3, default=(18, 3, 288), metavar=("CHORD", "DEPTH", "SPAN"),
                        help="quads across the chord, the depth and along the span (18 3 288: 79,356 DOF)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--ccx-runs", type=int, default=1)
    parser.add_argument("--only", nargs="*")
    parser.add_argument("--json")
    parser.add_argument("--element-size", type=float, default=0.1, help="modes: fg.cases.wingbox's element size [m]")
    parser.add_argument("--box", action="store_true", help="modes: the box of --divisions instead of the wingbox case")
    args = parser.parse_args(argv)
    {"profile": cmd_profile, "compare": cmd_compare, "backends": cmd_backends, "modes": cmd_modes}[args.command](args)


if __name__ == "__main__":
    main()
