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
    def verify(case: str = typer.Argument("cantilever", help="cantilever or wingbox (docs/method.md section 5 "
                                          "cases 3 and 4)"),
               seed: int = typer.Option(1, help="seed of the +-5 % mistuning"),
               method: str = typer.Option("least_squares", help="least_squares, trf, lm, slsqp, trust-constr or "
                                          "nelder-mead"),
               modes: int = typer.Option(8, help="measured modes per configuration"),
               element_size: float = typer.Option(0.2, help="the wingbox's mesh size [m]"),
               out: Optional[Path] = typer.Option(None, help="folder for verification.json and the MAC figure"),
               json_path: Optional[Path] = typer.Option(None, "--json", help="write the figures as JSON")):
        """Mistune a reference model (seeded), update it against its own surrogate data in three load
        cases, and report variable and frequency errors and an unseen load case's prediction."""
        from ..updating import verify as run

        try:
            result = run(case, seed=seed, n_modes=modes, method=method, element_size=element_size)
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
        for name, rows in result.multi.tables.items():
            cells = [[str(r["mode"]), r["label"], f"{r['measured_hz']:.4f}", f"{r['initial_hz']:.4f}",
                      f"{r['initial_error_percent']:+.3f}", f"{r['updated_hz']:.4f}",
                      f"{r['updated_error_percent']:+.4f}", f"{r['updated_mac']:.4f}" if r["updated_mac"] else ""]
                     for r in rows]
            print_table(console, f"'{name}': frequencies [Hz] and errors [%]",
                        ["mode", "label", "reference [Hz]", "initial [Hz]", "error [%]", "updated [Hz]", "error [%]",
                         "MAC"], cells, key=2, justify=["right", "left"] + ["right"] * 6)
        data = result.to_dict()
        if out is not None:
            out.mkdir(parents=True, exist_ok=True)
            (out / "verification.json").write_text(json.dumps(data, indent=1))
            _mac_figure(result, out / "mac.png")
            console.print(f"files in {out}/", markup=False, highlight=False)
        if json_path is not None:
            json_path.parent.mkdir(parents=True, exist_ok=True)
            json_path.write_text(json.dumps(data, indent=1))


def _mac_figure(result, path: Path) -> None:
    from ..report.plots import verification_mac

    verification_mac(result).savefig(path, dpi=120)
