"""`flexgvt ema identify FILE.uff [MORE.uff ...]`: PolyMAX (+ maximum-likelihood refinement) on the files'
FRFs, modes with standard deviations to UFF 55, CSV, JSON and a table, figures; several files averaged."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from ..errors import FlexGVTError
from .workflow import fail

app = typer.Typer(add_completion=False, no_args_is_help=True, help="Experimental modal analysis.")
console = Console()


def _identify_one(path, fit_band, max_order, poles, wide, refine):
    from ..ema import identify_wide_band, polymax
    from ..ema import refine as ml_refine
    from ..io.uff import read_uff

    frfs = read_uff(path).frfs
    if wide:
        modes = identify_wide_band(frfs, frequency_band=fit_band, max_order=max_order)
        if refine:
            modes = ml_refine(frfs, modes, frequency_band=fit_band)
        return frfs, None, modes
    stab = polymax(frfs, max_order=max_order, frequency_band=fit_band)
    if refine and not poles:
        from ..ema import select_ml

        modes = select_ml(stab)
        return frfs, (stab, modes.info["kept"]), modes
    modes = stab.select(frequencies_hz=[float(v) for v in poles.split(",")] if poles else None, refine=refine)
    return frfs, (stab, None), modes


def _fmt_std(v, fmt):
    return "-" if v is None or not np.isfinite(v) else fmt.format(v)


@app.command()
def identify(paths: list[Path] = typer.Argument(..., help="UFF file(s) with FRFs (dataset 58, function type 4); "
                                                "several files = repeated tests of one configuration, averaged"),
             band: Optional[list[float]] = typer.Option(None, "--band",
                                                        help="fit band: --band F_MIN --band F_MAX [Hz]"),
             max_order: int = typer.Option(40,
                                           help="highest model order of the stabilisation diagram (as fg.ema.polymax)"),
             poles: Optional[str] = typer.Option(None, help="pick poles by hand: comma-separated frequencies [Hz]"),
             wide: bool = typer.Option(False, "--wide", help="fit band by band (modes over decades of frequency, "
                                       "e.g. 0.2 Hz suspension modes with 100 Hz elastic modes)"),
             refine: bool = typer.Option(True, "--refine/--no-refine", help="maximum-likelihood refinement with "
                                         "standard deviations and likelihood-ratio selection (fg.ema.refine)"),
             out: Path = typer.Option(Path("ema-output"), help="folder for modes.uff, modes.csv and figures"),
             json_path: Optional[Path] = typer.Option(None, "--json", help="write the modes as JSON")):
    """Identify modes with PolyMAX (+ maximum-likelihood refinement) + LSFD; write UFF 55, CSV, figures.

    Several files: each is identified, then the modes are paired by frequency and MAC and averaged
    with their spread (fg.ema.average_tests)."""
    from ..ema import average_tests
    from ..report import plots
    from ..io.uff import ModalResults, shapes_at_points, write_uff

    try:
        if band and len(band) != 2:
            raise FlexGVTError("--band takes two values: --band F_MIN --band F_MAX")
        fit_band = tuple(band) if band else None
        if wide and poles:
            raise FlexGVTError("--poles picks from one stabilisation diagram; use it without --wide (on a band)")
        runs = [_identify_one(p, fit_band, max_order, poles, wide, refine) for p in paths]
        frfs, stab, _ = runs[0]
        per_test = [m for _, _, m in runs]
        table_tests = None
        if len(paths) > 1:
            modes = average_tests(per_test)
            table_tests = modes.info["tests"]
        else:
            modes = per_test[0]
        out.mkdir(parents=True, exist_ok=True)
        title = (paths[0].name if len(paths) == 1
                 else f"{len(paths)} tests averaged ({', '.join(p.name for p in paths)})")
        table = Table(title=f"{title}: identified modes")
        sd_label = "std" if len(paths) == 1 else "spread (std)"
        for col in ("mode", "f [Hz]", f"f {sd_label} [Hz]", "zeta [%]", f"zeta {sd_label} [%]") + \
                (("tests",) if table_tests else ()):
            table.add_column(col, justify="right")
        fs = modes.frequency_std_hz
        zs = modes.damping_std
        lines = ["mode,frequency_hz,frequency_std_hz,damping_ratio,damping_std"]
        for k, (f, z) in enumerate(zip(modes.frequencies_hz, modes.damping_ratio)):
            f_sd = None if fs is None else float(fs[k])
            z_sd = None if zs is None else float(zs[k])
            row = [str(k + 1), f"{f:.4f}", _fmt_std(f_sd, "{:.4f}"), f"{100 * z:.2f}",
                   _fmt_std(None if z_sd is None else 100 * z_sd, "{:.2f}")]
            if table_tests:
                row.append(str(int(table_tests["n_tests"][k])))
            table.add_row(*row)
            lines.append(f"{k + 1},{f:.8g},{'' if f_sd is None else f'{f_sd:.6g}'},{z:.8g},"
                         f"{'' if z_sd is None else f'{z_sd:.6g}'}")
        console.print(table)
        (out / "modes.csv").write_text("\n".join(lines) + "\n")
        points, shapes = shapes_at_points(np.real(modes.shapes), frfs.outputs)
        write_uff(out / "modes.uff", modes=ModalResults(modes.frequencies_hz, modes.damping_ratio, shapes, points,
                                                        fs, zs))
        figs = {"cmif.png": plots.cmif_plot(frfs.frequencies_hz, frfs.H, modes),
                "frf_fit.png": plots.frf_fit(frfs.frequencies_hz, frfs.H, modes, 0)}
        if stab is not None:  # one diagram per sub-band with --wide: not drawn
            figs["stabilisation.png"] = plots.stabilisation_diagram(stab[0], modes, clusters=stab[1])
        for name, fig in figs.items():
            fig.savefig(out / name, dpi=120)
        if json_path is not None:
            doc = {"file": str(paths[0]) if len(paths) == 1 else [str(p) for p in paths],
                   "frequencies_hz": modes.frequencies_hz.tolist(), "damping_ratio": modes.damping_ratio.tolist(),
                   "frequency_std_hz": None if fs is None else fs.tolist(),
                   "damping_std": None if zs is None else zs.tolist()}
            if table_tests:
                doc["tests"] = {"frequencies_hz": [[None if not np.isfinite(v) else float(v) for v in r]
                                                   for r in table_tests["frequencies_hz"]],
                                "damping_ratio": [[None if not np.isfinite(v) else float(v) for v in r]
                                                  for r in table_tests["damping_ratio"]],
                                "n_tests": table_tests["n_tests"].tolist()}
            json_path.write_text(json.dumps(doc, indent=2))
        console.print(f"modes written to {out / 'modes.uff'} and {out / 'modes.csv'}; figures in {out}/")
    except (FlexGVTError, OSError) as exc:
        fail(console, exc)
