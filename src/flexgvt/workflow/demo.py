"""`flexgvt demo`: the whole method on the X-HALE-like aircraft (docs/method.md sections 3-5).

A synthetic GVT of the "as-built" airframe (per-section stiffness and mass differences) in both
suspension layouts -> PolyMAX identification -> updating of the nominal model on both at once ->
suspension removed -> free-free and 20 m bungee predictions scored against the as-built truth.
The truth is used only to make the data and to score the prediction.
"""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path
from typing import Callable

import numpy as np

from ..model import Configuration
from ..updating.settings import renamed
from .projectbase import Project

SCORED_MODES = 7  # the first elastic free-free modes the prediction is judged on
# Truth modes within 3 % of each other are a close cluster: the demo's 3 OOP and 1 T (0.9 % apart)
# mix in the updated model by an amount set by left-right differences the data hardly see (MAC 0.53-0.99
# between factorisations' round-off, frequencies within 0.24 % throughout), so they are judged by span.
CLOSE = 0.03


def _full_mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    A = a.reshape(len(a), -1)
    B = b.reshape(len(b), -1)
    num = (A @ B.T) ** 2
    return num / np.outer(np.einsum("ij,ij->i", A, A), np.einsum("ij,ij->i", B, B))


def close_clusters(frequencies_hz: np.ndarray, close: float = CLOSE) -> list[list[int]]:
    """Indices of ascending ``frequencies_hz`` grouped into runs whose neighbours lie within ``close``
    (relative) of each other; isolated modes are groups of one."""
    groups: list[list[int]] = []
    for k, f in enumerate(frequencies_hz):
        if groups and f <= frequencies_hz[groups[-1][-1]] * (1.0 + close):
            groups[-1].append(k)
        else:
            groups.append([k])
    return groups


def score_against_truth(truth_modes, predicted_modes, n: int = SCORED_MODES, close: float = CLOSE) -> list[dict]:
    """The first ``n`` elastic truth modes, each paired with the predicted mode of highest full-shape
    MAC (same mesh): truth and predicted frequencies, error [%] and MAC. A truth mode with a
    neighbour within ``close`` in frequency also gets subspace_mac: the share of its shape that lies
    in the span of the predicted modes paired with its cluster (the shapes of a close pair turn into
    each other under asymmetries the test data cannot see; their span does not); None otherwise."""
    from scipy.optimize import linear_sum_assignment
    te = np.flatnonzero(truth_modes.frequencies_hz > 0)[:n]
    pe = np.flatnonzero(predicted_modes.frequencies_hz > 0)
    m = _full_mac(truth_modes.shapes[te], predicted_modes.shapes[pe])
    r, c = linear_sum_assignment(-m)
    partner = dict(zip(r.tolist(), c.tolist()))
    subspace = {}
    for group in close_clusters(truth_modes.frequencies_hz[te], close):
        if len(group) < 2:
            continue
        basis, _ = np.linalg.qr(predicted_modes.shapes[pe[[partner[i] for i in group]]].reshape(len(group), -1).T)
        for i in group:
            a = truth_modes.shapes[te[i]].ravel()
            subspace[i] = float(np.sum((basis.T @ a) ** 2) / (a @ a))
    rows = []
    for i, j in zip(r, c):
        ft, fp = float(truth_modes.frequencies_hz[te[i]]), float(predicted_modes.frequencies_hz[pe[j]])
        rows.append({"mode": int(i) + 1, "label": truth_modes.labels[te[i]], "truth_hz": ft, "predicted_hz": fp,
                     "error_percent": 100 * (fp - ft) / ft, "mac": float(m[i, j]),
                     "subspace_mac": subspace.get(int(i))})
    return rows


def _elastic(modes):
    """The modes with their suspension and rigid-body modes (mostly cord or rigid energy) set to 0 Hz."""
    return replace(modes, frequencies_hz=np.where(modes.energy_fractions[:, 4] > 0.5, 0.0, modes.frequencies_hz))


def _rms(values) -> float:
    v = [x for x in values if x is not None]
    return float(np.sqrt(np.mean(np.square(v)))) if v else float("nan")


def demo_project(out: Path, seed: int = 7, progress: Callable[[str], None] = print, *,
                 log: Callable[[str], None] | None = None) -> Project:
    """Write the demo's synthetic GVT and project file into ``out``; returns the loaded Project.
    progress: receives one line per step (``log``: its deprecated name)."""
    from .project import load_project
    from .template import write_example
    if log is not None:
        renamed("demo_project(log=...)", "demo_project(progress=...)")
        progress = log
    folder = Path(out)
    write_example(folder, seed=seed, progress=progress)
    return load_project(folder / "project.toml")


def run_demo(out: Path, seed: int = 7, progress: Callable[[str], None] = print, *,
             log: Callable[[str], None] | None = None) -> dict:
    """Run the demo into ``out``; returns the figures of its --json layout. The workflow never
    renders: `flexgvt demo` runs demo_project, workflow.run, the report, then demo_figures.
    progress: receives one line per step (``log``: its deprecated name)."""
    from .runner import run
    if log is not None:
        renamed("run_demo(log=...)", "run_demo(progress=...)")
        progress = log
    t0 = time.perf_counter()
    project = demo_project(out, seed, progress)
    t_data = time.perf_counter() - t0
    return demo_figures(run(project, progress), out, seed, t_data, t0)


def demo_figures(res, out: Path, seed: int, t_data: float, t0: float) -> dict:
    """The --json figures of a demo run into ``out``: free-free and bungee predictions scored against
    the as-built truth of ``seed``; t_data: time [s] to write the synthetic data, t0: perf_counter
    at the start."""
    from .. import cases
    from ..fem import solve_modes, solve_static
    project = res.project
    folder = Path(out)
    truth = cases.xhale(as_built=True, seed=seed)
    free_truth = solve_modes(solve_static(truth.model, Configuration("free_free")), SCORED_MODES + 8, damped=False)
    scores = {key: score_against_truth(free_truth, pred.free) for key, pred in res.predictions.items()}
    bungees = {}
    for name in project.spec.prediction.proposed:
        tm = solve_modes(solve_static(truth.model, truth.configurations[name]), 20, damped=False)
        bungees[name] = {key: score_against_truth(_elastic(tm), _elastic(pred.proposed[name]))
                         for key, pred in res.predictions.items()}
    configurations = {}
    if res.update is not None:
        for name, rows in res.update.tables.items():
            configurations[name] = {"initial_rms_error_percent": _rms(r["initial_error_percent"] for r in rows),
                                    "updated_rms_error_percent": _rms(r["updated_error_percent"] for r in rows),
                                    "modes": len(rows)}
    worst = {k: max(abs(r["error_percent"]) for r in rows) for k, rows in scores.items()}
    return {"case": "xhale", "seed": seed, "output": str(folder), "files": res.files,
            "timings_s": {"synthetic_gvt": t_data, **res.timings, "total": time.perf_counter() - t0},
            "free_free": scores, "max_abs_error_percent": worst, "bungees": bungees,
            "configurations": configurations,
            "updating": None if res.update is None else {"objective_initial": res.update.initial.objective,
                                                         "objective_final": res.update.final.objective,
                                                         "iterations": len(res.update.history) - 1,
                                                         "message": res.update.message},
            "identified": {n: {"frequencies_hz": i.frequencies_hz.tolist(), "damping_ratio": i.damping_ratio.tolist()}
                           for n, i in res.identified.items()}}
