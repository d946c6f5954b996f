"""`flexgvt ema identify FILE.uff`: PolyMAX on the file's FRFs, modes to UFF 55 and a table, figures."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from ..errors import FlexGVTError

app = typer.Typer(add_completion=False, no_args_is_help=True, help="Experimental modal analysis.")
console = Console()


@app.command()
def identify(path: Path = typer.Argument(..., help="UFF file with FRFs (dataset 58, function type 4)"),
             band: Optional[list[float]] = typer.Option(None, "--band", help="fit band: --band F_MIN --band F_MAX [Hz]"),
             max_order: int = typer.Option(40, help="highest model order of the stabilisation diagram (as fg.ema.polymax)"),
             poles: Optional[str] = typer.Option(None, help="pick poles by hand: comma-separated frequencies [Hz]"),
             wide: bool = typer.Option(False, "--wide", help="fit band by band (modes over decades of frequency, "
                                       "e.g. 0.2 Hz suspension modes with 100 Hz elastic modes)"),
             out: Path = typer.Option(Path("ema-output"), help="folder for modes.uff, modes.csv and figures"),
             json_path: Optional[Path] = typer.Option(None, "--json", help="write the modes as JSON")):
    """Identify modes with PolyMAX + LSFD and write them as UFF 55, CSV and figures."""
    from ..io.uff import ModalResults, read_uff, shapes_at_points, write_uff
    from ..ema import identify_wide_band, plots, polymax

    try:
        data = read_uff(path)
        frfs = data.frfs
        if band and len(band) != 2:
            raise FlexGVTError("--band takes two values: --band F_MIN --band F_MAX")
        fit_band = tuple(band) if band else None
        if wide and poles:
            raise FlexGVTError("--poles picks from one stabilisation diagram; use it without --wide (on a band)")
        if wide:
            stab, modes = None, identify_wide_band(frfs, frequency_band=fit_band, max_order=max_order)
        else:
            stab = polymax(frfs, max_order=max_order, frequency_band=fit_band)
            modes = stab.select(frequencies_hz=[float(v) for v in poles.split(",")] if poles else None)
        out.mkdir(parents=True, exist_ok=True)
        table = Table(title=f"{path.name}: identified modes")
        for col in ("mode", "f [Hz]", "zeta [%]"):
            table.add_column(col, justify="right")
        lines = ["mode,frequency_hz,damping_ratio"]
        for k, (f, z) in enumerate(zip(modes.frequencies_hz, modes.damping_ratio)):
            table.add_row(str(k + 1), f"{f:.4f}", f"{100 * z:.2f}")
            lines.append(f"{k + 1},{f:.8g},{z:.8g}")
        console.print(table)
        (out / "modes.csv").write_text("\n".join(lines) + "\n")
        points, shapes = shapes_at_points(np.real(modes.shapes), frfs.outputs)
        write_uff(out / "modes.uff", modes=ModalResults(modes.frequencies_hz, modes.damping_ratio, shapes, points))
        figs = {"cmif.png": plots.cmif_plot(frfs.frequencies_hz, frfs.H, modes),
                "frf_fit.png": plots.frf_fit(frfs.frequencies_hz, frfs.H, modes, 0)}
        if stab is not None:  # one diagram per sub-band with --wide: not drawn
            figs["stabilisation.png"] = plots.stabilisation_diagram(stab, modes)
        for name, fig in figs.items():
            fig.savefig(out / name, dpi=120)
        if json_path is not None:
            json_path.write_text(json.dumps({"file": str(path), "frequencies_hz": modes.frequencies_hz.tolist(),
                                             "damping_ratio": modes.damping_ratio.tolist()}, indent=2))
        console.print(f"modes written to {out / 'modes.uff'} and {out / 'modes.csv'}; figures in {out}/")
    except FlexGVTError as exc:
        console.print(f"[bold red]error:[/] {exc}")
        raise typer.Exit(code=2)
