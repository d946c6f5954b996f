"""The `flexgvt` command line."""

from __future__ import annotations

import json
import time
import warnings
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.markup import escape

from ..errors import FlexGVTError

app = typer.Typer(add_completion=False, no_args_is_help=True, rich_markup_mode=None,  # help text is plain: "[kg]" shows
                  help="GVT and FE model updating of very flexible aircraft.")
console = Console()  # a terminal's width; 80 columns (or COLUMNS) in logs and pipes: the tables split to fit

try:  # the EMA commands live in their own module
    from .ema import app as ema_app
except ImportError:  # not installed in this build
    ema_app = None
if ema_app is not None:
    app.add_typer(ema_app, name="ema")

from .show import register as _register_show  # noqa: E402
from .suspension import app as _suspension_app  # noqa: E402
from .plan import register as _register_plan  # noqa: E402
from .verify import register as _register_verify  # noqa: E402
from .workflow import register as _register_workflow  # noqa: E402

app.add_typer(_suspension_app, name="suspension")



def _version(value: bool) -> None:
    if value:
        from importlib.metadata import PackageNotFoundError, version

        try:  # the installed distribution's version (the package's __version__ is one layer up)
            text = version("flexgvt")
        except PackageNotFoundError:
            text = "unknown (not installed: pip install -e .)"
        typer.echo(f"flexgvt {text}")
        raise typer.Exit()


@app.callback()
def _main(version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                       help="print the flexgvt version and exit")) -> None:
    """GVT and FE model updating of very flexible aircraft."""


_register_verify(app, console)
_register_workflow(app, console)
_register_plan(app, console)
_register_show(app, console)


def _fail(exc: Exception) -> None:
    console.print(f"[bold red]error:[/] {escape(str(exc))}", soft_wrap=True)  # one line, whatever its length
    raise typer.Exit(code=2)


def _solve_with_progress(model, cfg, settings=None):
    from ..fem import solve_static

    with Progress(TextColumn(f"[cyan]{cfg.name}[/] nonlinear static"), BarColumn(),
                  TextColumn("{task.percentage:>5.1f} %"), TimeElapsedColumn(), console=console, transient=True) as bar:
        task = bar.add_task("solve", total=1.0)
        return solve_static(model, cfg, settings=settings, progress=lambda lam: bar.update(task, completed=lam))


def _result_record(state, modes, timings) -> dict:
    from ..fem import mass_properties

    mp = mass_properties(state)
    u = state.displacements[:, :3]
    return {"load_factor": state.load_factor, "max_displacement_m": float(np.linalg.norm(u, axis=1).max()),
            "frequencies_hz": modes.frequencies_hz.tolist(), "damping_ratio": modes.damping_ratio.tolist(),
            "labels": list(modes.labels), "mass_kg": mp.mass, "cg_m": mp.cg.tolist(), "timings_s": timings,
            "cautions": list(state.cautions + modes.cautions)}


def _modes_table(title: str, results: dict) -> None:
    """Print one column group per configuration: frequency [Hz], damping ratio [%] where any is
    non-zero, label; split by columns to fit the console."""
    from .tables import print_table

    headers, columns = ["mode"], []
    for name, r in results.items():
        damped = any(abs(z) >= 5e-4 for z in r["damping_ratio"])
        headers += [f"{name} f [Hz]"] + ([f"{name} zeta [%]"] if damped else []) + [f"{name} label"]
        columns.append((r, damped))
    n = max(len(r["frequencies_hz"]) for r in results.values())
    rows = []
    for k in range(n):
        row = [str(k + 1)]
        for r, damped in columns:
            have = k < len(r["frequencies_hz"])
            row.append(f"{r['frequencies_hz'][k]:.4f}" if have else "")
            if damped:
                row.append(f"{100 * r['damping_ratio'][k]:.2f}" if have else "")
            row.append(r["labels"][k] if have else "")
        rows.append(row)
    print_table(console, title, headers, rows,
                justify=["right"] + [("left" if h.endswith(" label") else "right") for h in headers[1:]])


