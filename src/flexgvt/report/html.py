"""A self-contained HTML report (one file, plotly.js embedded once, opens offline) with PNG
figures and CSV tables beside it.

    from flexgvt.report import ReportContent, write_report
    path = write_report(content, "out/report")     # out/report/report.html, figures/*.png, tables/*.csv

Layout written to out_dir:
    report.html                               summary, per configuration (updated on or checked):
                                              test set-up, deformed shape, stabilisation, test modes
                                              (damping, MPC, MPD), measured against synthesised FRFs
                                              with the MIF, auto-MAC, MAC, COMAC, frequency errors +
                                              table (damping, unpaired modes and why), animated modes;
                                              design variables, history, frequency vs load,
                                              prediction, notes
    figures/<config>_deformed.png, <config>_stabilisation.png, <config>_frfs.png,
            <config>_auto_mac.png, <config>_mac.png, <config>_comac.png,
            <config>_frequency_errors.png, design_variables.png, history.png, frequency_vs_load.png
    tables/<config>_setup_<table>.csv, <config>_test_modes.csv, <config>_frf_fit_<reference>.csv,
           <config>_comac.csv, <config>_frequencies.csv, design_variables.csv, prediction.csv
           (numbers rounded to what they support: flexgvt.workflow.outputs.round_value)
All text is HTML-escaped; empty parts (None, empty lists) are left out.
"""

from __future__ import annotations

import datetime as _dt
import html
import math
import hashlib
import re
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ReportError
from ..io.tables import columns as _columns, write_csv  # noqa: F401  (write_csv re-exported)
from .content import ConfigurationSection, ReportContent

CSS = """
body { font-family: Helvetica, Arial, sans-serif; margin: 0; color: #222; background: #f4f5f7; }
header { background: #1f3b5f; color: #fff; padding: 18px 32px; }
header h1 { margin: 0; font-size: 24px; }
header .stamp { font-size: 12px; opacity: 0.8; margin-top: 4px; }
nav { background: #fff; padding: 8px 32px; border-bottom: 1px solid #ddd; font-size: 13px; }
nav a { margin-right: 14px; color: #1f5fbf; text-decoration: none; }
main { max-width: 1200px; margin: 0 auto; padding: 12px 24px 40px; }
section { background: #fff; border: 1px solid #ddd; border-radius: 6px; padding: 12px 20px; margin: 16px 0; }
h2 { font-size: 20px; margin: 6px 0 10px; color: #1f3b5f; }
h3 { font-size: 16px; margin: 18px 0 6px; color: #333; }
table { border-collapse: collapse; margin: 8px 0 12px; font-size: 13px; }
th, td { border: 1px solid #d0d4da; padding: 3px 9px; }
th { background: #e9edf3; text-align: center; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr:nth-child(even) td { background: #f8f9fb; }
table.summary th { text-align: left; }
.plot { margin: 6px 0 14px; min-height: 200px; }
.note { font-size: 12px; color: #555; }
details { margin: 6px 0 12px; font-size: 13px; }
summary { cursor: pointer; color: #1f5fbf; }
"""

_UNITS = (("_hz", " [Hz]"), ("_percent", " [%]"), ("_deg", " [deg]"), ("_ns_per_m", " [N s/m]"),
          ("_n_per_m", " [N/m]"), ("_kg", " [kg]"), ("_m", " [m]"))  # longest suffix first
_SIGNED = ("error", "change", "shift")  # percentages shown with their sign


def _slug(text: str, taken: set[str]) -> str:
    """A file-name-safe, unique name for ``text`` (at most 48 characters of it, then a short hash of
    the whole, so a long configuration name still gives a short, distinct file name)."""
    base = re.sub(r"[^A-Za-z0-9_-]+", "_", text).strip("_") or "configuration"
    if len(base) > 48:
        base = f"{base[:48]}_{hashlib.sha256(text.encode('utf-8', 'replace')).hexdigest()[:8]}"
    slug, k = base, 2
    while slug in taken:
        slug, k = f"{base}_{k}", k + 1
    taken.add(slug)
    return slug


