"""`flexgvt run project.toml` and `flexgvt init`: the main job from a project file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from ..errors import FlexGVTError


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


def prediction_table(title: str, rows: list[dict]) -> Table:
    """The free-flying prediction as a rich table (the columns the rows hold)."""
    table = Table(title=title)
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys and not k.endswith("_mac") and k != "reference_label"]
    for k in keys:
        table.add_column(k.replace("_percent", " [%]").replace("_hz", " [Hz]").replace("_", " "), justify="right")
    for r in rows:
        table.add_row(*[_fmt(r.get(k), 2 if k.endswith("percent") else 4) for k in keys])
    return table


def run_with_progress(console: Console, job):
    """Run ``job(log)`` under a live status line (spinner, current step, elapsed time); every log
    line is also printed above it, so the record stays in the terminal and in logs."""
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    with Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(), console=console,
                  transient=True) as bar:
        task = bar.add_task("starting", total=None)

        def log(line: str) -> None:
            console.print(line, markup=False, highlight=False)
            bar.update(task, description=str(line).strip().splitlines()[0][:90])
        return job(log)


def register(app: typer.Typer, console: Console) -> None:
    @app.command()
    def run(project: Path = typer.Argument(..., help="project file (TOML); `flexgvt init` writes an example"),
            out: Optional[Path] = typer.Option(None, help="output folder (default: the project's outputs.directory)"),
            json_path: Optional[Path] = typer.Option(None, "--json", help="write the results as JSON"),
            report: bool = typer.Option(True, help="write the HTML report (--no-report to skip)")):
        """Identify, update on every configuration at once, remove the suspension, predict, report.

        Resumable: a second run reads the identified modes and the finished optimisation back from
        the project's results store."""
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

            def job(log):
                res = run_project(p, progress=log)
                if report:  # --report (the default) as before: the face renders, the workflow only returns results
                    from ..report import write_project_report
                    write_project_report(res)
                return res
            res = run_with_progress(console, job)
            for key, pred in res.predictions.items():
                console.print(prediction_table(f"free-flying prediction, {key} model", pred.rows))
            console.print(f"outputs in {p.output}/: " + ", ".join(Path(f).name for f in res.files.values()))
            if json_path is not None:
                json_path.write_text(json.dumps(res.to_dict(), indent=1))
                console.print(f"results written to {json_path}")
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
                files = write_example(folder, progress=console.print)
                console.print(f"synthetic GVT written: {', '.join(Path(f).name for f in files)}")
            else:
                path.write_text(example_project())
            console.print(f"example project written to {path}; run it with `flexgvt run {path}`")
        except (FlexGVTError, OSError) as exc:
            fail(console, exc)
