"""`flexgvt verify CASE`: the updating verification protocol of docs/method.md section 4."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console

from ..errors import FlexGVTError
from .tables import print_table


def register(app: typer.Typer, console: Console) -> None:
    @app.command()
    def verify(case: str = typer.Argument("cantilever", help="cantilever, wingbox or wingbox_local (docs/method.md "
                                          "section 5 cases 3 and 4; wingbox_local: one root bay's bottom skin 20 % "
                                          "thinner in the reference)"),
               seed: int = typer.Option(1, help="seed of the +-5 % mistuning"),
               method: str = typer.Option("least_squares", help="least_squares, trf, lm, slsqp, trust-constr or "
                                          "nelder-mead"),
               modes: int = typer.Option(8, help="measured modes per configuration"),
               element_size: float = typer.Option(0.2, help="the wingbox's mesh size [m] (0.25: the coarsest on which "
                                                  "the loaded skins buckle, two elements per rib bay)"),
               tolerance: Optional[float] = typer.Option(None, help="the optimiser's stopping tolerance on cost, "
                                                         "step and gradient (default 1e-10; the wingbox's test and "
                                                         "bench stop at 1e-3: docs/updating.md)"),
               out: Optional[Path] = typer.Option(None, help="folder for verification.json, the tables "
                                        "(frequencies.csv, variables.csv, static.csv, onsets.csv) and figures "
                                        "(errors.png, mac.png)"),
               json_path: Optional[Path] = typer.Option(None, "--json", help="write the figures as JSON")):
        """Mistune a reference model (seeded), update it against its own surrogate data in three load
        cases, and report variable and frequency errors and an unseen load case's prediction."""
        from ..updating import verify as run

        try:
            result = run(case, seed=seed, n_modes=modes, method=method, element_size=element_size, tolerance=tolerance)
        except FlexGVTError as exc:
            from rich.markup import escape
            console.print(f"[bold red]error:[/] {escape(str(exc))}", soft_wrap=True)
            raise typer.Exit(code=2) from None
        console.print(result.summary(), markup=False, highlight=False)
        e = result.variable_errors_percent
        cells = [[row["name"], f"{e['initial'][k]:+.3f}", f"{e['multi'][k]:+.4f}", f"{e['single'][k]:+.3f}",
                  f"{100 * row['std_normalised']:.2g}" if np.isfinite(row["std_normalised"]) else "unseen"]
                 for k, row in enumerate(result.multi.variables)]
        print_table(console, "design variables: error against the reference [%]",
                    ["variable", "initial [%]", "multi-configuration [%]", "single-configuration [%]",
                     "std (multi) [%]"], cells, justify=["left"] + ["right"] * 4)
        for name, row in result.configurations.items():
            seen = ("unseen by both models" if row["unseen"] else "seen by both models" if "single" in row["seen_by"]
                    else "seen by the multi-configuration model only")
            cells = [[str(m + 1), row["labels"][m] if m < len(row["labels"]) else "", f"{f:.4f}",
                      *[_pct(row[f"{k}_error_percent"][m]) for k in ("initial", "multi", "single")]]
                     for m, f in enumerate(row["reference_hz"])]
            print_table(console, f"'{name}' ({seen}): reference frequencies [Hz] and the models' errors [%]",
                        ["mode", "label", "reference [Hz]", "initial [%]", "multi-configuration [%]",
                         "single-configuration [%]"], cells, key=2, justify=["right", "left"] + ["right"] * 4)
        cells = [[name, r["node"], ("x", "y", "z", "rx", "ry", "rz")[r["component"] - 1], f"{r['reference']:.5g}",
                  *[f"{r[f'{k}_error_percent']:+.3g}" for k in ("initial", "multi", "single")]]
                 for name, row in result.configurations.items() for r in row.get("static", [])]
        if cells:
            print_table(console, "static deflections: the reference's [m or rad] and the models' errors [%] "
                        f"(the unseen '{result.prediction['configuration']}' is a prediction)",
                        ["configuration", "node", "component", "reference", "initial [%]", "multi-configuration [%]",
                         "single-configuration [%]"], cells, justify=["left", "right", "left"] + ["right"] * 4)
        if result.onsets:
            cells = [[name, *(_onset_cells(o) if o is not None else ["none found"] + [""] * 4)]
                     for name, o in result.onsets.items()]
            print_table(console, "buckling onset along the reference's load path (the groups its shape deforms most, "
                        "where, and the imperfection that took the path onto its post-buckled branch)",
                        ["configuration", "load factor", "[g]", "groups", "where", "imperfection"], cells,
                        justify=["left", "right", "right", "left", "left", "left"])
        if any("LOCAL" in lab for row in result.configurations.values() for lab in row["labels"]):
            console.print("LOCAL: a mode whose energy is mostly local (panel) deformation of the cross-sections "
                          "(a skin bay's own bending), not global bending (OOP, IP) or torsion (T); a second class "
                          "after a slash holds over 30 % of the energy", markup=False,
                          highlight=False)
        data = result.to_dict()
        if out is not None:
            out.mkdir(parents=True, exist_ok=True)
            (out / "verification.json").write_text(json.dumps(data, indent=1))
            _figures(result, out)
            console.print(f"files in {out}/", markup=False, highlight=False)
        if json_path is not None:
            json_path.parent.mkdir(parents=True, exist_ok=True)
            json_path.write_text(json.dumps(data, indent=1))