def _esc(text: Any) -> str:
    return html.escape(str(text))


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def format_value(key: str, value: Any) -> str:
    """A table cell as text: None/NaN as an en dash, frequencies to 4 decimals below 100 Hz,
    standard deviations to 2 significant digits, percentages to 2 decimals (errors, changes and
    shifts signed), MAC-like measures (mac, comac,
    mpc, frac) to 3 decimals, angles (*_deg) to 0.1, other floats to 4 significant digits."""
    if value is None:
        return "\u2013"
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (tuple, list, np.ndarray)):
        return "[" + ", ".join(format_value(key, v) for v in value) + "]"
    if not _is_number(value):
        return str(value)
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    v = float(value)
    if not math.isfinite(v):
        return "\u2013" if math.isnan(v) else str(v)
    k = key.lower()
    if "_std" in k or k.startswith("std"):  # a standard deviation: 2 significant digits
        return f"{v:.2g}"
    if k.endswith("_hz"):
        return f"{v:.4f}" if abs(v) < 100 else f"{v:.2f}"
    if k.endswith("percent"):
        return f"{v:+.2f}" if any(w in k for w in _SIGNED) else f"{v:.2f}"
    if any(m in k.split("_") for m in ("mac", "comac", "mpc", "frac")):
        return f"{v:.3f}"
    if k.endswith("_deg"):
        return f"{v:.1f}"
    if v != 0 and (abs(v) >= 1e5 or abs(v) < 1e-3):
        return f"{v:.4e}"
    return f"{v:.4g}"


def _header(key: str) -> str:
    for suffix, unit in _UNITS:
        if key.endswith(suffix):
            return key[: -len(suffix)].replace("_", " ") + unit
    return key.replace("_", " ")


