"""The X-HALE lab lines' pendulum length (not published) against the lab fit and the free-flying
prediction (issue 33).

    python bench/xhale_pendulum.py [--lengths 2 3 4 6 10] [--json PATH]

Each length runs examples/xhale_lab/run.py --pendulum-length L (the default 33 variables: the
original work's 30 and the pods' masses) without its report, and prints the lab fit's rms errors
and the first bending predicted free-free and on the 20 m bungees. The string below the pulley
holds each junction sideways with T / L; on the hung, sagging wing (the centre 0.58 m below the
outboard junctions) that restraint and the tension it puts in the wing stiffen the first bending.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import tempfile
import time
import warnings
from pathlib import Path

from flexgvt.errors import FlexGVTWarning


def _example():
    path = Path(__file__).resolve().parents[1] / "examples" / "xhale_lab" / "run.py"
    spec = importlib.util.spec_from_file_location("xhale_lab_example_run", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lengths", type=float, nargs="+", default=[2.0, 3.0, 4.0, 6.0, 10.0])
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore", FlexGVTWarning)
    example = _example()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for length in args.lengths:
            t0 = time.perf_counter()
            out = example.main(["--out", str(Path(tmp) / f"L{length:g}"), "--pendulum-length", str(length),
                                "--no-report"])
            first = next(r for r in out["prediction"] if r["label"].startswith("1 OOP"))
            rows.append({"pendulum_length_m": length,
                         "lab_rms_percent": {c: out["rms_error_percent"][c]["updated_hz"]
                                             for c in ("outboard", "inboard")},
                         "free_hz": first["free_hz"], "bungee_outboard_hz": first["bungee_outboard_hz"],
                         "bungee_inboard_hz": first["bungee_inboard_hz"], "seconds": time.perf_counter() - t0})
    print(f"\n{'L [m]':>6} {'lab rms outboard / inboard [%]':>31} {'1 OOP free':>10} {'bungees out':>11} "
          f"{'bungees in':>10}  [Hz]")
    for r in rows:
        lab = r["lab_rms_percent"]
        print(f"{r['pendulum_length_m']:6.1f} {lab['outboard']:15.2f} / {lab['inboard']:<13.2f} {r['free_hz']:10.3f} "
              f"{r['bungee_outboard_hz']:11.3f} {r['bungee_inboard_hz']:10.3f}")
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1))
    return {"rows": rows}


if __name__ == "__main__":
    main()