def _onset_cells(o) -> list[str]:
    path = (f"{1e3 * o.imperfection:.2g} mm" if o.continued else "none (left by itself)" if o.recovered
            else "none (not continued)")
    return [f"{o.load_factor:.4f}", "" if o.g is None else f"{o.g:.3f}", ", ".join(o.groups),
            o.location(), path]


def _pct(value: float) -> str:
    return "no partner" if not np.isfinite(value) else f"{value:+.4f}"


def _figures(result, out: Path) -> None:
    """mac.png (MAC after multi-configuration updating), errors.png (frequency errors of the three
    models in every configuration and the variables' errors) and the tables as CSV (frequencies,
    variables, static deflections, the reference's buckling onsets)."""
    import csv

    from ..report.plots import verification_errors, verification_mac

    verification_mac(result).savefig(out / "mac.png", dpi=120)
    verification_errors(result).savefig(out / "errors.png", dpi=120)
    with open(out / "frequencies.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["configuration", "unseen", "seen_by", "mode", "label", "reference_hz", "initial_hz", "multi_hz",
                    "single_hz", "initial_error_percent", "multi_error_percent", "single_error_percent"])
        for name, row in result.configurations.items():
            for m, f in enumerate(row["reference_hz"]):
                w.writerow([name, row["unseen"], " ".join(row["seen_by"]), m + 1, row["labels"][m], f"{f:.9g}",
                            *[f"{row[f'{k}_hz'][m]:.9g}" for k in ("initial", "multi", "single")],
                            *[f"{row[f'{k}_error_percent'][m]:.6g}" for k in ("initial", "multi", "single")]])
    with open(out / "variables.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        e = result.variable_errors_percent
        w.writerow(["variable", "initial_error_percent", "multi_error_percent", "single_error_percent"])
        for k, name in enumerate(result.names):
            w.writerow([name, *[f"{e[key][k]:.6g}" for key in ("initial", "multi", "single")]])
    with open(out / "static.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["configuration", "unseen", "node", "component", "reference", "initial", "multi", "single",
                    "initial_error_percent", "multi_error_percent", "single_error_percent"])
        for name, row in result.configurations.items():
            for r in row.get("static", []):
                w.writerow([name, row["unseen"], r["node"], r["component"], f"{r['reference']:.9g}",
                            *[f"{r[k]:.9g}" for k in ("initial", "multi", "single")],
                            *[f"{r[f'{k}_error_percent']:.6g}" for k in ("initial", "multi", "single")]])
    with open(out / "onsets.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["configuration", "buckled", "load_factor", "g", "bracket_low", "bracket_high", "groups", "bays",
                    "y_min_m", "y_max_m", "continued", "imperfection_m", "recovered"])
        for name, o in result.onsets.items():
            if o is None:
                w.writerow([name, False] + [""] * 11)
                continue
            w.writerow([name, True, f"{o.load_factor:.6g}", "" if o.g is None else f"{o.g:.6g}", f"{o.bracket[0]:.6g}",
                        f"{o.bracket[1]:.6g}", " ".join(o.groups), " ".join(str(b) for b in o.bays),
                        f"{o.span[0]:.6g}", f"{o.span[1]:.6g}", o.continued, f"{o.imperfection:.6g}", o.recovered])
