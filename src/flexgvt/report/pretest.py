"""The pre-test report of a plan (flexgvt.workflow.plan.PlanResult): one self-contained HTML page,
pretest.html, beside the plan's CSV tables and JSON.

    from flexgvt.report.pretest import write_pretest_report
    write_pretest_report(result)                 # result.output / "pretest.html"

Per configuration: the candidate suspensions ranked, with a frequency map (suspension modes
against the elastic modes, log scale); the target modes of the configuration as it will be
tested; the chosen sensors and the best driving points on the deformed structure (3D); the chosen
set's auto-MAC; notes. Units: m, Hz, %.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

import numpy as np

from ..errors import ReportError
from .html import CSS, _Page, _esc, _slug, table_html
from .interactive import _go, _layout, _scene, _wire

_SHOWN = ("rank", "suspension", "acceptable", "highest_suspension_hz", "first_elastic_hz", "separation",
          "first_elastic_shift_percent", "largest_elastic_shift_percent", "contaminated", "problems")


def frequency_map(plan):
    """Per candidate suspension (rows, best at the top): its suspension modes (orange) and the
    hung structure's elastic modes (blue) on a log frequency axis [Hz]."""
    go = _go()
    rows = [r for r in plan.layouts if r.modes is not None]
    if not rows:
        return None
    fig = go.Figure()
    names = [f"{k + 1}. {r.name}" for k, r in enumerate(rows)]
    for kind, color, symbol in (("suspension", "#e07b00", "diamond"), ("elastic", "#1f5fbf", "circle")):
        xs, ys, text = [], [], []
        for name, r in zip(names, rows):
            m = r.modes
            pick = m.energy_fractions[:, 4] > 0.5 if kind == "suspension" else (m.energy_fractions[:, 4] <= 0.5) & (
                m.frequencies_hz > 0)
            f = m.frequencies_hz[pick]
            labels = np.asarray(m.labels if m.labels else [""] * m.n_modes)[pick]
            xs += f.tolist()
            ys += [_esc(name)] * len(f)
            text += [f"{_esc(lab)}: {v:.4g} Hz" for lab, v in zip(labels, f)]
        fig.add_trace(go.Scatter(x=xs, y=ys, mode="markers", name=f"{kind} modes", text=text,
                                 hovertemplate="%{text}<extra></extra>",
                                 marker=dict(color=color, size=10, symbol=symbol, line=dict(width=0.5, color="#333"))))
    fig.update_xaxes(type="log", title="frequency [Hz]")
    fig.update_yaxes(autorange="reversed", automargin=True)
    _layout(fig, f"{plan.name}: candidate suspensions, suspension modes against elastic modes",
            min(160 + 34 * len(rows), 900), legend=dict(orientation="h", y=-0.15))
    return fig


def sensor_view(plan, model):
    """The deformed structure of the tested configuration (undeformed dashed) with the chosen
    sensors (red, a short line along each sensor's direction) and the best driving points (green)."""
    go = _go()
    edges = [model.index_of(g.nodes) for g in model.beams]
    edges = np.concatenate(edges) if edges else np.zeros((0, 2), int)
    xyz0, xyz = np.asarray(model.xyz, float), np.asarray(plan.state.positions, float)
    index = {int(n): k for k, n in enumerate(plan.modes.node_ids)}
    span = float(np.ptp(np.vstack([xyz0, xyz]), axis=0).max()) or 1.0
    traces = [_wire(go, xyz0, edges, "undeformed", "#999999", 3, "dash"),
              _wire(go, xyz, edges, f"deformed ({plan.tested})", "#1f5fbf", 5)]
    sensors = [(int(x.node), np.asarray(x.direction, float), x.name) for x in plan.sensors]
    exciters = [(e["node"], _vector(e["direction"]), f"{e['rank']}. {e['name']}") for e in plan.exciters]
    for items, name, color, symbol in ((sensors, "sensors", "#d62728", "circle"),
                                       (exciters, "driving points", "#2ca02c", "diamond")):
        pts, seg, text = [], [[], [], []], []
        for node, d, label in items:
            k = index[node]
            d = plan.state.rotations[k] @ d  # the sensor turns with the deformed structure
            p = xyz[k]
            pts.append(p)
            q = p + 0.04 * span * d
            for c in range(3):
                seg[c] += [float(p[c]), float(q[c]), None]
            text.append(_esc(label))
        if not pts:
            continue
        pts = np.asarray(pts)
        traces.append(go.Scatter3d(x=pts[:, 0], y=pts[:, 1], z=pts[:, 2], mode="markers", name=name, text=text,
                                   hovertemplate="%{text}<extra></extra>",
                                   marker=dict(size=5 if symbol == "circle" else 7, color=color, symbol=symbol)))
        traces.append(go.Scatter3d(x=seg[0], y=seg[1], z=seg[2], mode="lines", showlegend=False, hoverinfo="skip",
                                   line=dict(color=color, width=5)))
    fig = go.Figure(traces)
    _layout(fig, f"{plan.name}: sensors and driving points on the deformed structure", 520,
            scene=_scene(np.vstack([xyz0, xyz])), legend=dict(x=0.01, y=0.95))
    return fig


def _vector(axis: str) -> np.ndarray:
    """'+Z' -> (0, 0, 1)."""
    return np.eye(3)["XYZ".index(axis[-1])] * (-1.0 if axis.startswith("-") else 1.0)