@app.command()
def solve(case: str = typer.Argument(..., help="built-in case (cantilever_strip, strip_366, hale_wing, xhale, "
                                     "wingbox, swept_wing) or a .bdf deck"),
          config: Optional[list[str]] = typer.Option(None, "--config", "-c", help="configuration name(s); default all"),
          modes: Optional[int] = typer.Option(None, help="number of modes (default: a deck's EIGRL/EIGR ND, window "
                                              "and normalisation, as Nastran; else 10)"),
          out: Optional[Path] = typer.Option(None, help="folder for figures"),
          json_path: Optional[Path] = typer.Option(None, "--json", help="write results as JSON (layout: docs/cli.md)"),
          units: str = typer.Option("SI", help="bulk data units: SI (m-kg-s), mm-N-t-s (mm-t-s), in-lbf-s, "
                                    "ft-lbf-s"),
          allow_unsupported: bool = typer.Option(False,
                                                 help="bulk data: warn about unsupported cards instead of failing"),
          cbar_torsional_inertia: bool = typer.Option(False, help="bulk data: add rho*Ip torsional inertia to CBAR "
                                                      "mass (Nastran's CBAR has none, the default)"),
          mass_frame: str = typer.Option("deformed", help="mass matrix about the deformed state (physical) or the "
                                         "undeformed one (as Nastran SOL 400 and OpenSees)"),
          buckling: str = typer.Option("warn", help="an unstable final state (a buckled skin, a limit point): warn "
                                       "(locate it), stop (error with the last stable state), continue (onto the "
                                       "post-buckled path with a small imperfection in the buckling shape), ignore"),
          imperfection: float = typer.Option(0.0, help="--buckling continue: the imperfection's largest offset [m] "
                                             "(0: a tenth of the thickness of most buckled shells)")):
    """Static shape and pre-stressed modes of each configuration of a built-in case or a Nastran deck."""
    try:
        from ..fem import StaticSettings
        settings = StaticSettings(buckling=buckling.lower(), imperfection=imperfection)
        if case.lower().endswith((".bdf", ".dat", ".nas", ".blk")):
            from ..io.nastran import Units, read_bdf
            from ..workflow.units import unit_system
            system = Units(*unit_system(units, "--units"))
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                deck = read_bdf(case, units=system, unsupported="warn" if allow_unsupported else "error",
                                cbar_torsional_inertia=cbar_torsional_inertia)
            for w in caught:
                console.print(f"[yellow]note:[/] {escape(str(w.message))}")
            model, configurations, title = deck.model, deck.configurations, Path(case).name
            methods = deck.methods
        else:
            methods = {}
            from ..cases import get
            c = get(case)
            model, configurations, title = c.model, c.configurations, c.name
        names = list(config) if config else list(configurations)
        unknown = [n for n in names if n not in configurations]
        if unknown:
            raise FlexGVTError(f"no configuration {unknown} in '{title}'; choose from {list(configurations)}")
        from ..fem import solve_modes
        results, states, mode_sets = {}, {}, {}
        for name in names:
            with warnings.catch_warnings(record=True) as caught:  # the cautions are printed below, once
                warnings.simplefilter("always")
                t0 = time.perf_counter()
                st = _solve_with_progress(model, configurations[name], settings)
                t1 = time.perf_counter()
                if methods.get(name) is not None:
                    from ..workflow.deck import deck_modes
                    md = deck_modes(st, methods[name], modes, mass_frame)
                else:
                    md = solve_modes(st, modes or 10, mass_frame=mass_frame)
                t2 = time.perf_counter()
            states[name], mode_sets[name] = st, md
            results[name] = _result_record(st, md, {"static": t1 - t0, "modes": t2 - t1})
            summary, _, _ = st.summary().partition("\n  warning: ")
            console.print(f"[green]{escape(summary)}[/]  ({t1 - t0:.2f} s static, {t2 - t1:.2f} s modes)")
            for caution in st.cautions + md.cautions:
                console.print(f"  [bold yellow]warning:[/] {escape(caution)}")
            for w in caught:
                if str(w.message) not in st.cautions + md.cautions:
                    console.print(f"  [yellow]note:[/] {escape(str(w.message))}")
        _modes_table(f"{title}: pre-stressed modes", results)
        if out is not None:
            _write_figures(out, title, states, mode_sets)
        if json_path is not None:
            json_path.write_text(json.dumps({"case": title, "configurations": results}, indent=2))
            console.print(f"results written to {json_path}", markup=False, highlight=False)
    except FlexGVTError as exc:
        _fail(exc)


