"""`flexgvt suspension identify|plan`: suspension points from block tests; layouts planned on the
deformed structure."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape

from ..errors import FlexGVTError
from .tables import print_table

app = typer.Typer(add_completion=False, no_args_is_help=True,
                  help="Suspension: identify points from block tests, plan layouts.")
console = Console()  # 80 columns (or COLUMNS) in a pipe: the tables split to fit


def _fail(exc: Exception) -> None:
    console.print(f"[bold red]error:[/] {escape(str(exc))}", soft_wrap=True)
    raise typer.Exit(code=2)


def _write_json(path: Optional[Path], data) -> None:
    if path is not None:
        from ..updating.result import jsonable
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(jsonable(data), indent=1))
        console.print(f"results written to {path}", markup=False, highlight=False)


@app.command()
def identify(mass: float = typer.Option(..., help="block mass [kg]: the mass the suspension point carries"),
             frequency: Optional[list[float]] = typer.Option(None, help="damped frequency [Hz]; repeat for repeated "
                                                                          "tests"),
             damping: Optional[list[float]] = typer.Option(None, help="damping ratio [-], one per --frequency"),
             decay: Optional[Path] = typer.Option(None, help="CSV free-decay record: columns time [s], response"),
             peaks: Optional[str] = typer.Option(None, help="comma-separated times [s] of successive peaks"),
             out: Optional[Path] = typer.Option(None, help="folder for the figure"),
             json_path: Optional[Path] = typer.Option(None, "--json", help="write the identified point as JSON")):
    """Stiffness and damping of a suspension point from a block test (docs/method.md section 2)."""
    from ..suspension import identify_block
    try:
        kwargs = {}
        if frequency:
            if not damping or len(damping) not in (1, len(frequency)):
                raise FlexGVTError("give one --damping per --frequency (or one for all)")
            kwargs = dict(frequency_hz=list(frequency), damping_ratio=list(damping) if len(damping) > 1 else damping[0])
        elif decay is not None:
            try:
                data = np.loadtxt(decay, delimiter=",", ndmin=2)
            except (OSError, ValueError) as exc:
                raise FlexGVTError(f"{decay}: cannot read a two-column CSV record ({exc})") from None
            if data.shape[1] < 2:
                raise FlexGVTError(f"{decay}: needs two columns, time [s] and response")
            kwargs = dict(decay=(data[:, 0], data[:, 1]))
        elif peaks is not None:
            try:
                kwargs = dict(peak_times=[float(v) for v in peaks.split(",")])
            except ValueError:
                raise FlexGVTError(f"--peaks '{peaks}': give comma-separated times in seconds") from None
        point = identify_block(mass=mass, **kwargs)
    except FlexGVTError as exc:
        _fail(exc)
    rows = []
    for name, v, s, fmt in (("block mass [kg]", point.mass, 0.0, ".3f"), ("f_d [Hz]", point.damped_frequency_hz,
                             None, ".4f"), ("f_n [Hz]", point.frequency_hz, point.frequency_std_hz, ".4f"),
                            ("zeta [-]", point.damping_ratio, point.damping_ratio_std, ".4f"),
                            ("K [N/m]", point.stiffness, point.stiffness_std, ".4g"),
                            ("C [N s/m]", point.damping, point.damping_std, ".4g")):
        rows.append([name, format(v, fmt), "" if s is None else format(s, ".2g")])
    print_table(console, f"suspension point from {point.source} ({point.n_tests} test"
                f"{'s' if point.n_tests > 1 else ''})", ["quantity", "value", "std"], rows,
                justify=["left", "right", "right"])
    if out is not None:
        from ..report.plots import suspension_response
        out.mkdir(parents=True, exist_ok=True)
        suspension_response(point).savefig(out / "suspension_point.png", dpi=120)
        console.print(f"figure: {out / 'suspension_point.png'}", markup=False, highlight=False)
    _write_json(json_path, point.to_dict())


@app.command()
def plan(case: str = typer.Argument("strip_366", help="built-in case to hang"),
         stiffness: list[float] = typer.Option([5.0], help="candidate line rates [N/m] (repeat)"),
         station: list[float] = typer.Option([1.52], help="candidate attachment stations: +-y [m] (repeat)"),
         anchor_height: float = typer.Option(3.0, help="anchor height above the attachment [m]"),
         allowed_load: float = typer.Option(float("inf"), help="allowed load of each line [N]"),
         modes: int = typer.Option(8, help="elastic modes reported"),
         out: Optional[Path] = typer.Option(None, help="folder for the hung-shape figure"),
         json_path: Optional[Path] = typer.Option(None, "--json", help="write the ranked layouts as JSON")):
    """Hang the structure on every combination of candidate rates and symmetric stations and rank
    the layouts by how far the suspension modes sit below the first elastic mode."""
    from ..cases import get
    from ..suspension import Attachment, Layout, Line, LineElement, plan_suspension
    try:
        c = get(case)
        ids, xyz = c.model.node_ids, c.model.xyz
        layouts = []
        for k in stiffness:
            for y in station:
                line = Line((LineElement(f"{k:g} N/m line", k, anchor_height, allowed_load=allowed_load),))
                nodes = [int(ids[np.argmin(np.abs(xyz[:, 1] - s * y))]) for s in (-1, 1)]
                layouts.append(Layout(f"{k:g} N/m at y = +-{y:g} m", tuple(
                    Attachment(n, line, tuple(xyz[c.model.index_of([n])[0]] + (0, 0, anchor_height)))
                    for n in nodes)))
        results = plan_suspension(c.model, layouts, n_modes=modes)
    except FlexGVTError as exc:
        _fail(exc)
    rows, records = [], []
    for r in results:
        first = next((e["suspended_hz"] for e in r.elastic if e.get("suspended_hz")), None)
        bad = [e["label"] for e in r.elastic if e.get("contaminated")]
        rows.append([r.layout.name, ", ".join(f"{f:.3g}" for f in r.suspension_hz), f"{first:.3g}" if first else "-",
                     f"{r.separation:.2f}", ", ".join(bad) or "-", "\n".join(r.problems) or "ok"])
        records.append({"layout": r.layout.name, "acceptable": r.acceptable, "separation": r.separation,
                        "suspension_hz": r.suspension_hz.tolist(), "cord_tension_N": r.tensions.tolist(),
                        "elastic": r.elastic, "problems": r.problems})
    print_table(console, f"{c.name}: suspension layouts, best first",
                ["layout", "suspension modes [Hz]", "1st elastic [Hz]", "separation", "contaminated", "problems"],
                rows, justify=["left"] * 6)
    if out is not None:
        from ..report.plots import hung_shapes
        out.mkdir(parents=True, exist_ok=True)
        hung_shapes(c.name, results, xyz).savefig(out / "hung_shapes.png", dpi=120)
        console.print(f"figure: {out / 'hung_shapes.png'}", markup=False, highlight=False)
    _write_json(json_path, {"case": c.name, "layouts": records})