def auto_mac(plan):
    """Heatmap of the target modes' auto-MAC at the chosen sensors."""
    go = _go()
    a = np.asarray(plan.auto_mac)
    if a.size == 0:
        return None
    labels = [_esc(r["label"] or f"mode {r['mode']}") for r in plan.target_rows()]
    fig = go.Figure(go.Heatmap(z=a, x=list(range(len(labels))), y=list(range(len(labels))), zmin=0, zmax=1,
                               colorscale="Blues", texttemplate="%{z:.2f}", textfont=dict(size=10),
                               hovertemplate="%{y} / %{x}: MAC %{z:.3f}<extra></extra>"))
    fig.update_xaxes(tickvals=list(range(len(labels))), ticktext=labels)
    fig.update_yaxes(tickvals=list(range(len(labels))), ticktext=labels, autorange="reversed")
    _layout(fig, f"{plan.name}: auto-MAC at the {len(plan.sensors)} sensors (off-diagonal max "
            f"{plan.auto_mac_max:.2f})", min(300 + 28 * max(len(labels), 4), 800), width=640)
    return fig


def render_pretest(result) -> str:
    """The pre-test page of ``result`` (a PlanResult) as one HTML string."""
    s, project = result.settings, result.project
    page = _Page()
    page.section("summary", "Summary")
    spec = project.spec
    source = spec.model.bdf or f"built-in case {spec.model.case}"
    model = f"{project.model.name} ({source}; {project.model.n_nodes} nodes)"
    band = f" in {s.band_hz[0]:g}-{s.band_hz[1]:g} Hz" if s.band_hz else ""
    summary = [("project", spec.project.name), ("project file", str(project.path)), ("model", model),
               ("configurations planned", ", ".join(result.configurations)),
               ("target modes", f"{s.n_modes} lowest elastic{band}"),
               ("sensors", f"{s.sensors} of {s.directions} at {len(s.sensor_nodes) or 'every'} candidate node(s), "
                "by effective independence"),
               ("candidate suspensions", f"{len(s.stations)} station(s) x {len(s.stiffness)} rate(s) x "
                f"{len(s.length)} cord length(s)" if s.stations else "none in [plan] (the configurations' own)")]
    for name, p in result.configurations.items():
        text = f"tested on {p.tested}; {len(p.targets)} target modes; auto-MAC max {p.auto_mac_max:.2f}"
        if p.exciters:
            best = p.exciters[0]
            text += f"; best driving point {best['name']} (weakest {best['weakest_mode']}, {best['min_residue']:.2f})"
        summary.append((name, text))
    rows = "".join(f"<tr><th>{_esc(k)}</th><td>{_esc(v)}</td></tr>" for k, v in summary)
    page.add(f'<table class="summary">{rows}</table>')
    page.add('<p class="note">Separation: the hung structure\'s first elastic frequency over its highest suspension '
             "frequency. Shifts: each elastic mode of the hung test against the free-free structure (same masses, "
             "gravity removed). Driving-point residues are normalised per mode by the best candidate (1: the best "
             "point for that mode, 0: a node line of it); the exciters are ranked by their weakest mode.</p>")
    page.end()
    taken: set[str] = set()
    for name, p in result.configurations.items():
        slug = _slug(name, taken)
        page.section(f"cfg-{slug}", f"Configuration: {name}")
        if p.layouts:
            page.add("<h3>Candidate suspensions, best first</h3>")
            page.figure(frequency_map(p))
            page.add(table_html([{k: r[k] for k in _SHOWN} for r in p.layout_rows()]))
        page.add(f"<h3>Target modes (tested on {_esc(p.tested)})</h3>")
        page.add(table_html(p.target_rows()))
        page.add("<h3>Sensors and driving points</h3>")
        page.figure(sensor_view(p, project.model))
        page.figure(auto_mac(p))
        page.add(table_html(p.sensor_rows(), caption=f"{len(p.sensors)} sensors by effective independence"))
        page.add(table_html([{k: v for k, v in r.items() if k != "residues"} for r in p.exciters],
                            caption="driving points, best first (smallest normalised residue over the target modes)"))
        if p.notes:
            page.add("<h3>Notes</h3><ul>" + "".join(f"<li>{_esc(n)}</li>" for n in p.notes) + "</ul>")
        page.end()
    files = [Path(f).name for f in result.files.values()]
    page.section("files", "Tables")
    page.add(f'<p class="note">Beside this page: {_esc(", ".join(files))}.</p>')
    page.end()
    nav = " ".join(f'<a href="#{_esc(a)}">{_esc(t)}</a>' for a, t in page.nav)
    stamp = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    title = f"Pre-test plan: {spec.project.name}"
    return "\n".join([
        "<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_esc(title)}</title>", f"<style>{CSS}</style></head><body>",
        f'<header><h1>{_esc(title)}</h1><div class="stamp">flexgvt pre-test report, {stamp}</div></header>',
        f"<nav>{nav}</nav>", "<main>", *page.parts, "</main></body></html>"])


def write_pretest_report(result, out_dir: str | Path | None = None, name: str = "pretest.html") -> Path:
    """Write the pre-test page of ``result`` into ``out_dir`` (default: the plan's output folder)."""
    out = Path(out_dir) if out_dir is not None else Path(result.output)
    try:
        out.mkdir(parents=True, exist_ok=True)
        path = out / name
        path.write_text(render_pretest(result), encoding="utf-8")
    except OSError as exc:
        raise ReportError(f"cannot write the pre-test report into {out}: {exc.strerror}; choose a writable --out") \
            from None
    return path
