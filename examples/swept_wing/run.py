"""The 3D-printed swept wing (A3TB-WT, published: fg.data.load("a3tb_wt")): staged updating of the
A3TB-WT-like model fg.cases.swept_wing().

    python examples/swept_wing/run.py --out swept-wing --json swept-wing.json [--small]

Stage 0, the component tests (parts weighed, the spar's tip-load test), is the case's fixed input
(Table 5.7's initial values). Then the root spring's in-plane bending component M_z is set on the
laboratory GVT's first in-plane mode (Table 5.2, 7.10 Hz), as the original work's Section 5.4.2 set
Table 5.7's initial M_z (its 5000 N m/rad is that adjustment on the original's model). Stage 1
updates all 15 variables of Table 5.7, within its bounds about those values, on the shaker-table
GVT (Table 5.8); stage 2 starts from stage 1's model and updates only the six root-spring
components on the GVT of the wind-tunnel installation (Table 5.9). The tables hold
frequencies and labels only (no shapes): modes pair by label family and frequency. Each stage is
one function taking the model the previous stage produced and returning its UpdateResult (whose
.model is the next stage's start). The full run takes the best of four starts (x0 and three
seeded points in the bounds); --small: a coarser mesh, 10 iterations, one start (for the tests);
--stick: the stick model on the spar line (part_offsets=False), the earlier results;
--no-adjustment: Table 5.7's M_z itself as stage 1's centre (the earlier results).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import flexgvt as fg
from flexgvt.cases.swept_wing import swept_wing
from flexgvt.errors import FlexGVTError


def measured(stage: dict) -> fg.updating.Measured:
    """A stage's GVT (case.references['stages'][k]: frequencies and pairing labels) as Measured data."""
    return fg.updating.Measured(stage["configuration"], frequencies_hz=stage["measured_hz"],
                                labels=tuple(stage["labels"]))


def stage_variables(case: fg.cases.Case, stage: dict) -> list:
    """The case's design variables a stage names, with the stage's bounds."""
    rows = {r[0]: r for r in case.references["design_variables"]}
    makers = {"beam": fg.updating.beam, "spring": fg.updating.spring}
    out = []
    for n in stage["variables"]:
        name, kind, targets, attribute, _ = rows[n]
        out.append(makers[kind](name, targets, attribute, tuple(stage["bounds"][n])))
    return out


def run_stage(case: fg.cases.Case, model: fg.Model, stage: dict, **settings) -> fg.updating.UpdateResult:
    """One updating stage of case.references['stages'] (plain data: configuration, measured
    frequencies and labels, variables, bounds, unidentifiable) from ``model``; returns the
    UpdateResult, whose .model starts the next stage."""
    if "unidentifiable" in stage:
        settings = {**settings, "unidentifiable": stage["unidentifiable"]}
    return fg.updating.update(model, [case.configurations[stage["configuration"]]], [measured(stage)],
                              stage_variables(case, stage), **settings)


def _stage(case: fg.cases.Case, name: str) -> dict:
    return next(s for s in case.references["stages"] if s["name"] == name)


def stage_root_adjustment(case, model, **settings):
    """Before stage 1: the root spring's M_z alone on the laboratory GVT's first in-plane mode
    (Table 5.2, 7.10 Hz), the original work's Section 5.4.2 adjustment."""
    return run_stage(case, model, _stage(case, "root_spring_adjustment"), **settings)


def stage_shaker_table(case, model, **settings):
    """Stage 1: all 15 variables, Table 5.7's bounds, the shaker-table GVT (Table 5.8)."""
    return run_stage(case, model, _stage(case, "shaker_table"), **settings)


def stage_wind_tunnel(case, model, **settings):
    """Stage 2: the root spring's six components only, from stage 1's model, the wind-tunnel GVT
    (Table 5.9); the components the data do not constrain (the four rigid ones) held at stage 1's."""
    return run_stage(case, model, _stage(case, "wind_tunnel"), **settings)


