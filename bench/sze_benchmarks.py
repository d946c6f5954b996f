"""Sze, Liu & Lo (2004) nonlinear shell benchmarks at the paper's meshes, every tabulated level:
the measured values, their errors against the tables and the time (docs/shells.md, "Nonlinear
benchmarks"). The models and tables are those of tests/fem/test_sze_benchmarks.py.

    PYTHONPATH=src python bench/sze_benchmarks.py [slit hemisphere hemisphere24 pullout pinched pullout48 pinched64
                                                   pinched32]
"""

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "fem"))
import test_sze_benchmarks as sze  # noqa: E402

import flexgvt as fg  # noqa: E402

CASES = {  # name: (builder, mesh, table, columns, control)
    "slit": (sze.slit_annular_plate, (10, 80), sze.SLIT, ("W_A", "W_B"), "load"),
    "hemisphere": (sze.hemisphere, (16,), sze.HEMISPHERE, ("U_A out", "-U_B in"), "load"),
    "hemisphere24": (sze.hemisphere, (24,), sze.HEMISPHERE, ("U_A out", "-U_B in"), "load"),
    "pullout": (sze.pullout, (24, 36), sze.PULLOUT, ("W_A", "-U_B", "-U_C"), "load"),
    "pinched": (sze.pinched_cylinder, (48, 48), sze.PINCHED, ("-W_A", "U_B"), "arc-length"),
    # finer than the paper's meshes (the issue allows "at their meshes or finer")
    "pullout48": (sze.pullout, (48, 72), sze.PULLOUT, ("W_A", "-U_B", "-U_C"), "load"),
    "pinched64": (sze.pinched_cylinder, (64, 64), sze.PINCHED, ("-W_A", "U_B"), "arc-length"),
    # coarser, for the mesh trend against the independent solver (bench/peer_pinched_cylinder.py)
    "pinched32": (sze.pinched_cylinder, (32, 32), sze.PINCHED, ("-W_A", "U_B"), "arc-length"),
}


def run(name: str) -> None:
    build, mesh, table, columns, control = CASES[name]
    model, config, points = build(*mesh)
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        state = sze._solve(model, config, table[:, 0], control)
    except fg.errors.FlexGVTError as exc:
        print(f"{name} {'x'.join(map(str, mesh))} ({control}): failed: {exc}")
        return
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    got = sze.measured(name.rstrip("0123456789"), state, points)
    err = sze._errors(table, got)
    print(f"\n{name}, {'x'.join(map(str, mesh))} quads, {control} control: {wall:.1f} s wall, {cpu:.1f} s CPU, "
          f"{len(state.history)} iterations")
    if state.instability is not None:
        print(f"  {state.instability.describe()}")
    print("  P/Pmax " + " ".join(f"{c:>9} {'ref':>8} {'err %':>6}" for c in columns))
    for level, g, ref, e in zip(table[:, 0], got, table[:, 1:], err):
        print(f"  {level:6.3f} " + " ".join(f"{a:9.3f} {b:8.3f} {100 * c:+6.2f}" for a, b, c in zip(g, ref, e)))
    print(f"  largest error {100 * np.abs(err).max():.2f} %")


if __name__ == "__main__":
    for case in sys.argv[1:] or list(CASES):
        run(case)