def _write_figures(out: Path, title: str, states: dict, mode_sets: dict) -> list[Path]:
    from ..report import plots

    out.mkdir(parents=True, exist_ok=True)
    files = []
    fig = plots.static_shape(states.values(), f"{title}: static shapes")
    files.append(out / "static_shape.png")
    fig.savefig(files[-1], dpi=120)
    for name, md in mode_sets.items():
        fig = plots.mode_shapes(md, 6, f"{title} - {name}")
        files.append(out / f"modes_{name}.png")
        fig.savefig(files[-1], dpi=120)
    console.print("figures: " + ", ".join(str(f) for f in files), markup=False, highlight=False)
    return files


@app.command()
def demo(out: Path = typer.Option(Path("demo-output"), help="folder for the project, its data and results"),
         json_path: Optional[Path] = typer.Option(None, "--json", help="write per-mode prediction errors as JSON"),
         seed: int = typer.Option(7, help="seed of the as-built airframe and of the measurement noise"),
         report: bool = typer.Option(True, help="write the HTML report (--no-report to skip)"),
         fresh: bool = typer.Option(False, "--fresh/--continue", help="--fresh: discard what an earlier demo "
                                    "in --out stored; --continue (the default): resume from it"),
         verbose: bool = typer.Option(False, "--verbose", "-v", help="print every optimiser iteration")):
    """The whole method on the X-HALE-like aircraft: synthetic GVT of the as-built airframe in two
    suspension layouts, PolyMAX, updating on both at once (30 variables), suspension removed,
    free-free and 20 m bungee predictions scored against the as-built truth, report."""
    from ..workflow.demo import SCORED_MODES, demo_figures, demo_project
    from .workflow import print_prediction, run_with_progress

    def job(log, iteration):
        from ..report import write_project_report
        from ..workflow import run
        t0 = time.perf_counter()
        project = demo_project(out, seed=seed, progress=log)
        t_data = time.perf_counter() - t0
        res = run(project, progress=log, iterations=iteration, fresh=fresh)
        if report:  # the face renders; the workflow only returns results
            write_project_report(res)
        return demo_figures(res, out, seed, t_data, t0)
    try:
        console.rule("[bold]flexgvt demo: X-HALE-like aircraft, GVT on two suspension layouts[/]")
        result = run_with_progress(console, job, verbose)
        for name, c in result["configurations"].items():
            console.print(f"configuration '{name}': rms frequency error {c['initial_rms_error_percent']:.2f} % "
                          f"(initial model) -> {c['updated_rms_error_percent']:.2f} % (updated), {c['modes']} modes",
                          markup=False, highlight=False)
        for key, rows in result["free_free"].items():
            print_prediction(console, f"free-free prediction of the {key} model against the as-built truth "
                             f"(first {SCORED_MODES} elastic modes, paired by MAC)", rows)
        for name, by_model in result["bungees"].items():
            print_prediction(console, f"{name} (20 m bungees): updated model against the as-built truth",
                             by_model.get("updated", by_model.get("initial")))
        worst = result["max_abs_error_percent"]
        console.print("largest free-free error: " + ", ".join(f"{k} model {v:.2f} %" for k, v in worst.items()))
        if "report" in result["files"]:
            console.print(f"report: {result['files']['report']}", markup=False, highlight=False)
        console.print(f"done in {result['timings_s']['total']:.1f} s; everything in {out}/", markup=False,
                      highlight=False)
        if json_path is not None:
            json_path.write_text(json.dumps(result, indent=1, default=float))
            console.print(f"results written to {json_path}", markup=False, highlight=False)
    except FlexGVTError as exc:
        _fail(exc)


if __name__ == "__main__":
    app()