def frequency_rows(result, table: dict) -> list[dict]:
    rows = []
    for r, lab, m, oi, ou in zip(result.tables[next(iter(result.tables))], table["labels"], table["measured_hz"],
                                 table["original_initial_hz"], table["original_updated_hz"]):
        rows.append({"label": lab, "measured_hz": m, "original_initial_hz": oi, "original_updated_hz": ou,
                     "original_updated_error_percent": 100 * (ou - m) / m,
                     "initial_hz": r["initial_hz"], "initial_error_percent": r["initial_error_percent"],
                     "updated_hz": r["updated_hz"], "updated_error_percent": r["updated_error_percent"],
                     "model_label": None if r["updated_mode"] is None else
                     result.final.configurations[next(iter(result.tables))].labels[r["updated_mode"] - 1]})
    return rows


def variable_rows(result, case) -> list[dict]:
    pub = case.references["published"]["variables"]
    out = []
    for r in result.variables:
        p = pub[r["name"]]
        out.append({"name": r["name"], "table_row": p["table_row"], "lower": r["lower"], "upper": r["upper"],
                    "original_initial": p["initial"], "original_final": p["final"],
                    "original_change_percent": 100 * (p["final"] - p["initial"]) / p["initial"],
                    "initial": r["initial"], "final": r["final"], "change_percent": r["change_percent"],
                    "at_bound": r["at_bound"], "identifiable": r["identifiable"], "held": bool(r.get("fixed")),
                    "reason": r["reason"]})
    return out


def _print_frequencies(title: str, rows: list[dict]) -> None:
    print(f"\n{title} [Hz; errors in % of the measured]")
    print(f"{'mode':<7} {'GVT':>6} {'orig. init':>10} {'orig. upd':>14} {'flexgvt init':>16} {'flexgvt upd':>16}"
          "  model mode")
    for r in rows:
        def cell(f, e):
            return f"{'-':>16}" if f is None else f"{f:8.3f} ({e:+5.1f})"
        print(f"{r['label']:<7} {r['measured_hz']:6.2f} {r['original_initial_hz']:10.2f} "
              f"{r['original_updated_hz']:6.2f} ({r['original_updated_error_percent']:+5.1f}) "
              f"{cell(r['initial_hz'], r['initial_error_percent'])} {cell(r['updated_hz'], r['updated_error_percent'])}"
              f"  {r['model_label'] or '-'}")


