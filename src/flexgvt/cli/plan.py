"""`flexgvt plan project.toml`: pre-test planning on the user's own project (candidate suspensions,
sensors and driving points on the deformed configurations, a pre-test report)."""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from ..errors import FlexGVTError


def _num(v, fmt: str = ".3g") -> str:
    return "-" if v is None else format(v, fmt)


def layouts_table(name: str, rows: list[dict], n: int = 5) -> Table:
    """The best ``n`` candidate suspensions of a configuration (fits 80 columns)."""
    from rich import box
    table = Table(title=f"{name}: candidate suspensions, best first ({len(rows)} tried)", title_justify="left",
                  box=box.SIMPLE_HEAD, pad_edge=False)
    for col, just, width in (("#", "right", 2), ("suspension", "left", 22), ("susp. max [Hz]", "right", 6),
                             ("1st elastic [Hz]", "right", 7), ("separation", "right", 10),
                             ("largest shift [%]", "right", 7), ("ok", "left", 3)):
        table.add_column(col, justify=just, overflow="fold", max_width=width)
    for r in rows[:n]:
        table.add_row(str(r["rank"]), escape(r["suspension"]), _num(r["highest_suspension_hz"]),
                      _num(r["first_elastic_hz"]), _num(r["separation"], ".2f"),
                      _num(r["largest_elastic_shift_percent"], "+.2f"), "yes" if r["acceptable"] else "no")
    return table


def register(app: typer.Typer, console: Console) -> None:
    @app.command()
    def plan(project: Path = typer.Argument(..., help="project file (TOML) with an optional [plan] table"),
             out: Optional[Path] = typer.Option(None, help="output folder (default: <outputs.directory>/pretest)"),
             json_path: Optional[Path] = typer.Option(None, "--json", help="also write the plan as JSON here"),
             report: bool = typer.Option(True, help="write pretest.html (--no-report to skip)")):
        """Pre-test planning: rank candidate suspensions, place sensors and driving points on each
        deformed configuration, write the tables and a pre-test report."""
        from .workflow import fail, run_with_progress
        from ..workflow.plan import load_plan_project, plan_project
        try:
            p = load_plan_project(project)
            if out is not None:
                from ..workflow.validate import checked_path, output_dir
                out = checked_path(Path("."), str(out), "--out", "output directory")
                output_dir(out.parent, out.name, True, "--out")
            console.print(f"[bold]{escape(p.spec.project.name)}[/]: pre-test plan")
            res = run_with_progress(console, lambda log, iteration: plan_project(p, out=out, progress=log))
            for name, c in res.configurations.items():
                if c.layouts:
                    console.print(layouts_table(name, c.layout_rows()))
                lines = [f"{name}: tested on {c.tested}; {len(c.targets)} target modes "
                         f"{_num(float(c.modes.frequencies_hz[c.targets].min()))}-"
                         f"{_num(float(c.modes.frequencies_hz[c.targets].max()))} Hz",
                         f"{len(c.sensors)} sensors (auto-MAC off-diagonal max {c.auto_mac_max:.2f}): "
                         + ", ".join(c.sensors.names),
                         "driving points (smallest normalised residue over the targets, weakest mode):"]
                lines += [f"{e['rank']:2d}. {e['name']:<10} {e['min_residue']:.2f}  {e['weakest_mode']}"
                          for e in c.exciters]
                lines += [f"note: {n}" for n in c.notes]
                for k, line in enumerate(lines):  # wrapped here: piped output keeps 80 columns and every number
                    console.print(escape(textwrap.fill(line, 78, initial_indent="" if k == 0 else "  ",
                                                       subsequent_indent="    ")), highlight=False, soft_wrap=True)
            if report:
                from ..report.pretest import write_pretest_report
                res.files["report"] = write_pretest_report(res)
            if json_path is not None:
                json_path.write_text(res.files["json"].read_text())
                res.files["--json"] = json_path
            console.print(escape(textwrap.fill(f"outputs in {res.output}/: " + ", ".join(
                Path(f).name for k, f in res.files.items() if k != "--json"), 78, subsequent_indent="  ")),
                highlight=False, soft_wrap=True)
        except (FlexGVTError, OSError) as exc:
            fail(console, exc)
