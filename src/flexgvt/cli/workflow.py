"""`flexgvt run project.toml` and `flexgvt init`: the main job from a project file."""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console

from ..errors import FlexGVTError, FlexGVTWarning


def fail(console: Console, exc: Exception) -> None:
    """Print a FlexGVTError (or an OSError from writing an output file) as one error line, exit status 2.
    The message is printed as text, never as rich markup (it may hold '[...]' from a user's input)."""
    from rich.markup import escape
    if isinstance(exc, OSError):
        msg = f"{exc.filename or ''}: {exc.strerror or exc}; check the path, its permissions and free space"
    else:
        msg = str(exc)
    console.print(f"[bold red]error:[/] {escape(msg)}", soft_wrap=True)
    raise typer.Exit(code=2)


def _fmt(v, digits: int = 4) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.{digits}f}"
    return str(v)


def prediction_rows(rows: list[dict]) -> tuple[list[str], list[list[str]]]:
    """The free-flying prediction's headers (with units) and formatted cells (the columns the rows
    hold; frequencies to 4 decimals, percentages to 2)."""
    from .tables import header
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys and (not k.endswith("_mac") or k == "subspace_mac")
                 and k != "reference_label"]
    return ([header(k) for k in keys],
            [[_fmt(r.get(k), 2 if k.endswith("percent") else 4) for k in keys] for r in rows])


def print_prediction(console: Console, title: str, rows: list[dict]) -> None:
    """The free-flying prediction as console tables no wider than the console (split by columns,
    mode and label repeated in each part)."""
    from .tables import print_table
    headers, cells = prediction_rows(rows)
    print_table(console, title, headers, cells, key=2 if len(headers) > 1 and headers[1] == "label" else 1,
                justify=["left" if h == "label" else "right" for h in headers])


def _g(v) -> str:
    return "" if v is None else f"{v:.6g}"


def frequency_cells(rows: list[dict]) -> tuple[list[str], list[list[str]]]:
    """An updating table's rows (flexgvt.updating's layout: measured, initial and updated frequency,
    errors, MACs) as headers with units and cells; an unpaired mode's row says so."""
    mac = any(r.get("initial_mac") is not None or r.get("updated_mac") is not None for r in rows)
    headers = ["mode", "label", "measured [Hz]", "initial [Hz]", "error [%]", "updated [Hz]", "error [%]"]
    headers += ["MAC initial", "MAC updated"] if mac else []
    cells = []
    for r in rows:
        row = [str(r.get("mode", "")), str(r.get("label") or ""), _fmt(r.get("measured_hz")),
               _fmt(r.get("initial_hz")), _fmt(r.get("initial_error_percent"), 2),
               _fmt(r.get("updated_hz")) if r.get("updated_hz") is not None else "unpaired",
               _fmt(r.get("updated_error_percent"), 2)]
        cells.append(row + ([_fmt(r.get("initial_mac"), 3), _fmt(r.get("updated_mac"), 3)] if mac else []))
    return headers, cells


def variable_cells(rows: list[dict]) -> tuple[list[str], list[list[str]]]:
    """Design-variable rows (initial, final, change, normalised bounds, status) as headers and cells."""
    headers = ["variable", "initial", "final", "change [%]", "bounds", "note"]
    cells = []
    for r in rows:
        note = "held (not identifiable)" if r.get("fixed") else ", ".join(
            w for w, on in (("at bound", r.get("at_bound")), ("not identifiable", not r.get("identifiable", True)))
            if on)
        cells.append([str(r["name"]), _g(r.get("initial")), _g(r.get("final")), _fmt(r.get("change_percent"), 2),
                      f"{r['lower']:g} - {r['upper']:g}" if r.get("lower") is not None else "", note])
    return headers, cells


def print_updating(console: Console, title: str, frequencies: dict, variables: list[dict]) -> None:
    """One updating's frequency table per configuration and its design variables."""
    from .tables import print_table
    for name, rows in frequencies.items():
        headers, cells = frequency_cells(rows)
        print_table(console, f"{title}: {name}", headers, cells, key=2,
                    justify=["left" if h == "label" else "right" for h in headers])
    headers, cells = variable_cells(variables)
    print_table(console, f"{title}: design variables", headers, cells,
                justify=["left" if h in ("variable", "note") else "right" for h in headers])


def print_stages(console: Console, stages: list[dict]) -> None:
    """Each stage of a staged updating (results.json's ``stages`` entries) as its own tables: a stage
    of fixed inputs its values, an updating stage its frequencies and variables."""
    from .tables import print_table
    for k, st in enumerate(stages):
        title = f"stage {k + 1} of {len(stages)} ('{st['name']}')"
        if st["fixed_inputs"]:
            print_table(console, f"{title}: fixed inputs",
                        ["variable", "attribute", "before", "set to", "change [%]"],
                        [[r["name"], f"{r['kind']} {r['attribute']}", _g(r["before"]), _g(r["value"]),
                          _fmt(r.get("change_percent"), 2)] for r in st["fixed_inputs"]],
                        justify=["left", "left", "right", "right", "right"])
        if st["variables"]:
            print_updating(console, title, st["frequencies"], st["variables"])
        for r in st.get("mass_properties") or ():
            console.print(f"  {r['property']}: measured {r['measured']:.6g}, initial {r['initial']:.6g}, updated "
                          f"{r['updated']:.6g}", markup=False, highlight=False)