def table_html(rows: list[dict], caption: str | None = None) -> str:
    """Rows of dicts as an escaped HTML table; columns in first-seen key order."""
    if not rows:
        return ""
    cols = _columns(rows)
    out = ["<table>"]
    if caption:
        out.append(f"<caption>{_esc(caption)}</caption>")
    out.append("<tr>" + "".join(f"<th>{_esc(_header(c))}</th>" for c in cols) + "</tr>")
    for r in rows:
        cells = []
        for c in cols:
            v = r.get(c)
            cls = ' class="num"' if _is_number(v) else ""
            cells.append(f"<td{cls}>{_esc(format_value(c, v))}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


class _Page:
    """Accumulates the HTML of one report: numbered plot divs, plotly.js in the first only."""

    def __init__(self):
        self.parts: list[str] = []
        self.n_figures = 0
        self.nav: list[tuple[str, str]] = []

    def add(self, text: str) -> None:
        self.parts.append(text)

    def section(self, anchor: str, title: str) -> None:
        self.nav.append((anchor, title))
        self.add(f'<section id="{_esc(anchor)}"><h2>{_esc(title)}</h2>')

    def end(self) -> None:
        self.add("</section>")

    def figure(self, fig) -> None:
        if fig is None:
            return
        self.n_figures += 1
        div = fig.to_html(full_html=False, include_plotlyjs=self.n_figures == 1, div_id=f"plot{self.n_figures}",
                          config={"displaylogo": False, "responsive": True}, auto_play=False)
        self.add(f'<div class="plot">{div}</div>')


def _save_png(maker, args, figs_dir: Path | None, name: str, written: list[Path]) -> None:
    if figs_dir is None:
        return
    from . import figures

    fig = maker(*args)
    if fig is not None:
        written.append(figures.save(fig, figs_dir / f"{name}.png"))


def _csv(rows: list[dict], path: Path) -> Path:
    """A report table as CSV, numbers rounded to what they support (flexgvt.workflow.outputs.round_rows)."""
    from ..workflow.outputs import round_rows

    return write_csv(round_rows(rows), path)


def _table(page: _Page, rows: list[dict], tabs_dir, name: str, written: list[Path], fold: str = "") -> None:
    """A table (folded under ``fold`` when it has more than 12 rows) and its CSV."""
    if fold and len(rows) > 12:
        page.add(f"<details><summary>{_esc(fold)} ({len(rows)} rows)</summary>{table_html(rows)}</details>")
    else:
        page.add(table_html(rows))
    if tabs_dir is not None and rows:
        written.append(_csv(rows, tabs_dir / f"{name}.csv"))


def _configuration(page: _Page, sec: ConfigurationSection, slug: str, figs_dir, tabs_dir, written) -> None:
    from . import figures, interactive

    check = sec.role == "check"
    page.section(f"cfg-{slug}", f"Configuration: {sec.name}" + (" (check: not used in updating)" if check else ""))
    for title, rows in sec.setup.items():
        if rows:
            page.add(f"<h3>Test set-up: {_esc(title)}</h3>")
            _table(page, rows, tabs_dir, f"{slug}_setup_{_slug(title, set())}", written, fold=f"show the {title}")
    page.add("<h3>Static deformed shape</h3>")
    page.figure(interactive.deformed_shape(sec))
    _save_png(figures.deformed_shape, (sec,), figs_dir, f"{slug}_deformed", written)
    if sec.stabilisation is not None:
        page.add("<h3>Stabilisation diagram</h3>")
        title = f"{sec.name}: stabilisation diagram"
        page.figure(interactive.stabilisation(sec.stabilisation, title))
        _save_png(figures.stabilisation, (sec.stabilisation, title), figs_dir, f"{slug}_stabilisation", written)
    if sec.test_modes:
        page.add("<h3>Test modes</h3><p class=\"note\">Identified modes with their standard deviations where "
                 "known; MPC (modal phase collinearity, 1 for a real normal mode) and MPD (mean phase deviation, "
                 "0 deg for a real mode) measure how complex each measured shape is.</p>")
        _table(page, sec.test_modes, tabs_dir, f"{slug}_test_modes", written)
    if sec.frfs:
        page.add("<h3>Measured and synthesised FRFs</h3><p class=\"note\">Per reference: the measured FRFs "
                 "against those synthesised from the identified modes (residues fitted by least squares, with "
                 "lower and upper residual terms for the modes outside the band), and the mode indicator "
                 "function (MIF, dips at the modes the reference excites). FRAC: the correlation of a "
                 "synthesised FRF with the measured one over the band (1 = the same curve); a low FRAC where "
                 "the synthesis misses a peak points at a mode the identification did not find.</p>")
        _save_png(figures.frf_comparison, (sec.frfs, sec.name), figs_dir, f"{slug}_frfs", written)
        for comp in sec.frfs:
            page.figure(interactive.frf_comparison(comp, sec.name))
            if comp.fit:
                _table(page, comp.fit, tabs_dir, f"{slug}_frf_fit_{_slug(comp.reference, set())}", written)
    if sec.auto_mac is not None:
        page.add("<h3>Auto-MAC of the test modes</h3><p class=\"note\">Off-diagonal values near 1 flag test "
                 "modes the sensors cannot tell apart (spatial aliasing, too few or badly placed sensors).</p>")
        page.figure(interactive.auto_mac(sec))
        _save_png(figures.auto_mac, (sec,), figs_dir, f"{slug}_auto_mac", written)
    if sec.mac_initial is not None or sec.mac_updated is not None:
        page.add("<h3>MAC matrices</h3>")
        page.figure(interactive.mac_matrices(sec))
        _save_png(figures.mac_matrices, (sec,), figs_dir, f"{slug}_mac", written)
    if sec.comac:
        page.add("<h3>COMAC per sensor</h3><p class=\"note\">Coordinate MAC of each sensor DOF over the paired "
                 "modes (updated model): a low value points at a sensor in the wrong place or direction, or a "
                 "region the model gets wrong. Table: tables/" + _esc(slug) + "_comac.csv.</p>")
        page.figure(interactive.comac(sec.comac, sec.name))
        _save_png(figures.comac, (sec.comac, sec.name), figs_dir, f"{slug}_comac", written)
        if tabs_dir is not None:
            written.append(_csv(sec.comac, tabs_dir / f"{slug}_comac.csv"))
    if sec.frequency_table:
        page.add("<h3>Frequencies and damping</h3>")
        if any("model_damping_percent" in r for r in sec.frequency_table):
            page.add("<p class=\"note\">model damping: the damping ratio of the paired mode of the updated model "
                     "from the dampers it carries (suspension cords, springs); the model has no structural "
                     "damping, so this is the suspension's share of the measured damping.</p>")
        if any("LOCAL" in str(r.get("label", "")) for r in sec.frequency_table):
            page.add("<p class=\"note\">LOCAL: a mode whose energy is mostly local (panel) deformation of the "
                     "cross-sections (a skin bay's own bending, as after buckling), not global bending (OOP, IP) "
                     "or torsion (T); a second class after a slash holds over 30 % of the energy.</p>")
        title = f"{sec.name}: frequency errors before and after updating"
        page.figure(interactive.frequency_errors(sec.frequency_table, title))
        _save_png(figures.frequency_errors, (sec.frequency_table, title), figs_dir, f"{slug}_frequency_errors",
                  written)
        _table(page, sec.frequency_table, tabs_dir, f"{slug}_frequencies", written)
    if sec.notes:
        page.add("<ul>" + "".join(f"<li>{_esc(n)}</li>" for n in sec.notes) + "</ul>")
    if sec.modes:
        page.add("<h3>Mode shapes</h3><p class=\"note\">Pick a mode in the menu to play it; the "
                 "analytical shape (blue) oscillates about the deformed geometry (grey), the measured "
                 "points (red) move with the measured shape scaled to it. Drag to rotate.</p>")
        page.figure(interactive.mode_animation(sec))
    page.end()


def _stage(page: _Page, stage, k: int, n: int, slug: str, figs_dir, tabs_dir, written) -> None:
    """A stage of a staged updating: its summary, fixed inputs, variables and frequency tables."""
    from . import figures, interactive

    page.section(slug, f"Stage {k + 1} of {n}: {stage.name}")
    if stage.summary:
        rows = "".join(f"<tr><th>{_esc(a)}</th><td>{_esc(b)}</td></tr>" for a, b in stage.summary)
        page.add(f'<table class="summary">{rows}</table>')
    if stage.fixed:
        page.add("<h3>Fixed inputs</h3><p class=\"note\">Set before the stage updates (component tests): the "
                 "mean of each variable's targets becomes the value.</p>")
        _table(page, stage.fixed, tabs_dir, f"{slug}_fixed_inputs", written)
    if stage.variables:
        page.add("<h3>Design variables</h3><p class=\"note\">initial: the value the stage started from (the "
                 "previous stage's answer); bounds: normalised about it.</p>")
        _table(page, stage.variables, tabs_dir, f"{slug}_variables", written)
    if stage.mass:
        page.add("<h3>Mass properties</h3>")
        _table(page, stage.mass, tabs_dir, f"{slug}_mass_properties", written)
    for name, rows in stage.frequencies.items():
        page.add(f"<h3>Frequencies: {_esc(name)}</h3>")
        title = f"stage {k + 1} ({stage.name}), {name}: frequency errors before and after"
        page.figure(interactive.frequency_errors(rows, title))
        _save_png(figures.frequency_errors, (rows, title), figs_dir, f"{slug}_{_slug(name, set())}_frequency_errors",
                  written)
        _table(page, rows, tabs_dir, f"{slug}_{_slug(name, set())}_frequencies", written)
    if stage.notes:
        page.add("<ul>" + "".join(f"<li>{_esc(t)}</li>" for t in stage.notes) + "</ul>")
    page.end()


def render(content: ReportContent, figs_dir: Path | None = None, tabs_dir: Path | None = None,
           written: list[Path] | None = None) -> str:
    """The report as one HTML string; PNG figures and CSV tables into figs_dir/tabs_dir when given."""
    from . import figures, interactive

    written = [] if written is None else written
    page = _Page()
    if content.summary:
        page.section("summary", "Summary")
        rows = "".join(f"<tr><th>{_esc(k)}</th><td>{_esc(v)}</td></tr>" for k, v in content.summary)
        page.add(f'<table class="summary">{rows}</table>')
        page.end()
    taken: set[str] = set()
    for k, stage in enumerate(content.stages):
        _stage(page, stage, k, len(content.stages), _slug(f"stage-{k + 1}-{stage.name}", taken), figs_dir, tabs_dir,
               written)
    for sec in content.configurations:
        _configuration(page, sec, _slug(sec.name, taken), figs_dir, tabs_dir, written)
    if content.variables:
        page.section("variables", content.variables_title)
        page.figure(interactive.design_variables(content.variables))
        _save_png(figures.design_variables, (content.variables,), figs_dir, "design_variables", written)
        _table(page, content.variables, tabs_dir, "design_variables", written)
        page.end()
    if content.history:
        page.section("history", content.history_title)
        page.figure(interactive.history(content.history))
        _save_png(figures.history, (content.history,), figs_dir, "history", written)
        page.end()
    if content.load_evolution is not None and len(content.load_evolution["load_factors"]):
        page.section("load", "Frequencies versus load")
        page.figure(interactive.load_evolution(content.load_evolution))
        _save_png(figures.load_evolution, (content.load_evolution,), figs_dir, "frequency_vs_load", written)
        page.end()
    if content.prediction:
        page.section("prediction", content.prediction_title)
        _table(page, content.prediction, tabs_dir, "prediction", written)
        taken: set[str] = set()
        for name, rows in content.prediction_modes.items():
            page.add(table_html(rows, caption=f"{name}: every mode"))
            if tabs_dir is not None:
                written.append(write_csv(rows, tabs_dir / f"prediction_modes_{_slug(name, taken)}.csv"))
        page.end()
    if content.notes:
        page.section("notes", "Notes")
        page.add("<ul>" + "".join(f"<li>{_esc(n)}</li>" for n in content.notes) + "</ul>")
        page.end()
    nav = " ".join(f'<a href="#{_esc(a)}">{_esc(t)}</a>' for a, t in page.nav)
    stamp = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    return "\n".join([
        "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_esc(content.title)}</title>", f"<style>{CSS}</style></head><body>",
        f'<header><h1>{_esc(content.title)}</h1><div class="stamp">flexgvt report, {stamp}</div></header>',
        f"<nav>{nav}</nav>", "<main>", *page.parts, "</main></body></html>",
    ])


def write_report(content: ReportContent, out_dir: str | Path, name: str = "report.html",
                 figures: bool = True, tables: bool = True) -> Path:
    """Write `name` (self-contained HTML), figures/*.png (when figures) and tables/*.csv (when
    tables) into out_dir (created); return the path of the HTML file."""
    if not isinstance(content, ReportContent):
        raise ReportError(f"write_report takes a ReportContent, got {type(content).__name__}")
    out = Path(out_dir)
    figs_dir, tabs_dir = out / "figures", out / "tables"
    try:
        out.mkdir(parents=True, exist_ok=True)
        if figures:
            figs_dir.mkdir(exist_ok=True)
        if tables:
            tabs_dir.mkdir(exist_ok=True)
    except OSError as exc:
        raise ReportError(f"cannot create the report folder {out}: {exc}; choose a writable --out") from exc
    text = render(content, figs_dir if figures else None, tabs_dir if tables else None)
    path = out / name
    path.write_text(text, encoding="utf-8")
    return path
