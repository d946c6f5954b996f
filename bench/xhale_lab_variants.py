"""The X-HALE's unpublished dimensions against the lab fit and the free-flying prediction (issue 33).

    python bench/xhale_lab_variants.py [--json PATH] [--quick]

Each variant runs examples/xhale_lab/run.py with one chosen dimension of fg.cases.xhale changed
(`--property NAME=VALUE`; the default 33 variables: the original work's 30 and the pods' masses)
without its report, and prints the lab fit's rms errors and the first bending predicted free-free
and on the 20 m bungees. The dimensions: the lab lines' string below the pulley (pendulum_length:
it holds each junction sideways with T / L, and the hung wing sags 0.58 m at the centre between the
outboard junctions, so its first bending moves them sideways), the joiners' length (joiner_half)
and the pods' drop below the wing (pod_offset_z). --quick: the case's values and one pendulum
length (a smoke run).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

from flexgvt.errors import FlexGVTWarning

sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/ beside this script
from benchdoc import load_example  # noqa: E402

VARIANTS = [{}, {"pendulum_length": 2.0}, {"pendulum_length": 4.0}, {"pendulum_length": 6.0},
            {"pendulum_length": 10.0}, {"joiner_half": 0.025}, {"joiner_half": 0.08}, {"joiner_half": 0.12},
            {"pod_offset_z": -0.02}, {"pod_offset_z": -0.1}]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--quick", action="store_true", help="the case's values and one pendulum length")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore", FlexGVTWarning)
    example = load_example("xhale_lab/run.py", "xhale_lab_example_run")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, variant in enumerate(VARIANTS[:2] if args.quick else VARIANTS):
            t0 = time.perf_counter()
            extra = [a for name, value in variant.items() for a in ("--property", f"{name}={value}")]
            with contextlib.redirect_stdout(io.StringIO()):
                out = example.main(["--out", str(Path(tmp) / f"v{k}"), "--no-report", *extra])
            first = next(r for r in out["prediction"] if r["label"].startswith("1 OOP"))
            rms = out["rms_error_percent"]
            rows.append({"variant": variant,
                         "lab_rms_percent": {c: rms[c]["updated_hz"] for c in ("outboard", "inboard")},
                         "lab_initial_rms_percent": {c: rms[c]["initial_hz"] for c in ("outboard", "inboard")},
                         "free_hz": first["free_hz"], "bungee_outboard_hz": first["bungee_outboard_hz"],
                         "bungee_inboard_hz": first["bungee_inboard_hz"], "seconds": time.perf_counter() - t0})
    print(f"{'variant':<22} {'lab rms out / in [%]':>20} {'(initial)':>13} {'1 OOP free':>10} {'bungees out':>11} "
          f"{'bungees in':>10}  [Hz]")
    for r in rows:
        name = ", ".join(f"{k} = {v:g}" for k, v in r["variant"].items()) or "the case's values"
        lab, ini = r["lab_rms_percent"], r["lab_initial_rms_percent"]
        print(f"{name:<22} {lab['outboard']:10.2f} / {lab['inboard']:<7.2f} ({ini['outboard']:.2f} / "
              f"{ini['inboard']:.2f}) {r['free_hz']:10.3f} {r['bungee_outboard_hz']:11.3f} "
              f"{r['bungee_inboard_hz']:10.3f}")
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1))
    return {"rows": rows}


if __name__ == "__main__":
    main()