def run_with_progress(console: Console, job, verbose: bool = False):
    """Run ``job(log, iteration)`` under a live progress line (spinner, current step, a bar while the
    updating iterates, the current objective, elapsed time) on a terminal, none in a pipe or log.
    Every log line is printed above it, so the record stays; the optimiser's iterations are printed
    one line each only when ``verbose``. Ctrl-C: the interruption's message (where the run
    stopped, that a rerun resumes), exit status 130."""
    from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    with Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(bar_width=20),
                  TextColumn("{task.fields[objective]}"), TimeElapsedColumn(), console=console, transient=True,
                  disable=not console.is_terminal) as bar:
        task = bar.add_task("starting", total=None, objective="")

        def log(line: str) -> None:
            console.print(line, markup=False, highlight=False)
            bar.update(task, description=str(line).strip().splitlines()[0][:40], objective="")

        def iteration(row: dict) -> None:
            text = f"iteration {row.get('iteration', '?')}: objective {row['objective']:.6g}"
            if verbose:
                console.print("  " + text, markup=False, highlight=False)
            bar.update(task, description="updating", objective=text)
        try:
            return job(log, iteration)
        except KeyboardInterrupt as exc:
            bar.stop()
            what = getattr(exc, "message", None) or "interrupted; a rerun resumes from the results store"
            console.print(f"stopped (Ctrl-C): {what}", markup=False, highlight=False, soft_wrap=True)
            raise typer.Exit(code=130) from None


def register(app: typer.Typer, console: Console) -> None:
    @app.command()
    def run(project: Path = typer.Argument(..., help="project file (TOML); `flexgvt init` writes an example"),
            out: Optional[Path] = typer.Option(None, help="output folder (default: the project's outputs.directory)"),
            json_path: Optional[Path] = typer.Option(None, "--json", help="write the results as JSON"),
            report: bool = typer.Option(True, help="write the HTML report (--no-report to skip)"),
            fresh: bool = typer.Option(False, "--fresh/--continue",
                                       help="--fresh: discard the stored identification and updating and start "
                                       "again; --continue (the default): resume from the results store"),
            verbose: bool = typer.Option(False, "--verbose", "-v", help="print every optimiser iteration")):
        """Identify, update on every configuration at once, remove the suspension, predict, report.

        Resumes by default: a rerun reads the identified modes and the updating back from the
        project's results store (outputs.directory/store); an interrupted updating continues
        where it stopped, and one stopped at its limits continues when max_iterations or the
        tolerance are raised. --fresh starts again."""
        from ..workflow import load_project, run as run_project
        try:
            p = load_project(project)
            if out is not None:
                from ..workflow.validate import checked_path, output_dir
                out = checked_path(Path("."), str(out), "--out", "output directory")
                output_dir(out.parent, out.name, True, "--out")
                p.spec = p.spec.model_copy(update={"outputs": p.spec.outputs.model_copy(
                    update={"directory": str(out.resolve())})})
            from rich.markup import escape
            console.rule(f"[bold]{escape(p.spec.project.name)}[/]")

            def job(log, iteration):
                with warnings.catch_warnings():  # flexgvt's cautions as log lines, in place, without source lines
                    shown = warnings.showwarning

                    def show(message, category, filename, lineno, file=None, line=None):
                        if issubclass(category, FlexGVTWarning):
                            log(f"warning: {message}")
                        else:
                            shown(message, category, filename, lineno, file, line)
                    warnings.showwarning = show
                    res = run_project(p, progress=log, iterations=iteration, fresh=fresh)
                if report:  # --report (the default) as before: the face renders, the workflow only returns results
                    from ..report import write_project_report
                    write_project_report(res)
                return res
            res = run_with_progress(console, job, verbose)
            if res.stages:
                print_stages(console, [s.to_dict() for s in res.stages])
            elif res.update is not None:
                print_updating(console, "updating", res.update.tables, res.update.variables)
            for key, pred in res.predictions.items():
                print_prediction(console, f"free-flying prediction, {key} model", pred.rows)
            console.print(f"outputs in {p.output}/: " + ", ".join(Path(f).name for f in res.files.values()),
                          markup=False, highlight=False)
            if json_path is not None:
                json_path.write_text(json.dumps(res.to_dict(), indent=1))
                console.print(f"results written to {json_path}", markup=False, highlight=False)
        except (FlexGVTError, OSError) as exc:
            fail(console, exc)

    @app.command()
    def init(folder: Path = typer.Argument(Path("."), help="folder for project.toml"),
             data: bool = typer.Option(False, "--data", help="also write a synthetic GVT of the X-HALE-like "
                                       "aircraft so the project runs as it is"),
             force: bool = typer.Option(False, help="overwrite an existing project.toml")):
        """Write a commented example project (every key explained)."""
        from ..workflow.template import example_project, write_example
        try:
            folder.mkdir(parents=True, exist_ok=True)
            path = folder / "project.toml"
            if path.exists() and not force:
                raise FlexGVTError(f"{path} exists; use --force to overwrite it")
            if data:
                files = write_example(folder, progress=lambda s: console.print(s, markup=False))
                console.print(f"synthetic GVT written: {', '.join(Path(f).name for f in files)}", markup=False,
                              highlight=False)
            else:
                path.write_text(example_project())
            console.print(f"example project written to {path}; run it with `flexgvt run {path}`", markup=False,
                          highlight=False)
        except (FlexGVTError, OSError) as exc:
            fail(console, exc)
