"""`flexgvt ema identify FILE.uff [MORE.uff ...]`: PolyMAX (+ maximum-likelihood refinement) on the files'
FRFs, modes with standard deviations to UFF 55, CSV, JSON and a table, figures; several files averaged.
`flexgvt ema frf TIME.uff --out frfs.uff`: FRFs (H1/H2/Hv) estimated from the time histories of a file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import warnings

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape

from ..errors import FlexGVTError, FlexGVTWarning
from .tables import print_table
from .workflow import fail

app = typer.Typer(add_completion=False, no_args_is_help=True, help="Experimental modal analysis.")
console = Console()


_DIRECTION = {"X": 1, "Y": 2, "Z": 3, "RX": 4, "RY": 5, "RZ": 6}


def dof_name(dof) -> str:
    """(100, 3) -> '100+Z'."""
    p, d = int(dof[0]), int(dof[1])
    name = {v: k for k, v in _DIRECTION.items()}.get(abs(d), str(abs(d)))
    return f"{p}{'-' if d < 0 else '+'}{name}"


def _read(path, drop_incomplete: bool):
    """read_uff(path), printing what was dropped with --drop-incomplete."""
    from ..io.uff import read_uff

    with warnings.catch_warnings():  # said below, once, in the console
        warnings.simplefilter("ignore", FlexGVTWarning)
        data = read_uff(path, drop_incomplete=drop_incomplete)
    for line in data.dropped:
        console.print(f"[yellow]dropped[/] ({escape(path.name)}): {escape(line)}", soft_wrap=True)
    return data


def _identify_one(path, fit_band, max_order, poles, wide, refine, drop_incomplete=False, dropped=None):
    from ..ema import identify_wide_band, polymax
    from ..ema import refine as ml_refine

    data = _read(path, drop_incomplete)
    if data.dropped and dropped is not None:
        dropped[str(path)] = list(data.dropped)
    frfs = data.frfs
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
             json_path: Optional[Path] = typer.Option(None, "--json", help="write the modes as JSON"),
             drop_incomplete: bool = typer.Option(False, "--drop-incomplete", help="leave out the FRF channels "
                                                  "(responses, or a reference) whose matrix is incomplete, and say "
                                                  "which")):
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
        dropped: dict[str, list[str]] = {}
        runs = [_identify_one(p, fit_band, max_order, poles, wide, refine, drop_incomplete, dropped) for p in paths]
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
        sd_label = "std" if len(paths) == 1 else "spread (std)"
        headers = ["mode", "f [Hz]", f"f {sd_label} [Hz]", "zeta [%]", f"zeta {sd_label} [%]"] + \
            (["tests"] if table_tests else [])
        rows = []
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
            rows.append(row)
            lines.append(f"{k + 1},{f:.8g},{'' if f_sd is None else f'{f_sd:.6g}'},{z:.8g},"
                         f"{'' if z_sd is None else f'{z_sd:.6g}'}")
        print_table(console, f"{title}: identified modes", headers, rows)
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
            if dropped:
                doc["dropped_channels"] = dropped
            if table_tests:
                doc["tests"] = {"frequencies_hz": [[None if not np.isfinite(v) else float(v) for v in r]
                                                   for r in table_tests["frequencies_hz"]],
                                "damping_ratio": [[None if not np.isfinite(v) else float(v) for v in r]
                                                  for r in table_tests["damping_ratio"]],
                                "n_tests": table_tests["n_tests"].tolist()}
            json_path.write_text(json.dumps(doc, indent=2))
        console.print(f"modes written to {out / 'modes.uff'} and {out / 'modes.csv'}; figures in {out}/",
                      markup=False, highlight=False)
    except (FlexGVTError, OSError) as exc:
        fail(console, exc)


@app.command()
def frf(path: Path = typer.Argument(..., help="UFF file with simultaneous time histories (dataset 58, function "
                                    "type 1): force and response channels of one run"),
        reference: Optional[list[str]] = typer.Option(None, "--reference", "-r", help="a force channel as "
                                                      "POINT+DIRECTION (100+Z); repeat for several; default: the "
                                                      "channels the file marks as forces"),
        estimator: str = typer.Option("H1", help="H1 (noise on the response), H2 or Hv (one reference)"),
        nperseg: Optional[int] = typer.Option(None, "--nperseg", min=8, help="samples per averaged block "
                                              "(default: the whole record, no averaging)"),
        overlap: float = typer.Option(0.5, min=0.0, max=0.95, help="overlap of the blocks (0..0.95)"),
        window: str = typer.Option("hann", help="window of the blocks: hann or rect"),
        drop_incomplete: bool = typer.Option(False, "--drop-incomplete", help="leave out incomplete FRF channels "
                                             "the file also holds, and say which"),
        out: Path = typer.Option(..., "--out", help="UFF file to write the FRFs (dataset 58, function type 4) "
                                 "and the file's geometry to")):
    """Estimate FRFs from a file's time histories (averaged blocks with a window) and write them as UFF 58."""
    from ..ema import estimate_frf_from_time
    from ..io.uff import write_uff
    from ..workflow.identification import parse_dof

    try:
        refs = [parse_dof(r, "--reference") for r in reference] if reference else None
        if estimator not in ("H1", "H2", "Hv"):
            raise FlexGVTError(f"--estimator {estimator!r} must be H1, H2 or Hv")
        if window not in ("hann", "rect"):
            raise FlexGVTError(f"--window {window!r} must be hann or rect")
        data = _read(path, drop_incomplete)
        frfs = estimate_frf_from_time(data.time_histories, references=refs, estimator=estimator, nperseg=nperseg,
                                      overlap=overlap, window=window)
        write_uff(out, geometry=data.geometry, frfs=frfs)
        coh = np.asarray(frfs.coherence) if frfs.coherence is not None else None
        names = ", ".join(dof_name(d) for d in frfs.inputs.tolist())
        console.print(f"{frfs.H.shape[1]} responses x {frfs.H.shape[2]} reference(s) ({names}), "
                      f"{len(frfs.frequencies_hz)} lines to {frfs.frequencies_hz[-1]:.4g} Hz, {estimator}, "
                      f"{frfs.n_averages} averages" + ("" if coh is None else
                                                       f", median coherence {np.median(coh):.3f}"),
                      markup=False, highlight=False)
        console.print(f"FRFs written to {out}", soft_wrap=True, markup=False, highlight=False)
    except (FlexGVTError, OSError) as exc:
        fail(console, exc)
