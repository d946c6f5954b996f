"""The X-HALE lab GVT (measured, shipped: fg.data.load("xhale_lab_gvt")): update the X-HALE-like model on
both suspension layouts at once (the original work's 30 variables, and by default the five pods'
masses as three more, the published gross mass held by a mass residual), then predict the
free-flying modes with the suspension removed and on the 20 m bungees of the free-flying test, each
with its 95 % confidence interval, and list every mode of each predicted configuration.

    python examples/xhale_lab/run.py --out xhale-lab --json xhale-lab.json [--data my_table.json]
                                     [--variables original]

The pods' masses were not published (the model's split, 3.40 kg at the centre and 0.89 kg at each
other junction, is an assumption tuned to the original work's initial model); only the gross mass
(11.35 kg) was. `--variables original` updates on the original work's 30 variables alone.

The measured tables hold frequencies only (no shapes): modes are paired by frequency at the
initial model and followed by MAC between design points. The table compares each configuration
with the original work's initial and updated Nastran models. The project written to --out reads
the measured table from its own copy there (xhale_lab_gvt.json), so `flexgvt run` reruns it.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

import flexgvt as fg
from flexgvt.errors import FileFormatError, FlexGVTError
from flexgvt.workflow import example_project, load_project, run
from flexgvt.workflow.template import variable_blocks


def measured_tables(path: Path | None) -> dict:
    """The measured table: the shipped one, or ``path`` in its form ('labels', and per layout
    'outboard' and 'inboard' the lists 'measured_hz', 'original_initial_fem_hz' and
    'original_updated_fem_hz' [Hz], all of the labels' length)."""
    if path is None:
        return fg.data.load("xhale_lab_gvt")
    lab = fg.data.read(path)
    labels = lab.get("labels")
    if not isinstance(labels, list) or not labels or not all(isinstance(s, str) for s in labels):
        raise FileFormatError(f"{path}: 'labels' must be a list of mode labels (the form of "
                              "fg.data.load('xhale_lab_gvt'))")
    for c in ("outboard", "inboard"):
        entry = lab.get(c) if isinstance(lab.get(c), dict) else {}
        for k in ("measured_hz", "original_initial_fem_hz", "original_updated_fem_hz"):
            v = entry.get(k)
            if not (_frequencies(v) and len(v) == len(labels)):
                raise FileFormatError(f"{path}: '{c}' must hold '{k}', {len(labels)} positive frequencies [Hz] "
                                      "(one per label; the form of fg.data.load('xhale_lab_gvt'))")
    return lab


# The pods' masses (their split of the gross mass was not published): centre, inner pair, outer pair
POD_VARIABLES = [("pod_centre", "mass", ["pod_+0"], "mass", (0.5, 1.5)),
                 ("pods_inner", "mass", ["pod_-1", "pod_+1"], "mass", (0.5, 1.5)),
                 ("pods_outer", "mass", ["pod_-2", "pod_+2"], "mass", (0.5, 1.5))]


def with_pod_masses(text: str) -> str:
    """The project text with the pods' masses as three design variables (centre, inner pair, outer
    pair) and the published gross mass as a residual."""
    mass = '# [objective.measured_mass]\n# mass = "11.35 kg"'
    if mass not in text or "\n[optimiser]" not in text:
        raise FlexGVTError("the project template changed: examples/xhale_lab/run.py cannot add the pods' masses")
    text = text.replace(mass, '[objective.measured_mass]\nmass = "11.35 kg"  # the published gross mass', 1)
    pods = "# The pods' masses (their split of the gross mass was not published)\n" + variable_blocks(POD_VARIABLES)
    return text.replace("\n[optimiser]", "\n" + pods + "[optimiser]", 1)


def _property(text: str) -> tuple[str, float | list[float]]:
    """NAME=VALUE of --property: a number, or numbers separated by commas."""
    name, sep, value = text.partition("=")
    try:
        numbers = [float(v) for v in value.split(",")]
    except ValueError:
        numbers = []
    if not sep or not name.strip() or not numbers:
        raise argparse.ArgumentTypeError(f"--property {text!r}: give NAME=VALUE, VALUE a number or numbers separated "
                                         "by commas (e.g. pendulum_length=6)")
    return name.strip(), numbers[0] if len(numbers) == 1 else numbers


def _frequencies(values) -> bool:
    """A non-empty list of finite positive numbers."""
    return isinstance(values, list) and len(values) > 0 and all(
        isinstance(f, (int, float)) and not isinstance(f, bool) and math.isfinite(f) and f > 0 for f in values)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("xhale-lab-output"), help="folder for the project and results")
    parser.add_argument("--json", type=Path, default=None, help="write the tables as JSON")
    parser.add_argument("--data", type=Path, default=None,
                        help="measured table (.json, the form of the shipped one; "
                             "default: fg.data.load('xhale_lab_gvt'))")
    parser.add_argument("--variables", choices=("pods", "original"), default="pods",
                        help="the original work's 30 variables, plus (pods, the default) the pods' masses")
    parser.add_argument("--property", action="append", default=[], metavar="NAME=VALUE", type=_property,
                        help="change a chosen dimension of the case that was not published (repeatable; "
                             "fg.cases.xhale's properties, e.g. pendulum_length=6 for the lab lines' string below "
                             "the pulley [m], joiner_half=0.06 [m], pod_offset_z=-0.1 [m]; a list as 0.01,0.002,0.006)")
    parser.add_argument("--no-report", action="store_true", help="skip the HTML report")
    args = parser.parse_args(argv)

    lab = measured_tables(args.data)
    labels = lab["labels"]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "xhale_lab_gvt.json").write_text(json.dumps(lab, indent=1))
    options = {"properties": dict(args.property)} if args.property else {}
    text = example_project("xhale", name="X-HALE lab GVT (measured), both layouts at once",
                           modes={c: ("xhale_lab_gvt.json", f"{c}", labels) for c in ("outboard", "inboard")},
                           options=options)
    # The free-flying test's bungees twice: massless, and with their own mass distributed (the
    # case's *_heavy configurations: their surge and string modes in the solve).
    heavy = '"bungee_outboard", "bungee_inboard"'
    if heavy in text:
        text = text.replace(heavy, heavy + ', "bungee_outboard_heavy", "bungee_inboard_heavy"', 1)
    if args.variables == "pods":
        text = with_pod_masses(text)
    (args.out / "project.toml").write_text(text)
    project = load_project(args.out / "project.toml")
    res = run(project, progress=print)
    if not args.no_report:
        fg.report.write_project_report(res)

    rows = {}
    print(f"\n{'configuration':<10} {'mode':<10} {'measured':>8} {'orig. init':>10} {'orig. upd':>9} "
          f"{'flexgvt init':>12} {'flexgvt upd':>11}   [Hz]")
    for c in ("outboard", "inboard"):
        table = res.update.tables[c]
        rows[c] = []
        for k, r in enumerate(table):
            row = {"label": labels[k], "measured_hz": r["measured_hz"],
                   "original_initial_hz": lab[c]["original_initial_fem_hz"][k],
                   "original_updated_hz": lab[c]["original_updated_fem_hz"][k],
                   "initial_hz": r["initial_hz"], "updated_hz": r["updated_hz"]}
            rows[c].append(row)
            print(f"{c:<10} {labels[k]:<10} {row['measured_hz']:8.2f} {row['original_initial_hz']:10.2f} "
                  f"{row['original_updated_hz']:9.2f} {row['initial_hz']:12.3f} {row['updated_hz']:11.3f}")
    summary = {}
    for c, rr in rows.items():
        m = np.array([r["measured_hz"] for r in rr])
        err = lambda key: float(np.sqrt(np.mean((np.array([r[key] for r in rr]) / m - 1) ** 2)) * 100)  # noqa: E731
        summary[c] = {k: err(k) for k in ("original_initial_hz", "original_updated_hz", "initial_hz", "updated_hz")}
    print("\nrms frequency error against the measured modes [%]")
    for c, s in summary.items():
        print(f"  {c}: original work initial {s['original_initial_hz']:.2f}, updated {s['original_updated_hz']:.2f}; "
              f"flexgvt initial {s['initial_hz']:.2f}, updated {s['updated_hz']:.2f}")
    mass = {}
    a, b = res.update.initial.mass_properties, res.update.final.mass_properties
    if a is not None and b is not None:
        mass = {"initial_kg": float(a.mass), "updated_kg": float(b.mass), "published_kg": 11.35}
        pods = {v["name"]: v["final"] for v in res.update.variables if v["kind"] == "mass"}
        print(f"\ngross mass: published 11.35 kg, initial model {a.mass:.3f} kg, updated {b.mass:.3f} kg"
              + ("; pods " + ", ".join(f"{k} {v:.3f} kg" for k, v in pods.items()) if pods else ""))
    prediction = res.predictions["updated"]
    pred = prediction.rows
    keys = [k[:-3] for k in pred[0] if k.endswith("_hz") and not k.endswith(("_low_hz", "_high_hz"))
            and k != "free_hz"]
    bounds = prediction.uncertainty
    if bounds and "failed" in bounds:
        print(f"\nconfidence bounds not computed: {bounds['failed']}")
        bounds = None
    level = f"{100 * bounds['confidence']:g} %" if bounds else ""
    print("\nfree-flying prediction (updated model) [Hz]: free-free, then each layout's mode paired by MAC"
          + (f"; [low, high]: {level} interval ({bounds['method']}, sigma from {bounds['sigma_source']})"
             if bounds else ""))

    def cell(r: dict, key: str, width: int) -> str:
        f = r.get(f"{key}_hz")
        if f is None:
            return " " * width
        lo, hi = r.get(f"{key}_low_hz"), r.get(f"{key}_high_hz")
        text = f"{f:.3f}" + ("" if lo is None or hi is None else f" [{lo:.3f}, {hi:.3f}]")
        return f"{text:>{width}}"

    w = 23 if bounds else 9
    print(f"{'mode':<10} {'free-free':>{w}} " + " ".join(f"{k:>{w}}" for k in keys))
    for r in pred:
        print(f"{r['label']:<10} {cell(r, 'free', w)} " + " ".join(cell(r, k, w) for k in keys))
    print("\nevery mode of each predicted configuration (free-free partner by mass-weighted MAC; '-': none; "
          "'bungee surge' / 'bungee string': the heavy bungees' own modes)")
    for name, modes in prediction.modes.items():
        print(f"  {name}:")
        for m in modes:
            if m["suspension"] and "bungee" not in m["label"]:  # rigid/pendulum modes left out; a cord's own kept
                continue
            iv = "" if m.get("low_hz") is None else f" [{m['low_hz']:.3f}, {m['high_hz']:.3f}]"
            partner = "-" if m["free_mode"] is None else f"{m['free_label']} (MAC {m['mac']:.3f})"
            print(f"    {m['label']:<10} {m['frequency_hz']:8.3f}{iv:<20}  free-free: {partner}")
    out = {"configurations": rows, "rms_error_percent": summary, "gross_mass": mass, "prediction": pred,
           "prediction_modes": prediction.modes, "prediction_uncertainty": prediction.uncertainty,
           "variables": res.update.variables, "timings_s": res.timings, "files": res.files}
    if args.json is not None:
        args.json.write_text(json.dumps(out, indent=1, default=float))
    return out


if __name__ == "__main__":
    try:
        main()
    except FlexGVTError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