def _print_variables(title: str, rows: list[dict]) -> None:
    print(f"\n{title}")
    print(f"{'variable':<13} {'bounds':>12} {'orig. init':>11} {'orig. final':>11} {'(%)':>7} {'flexgvt init':>12} "
          f"{'flexgvt final':>13} {'(%)':>7}  note")
    for r in rows:
        note = "held (not identifiable)" if r["held"] else ", ".join(
            w for w, on in (("at bound", r["at_bound"]), ("not identifiable", not r["identifiable"])) if on)
        print(f"{r['name']:<13} {r['lower']:5.2f}-{r['upper']:<5.2f} {r['original_initial']:11.4g} "
              f"{r['original_final']:11.4g} {r['original_change_percent']:+7.1f} {r['initial']:12.4g} "
              f"{r['final']:13.4g} {r['change_percent']:+7.1f}  {note}")


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("swept-wing-output"), help="folder for the results")
    parser.add_argument("--json", type=Path, default=None, help="write the tables as JSON")
    parser.add_argument("--unidentifiable", choices=("free", "fix"), default="free",
                        help="variables the data do not constrain: left free within their bounds (default, as the "
                             "original work) or held at their initial values (flexgvt's default)")
    parser.add_argument("--small", action="store_true", help="coarse mesh, fewer iterations (tests)")
    parser.add_argument("--no-adjustment", action="store_true",
                        help="start stage 1 from Table 5.7's M_z (5000 N m/rad) instead of setting it on the "
                             "laboratory GVT's first in-plane mode first (Section 5.4.2), as before")
    parser.add_argument("--stick", action="store_true",
                        help="the stick model on the spar line (part_offsets=False: every part's section about the "
                             "spar, no chordwise offsets), as before the part offsets")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    case = swept_wing(n_wing=10 if args.small else 20, part_offsets=not args.stick)
    settings = dict(n_modes=14, max_iterations=10 if args.small else 100, starts=1 if args.small else 4,
                    unidentifiable=args.unidentifiable)
    pub = case.references["published"]

    print("stage 0 (component tests, fixed inputs):",
          ", ".join(f"{k} {v:.4g}" for k, v in case.references["stage0"].items()))
    adjustment, start = None, case.model
    if not args.no_adjustment:
        adjustment = stage_root_adjustment(case, case.model, n_modes=settings["n_modes"], max_iterations=50)
        start = adjustment.model
        row, var = adjustment.tables[next(iter(adjustment.tables))][0], adjustment.variables[0]
        print(f"root-spring adjustment (Section 5.4.2) on the laboratory GVT's IP 1 (Table 5.2, "
              f"{row['measured_hz']:.2f} Hz): M_z {var['initial']:.4g} -> {var['final']:.4g} N m/rad "
              f"({var['change_percent']:+.1f} %), IP 1 {row['initial_hz']:.3f} -> {row['updated_hz']:.3f} Hz")
    stage1 = stage_shaker_table(case, start, **settings)
    rows1 = frequency_rows(stage1, pub["shaker_table"])
    vars1 = variable_rows(stage1, case)
    _print_frequencies("stage 1: shaker-table GVT (Table 5.8), 15 variables", rows1)
    _print_variables("stage 1 variables beside Table 5.7", vars1)
    stage2 = stage_wind_tunnel(case, stage1.model, **settings)
    rows2 = frequency_rows(stage2, pub["wind_tunnel"])
    vars2 = [{"name": r["name"], "lower": r["lower"], "upper": r["upper"], "stage1": r["initial"],
              "final": r["final"], "change_percent": r["change_percent"], "at_bound": r["at_bound"],
              "held": bool(r.get("fixed")), "reason": r["reason"]} for r in stage2.variables]
    _print_frequencies("stage 2: wind-tunnel GVT (Table 5.9), root spring only, from stage 1", rows2)
    print("\nstage 2 root spring (the original work's values after this stage were not published)")
    for r in vars2:
        print(f"  {r['name']:<4} {r['stage1']:11.4g} -> {r['final']:11.4g} ({r['change_percent']:+.1f} %)"
              f"{'  held (not identifiable)' if r['held'] else ('  at bound' if r['at_bound'] else '')}")

    def worst(rows, n, key="updated_error_percent"):
        e = [abs(r[key]) for r in rows[:n] if r[key] is not None]
        return max(e) if len(e) == n else None
    orig = "original_updated_error_percent"
    summary = {"shaker_table": {"worst_first3_percent": worst(rows1, 3), "worst_first5_percent": worst(rows1, 5),
                                "original_worst_first3_percent": worst(rows1, 3, orig),
                                "original_worst_first5_percent": worst(rows1, 5, orig),
                                "target": "< 0.5 % on the first three modes, < 2 % on five (the original work's)"},
               "wind_tunnel": {"worst_first5_percent": worst(rows2, 5),
                               "original_worst_first5_percent": worst(rows2, 5, orig),
                               "target": "within 1 % (the original work's final errors)"}}
    s1, s2 = summary["shaker_table"], summary["wind_tunnel"]
    print(f"\nworst |error| [%]: stage 1 first three {s1['worst_first3_percent']:.2f}, first five "
          f"{s1['worst_first5_percent']:.2f}; stage 2 first five {s2['worst_first5_percent']:.2f}")
    out = {"stage0": case.references["stage0"],
           "stages": {**({} if adjustment is None else {"root_spring_adjustment": {
               "frequencies": adjustment.tables[next(iter(adjustment.tables))], "variables": adjustment.variables,
               "message": adjustment.message, "warnings": adjustment.warnings, "seconds": adjustment.seconds}}),
                      "shaker_table": {"frequencies": rows1, "variables": vars1, "message": stage1.message,
                                       "warnings": stage1.warnings, "seconds": stage1.seconds},
                      "wind_tunnel": {"frequencies": rows2, "variables": vars2, "message": stage2.message,
                                      "warnings": stage2.warnings, "seconds": stage2.seconds}},
           "summary": summary}
    text = json.dumps(out, indent=1, default=float)
    (args.out / "swept_wing.json").write_text(text)
    if args.json is not None:
        args.json.write_text(text)
    return out


if __name__ == "__main__":
    try:
        main()
    except FlexGVTError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
