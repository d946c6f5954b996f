"""Interactive plotly figures of the HTML report, built from the plain data of report.content.

Every function returns a `plotly.graph_objects.Figure` (or None when there is nothing to draw);
html.write_report embeds them. Text shown by plotly is HTML-escaped here, because plotly
interprets a subset of HTML in labels. Units: m, Hz, %.
"""

from __future__ import annotations

import html as _html
import math

import numpy as np

from .content import ConfigurationSection, Geometry, ModeShape, StabilisationData

FRAMES_PER_CYCLE = 16
FRAME_MS = 50
CYCLES = 25  # cycles played when a mode is picked in the dropdown (about 20 s)
_FONT = dict(family="Helvetica, Arial, sans-serif", size=12)
# orthographic view from aft-left-above (x aft, y span, z up)
_CAMERA = dict(eye=dict(x=1.5, y=-1.7, z=1.0), projection=dict(type="orthographic"))


def _go():
    import plotly.graph_objects as go

    return go


def _esc(text) -> str:
    return _html.escape(str(text), quote=False)


def _layout(fig, title: str, height: int, **kwargs) -> None:
    fig.update_layout(title=dict(text=_esc(title), x=0.01, font=dict(size=15)), height=height,
                      template="plotly_white", font=_FONT, margin=dict(l=60, r=30, t=60, b=50), **kwargs)


def _segments(xyz: np.ndarray, edges: np.ndarray) -> tuple[list, list, list]:
    """x, y, z lists of a wireframe, one segment per edge separated by None (a gap); coordinates
    rounded to 1e-6 of the extent (they are written as JSON text, once per animation frame)."""
    ext = float(np.ptp(xyz, axis=0).max()) if len(xyz) > 1 else 0.0
    if ext > 0:
        xyz = np.round(xyz, max(0, int(np.ceil(-np.log10(ext * 1e-6)))))
    if len(edges) == 0:
        return xyz[:, 0].tolist(), xyz[:, 1].tolist(), xyz[:, 2].tolist()
    pts = np.full((len(edges), 3, 3), np.nan)
    pts[:, 0], pts[:, 1] = xyz[edges[:, 0]], xyz[edges[:, 1]]
    flat = pts.reshape(-1, 3)
    out = []
    for k in range(3):
        col = flat[:, k].tolist()
        out.append([None if math.isnan(v) else v for v in col])
    return out[0], out[1], out[2]


def _wire(go, geom_xyz, edges, name, color, width=4, dash=None, markers=False, **kw):
    x, y, z = _segments(geom_xyz, edges)
    mode = "lines+markers" if markers else "lines"
    return go.Scatter3d(x=x, y=y, z=z, mode=mode, name=_esc(name),
                        line=dict(color=color, width=width, dash=dash),
                        marker=dict(size=2, color=color), hoverinfo="skip" if not markers else None, **kw)


def _fit(ratio: np.ndarray, max_width: float = 2.7, max_height: float = 1.7) -> np.ndarray:
    """Scale a scene aspect ratio so the box, seen orthographically from _CAMERA, fits the plot.

    In plotly's orthographic projection the aspect ratio sets the zoom: one unit takes about half
    the scene height in pixels; the limits keep the box within the height and a width/height of
    about 1.5 (scenes are wider on a desktop page)."""
    eye = np.array([_CAMERA["eye"][k] for k in "xyz"])
    e = eye / np.linalg.norm(eye)
    up = np.array([0.0, 0.0, 1.0]) - e[2] * e
    up /= np.linalg.norm(up)
    right = np.cross(up, e)
    corners = np.array([[i, j, k] for i in (-0.5, 0.5) for j in (-0.5, 0.5) for k in (-0.5, 0.5)]) * ratio
    w, h = np.ptp(corners @ right), np.ptp(corners @ up)
    return ratio * min(max_width / max(w, 1e-12), max_height / max(h, 1e-12))


def _scene(xyz_all: np.ndarray, pad: float = 0.05) -> dict:
    """Orthographic scene with equal scales on x, y, z: fixed ranges padded around xyz_all (n, 3)
    [m] (steady during animations) and the aspect ratio of the ranges, zoomed to fit."""
    axes = dict(xaxis=dict(title="x [m]"), yaxis=dict(title="y [m]"), zaxis=dict(title="z [m]"))
    lo, hi = xyz_all.min(axis=0), xyz_all.max(axis=0)
    span = max(float((hi - lo).max()), 1e-12)
    lo, hi = lo - pad * span, hi + pad * span
    ranges = hi - lo
    ratio = _fit(ranges / ranges.max())
    for k, ax in enumerate(("xaxis", "yaxis", "zaxis")):
        axes[ax]["range"] = [float(lo[k]), float(hi[k])]
        axes[ax]["autorange"] = False
    return dict(aspectmode="manual", aspectratio=dict(x=ratio[0], y=ratio[1], z=ratio[2]), camera=_CAMERA, **axes)


def deformed_shape(section: ConfigurationSection):
    """3D undeformed (grey, dashed) and deformed (blue) wireframes, equal scales [m]."""
    go = _go()
    fig = go.Figure([
        _wire(go, section.undeformed.xyz, section.undeformed.edges, "undeformed", "#999999", 3, "dash"),
        _wire(go, section.deformed.xyz, section.deformed.edges, "deformed", "#1f5fbf", 5, markers=True),
    ])
    both = np.vstack([section.undeformed.xyz, section.deformed.xyz])
    _layout(fig, f"{section.name}: static deformed shape", 520, scene=_scene(both),
            legend=dict(x=0.01, y=0.95))
    return fig


def stabilisation(data: StabilisationData, title: str = "Stabilisation diagram"):
    """Poles by model order (stable filled, others open grey), selected modes as red dashed lines,
    the mode indicator on a secondary log axis."""
    go = _go()
    f = data.frequencies_hz
    lo, hi = (float(f.min()), float(f.max())) if len(f) else (0.0, float(data.poles_hz.max(initial=1.0)))
    inside = (data.poles_hz >= lo) & (data.poles_hz <= hi)
    traces = []
    for ok, name, sym, color, size in ((False, "not stable", "circle-open", "#aaaaaa", 5),
                                       (True, "stable", "circle", "#1f5fbf", 6)):
        m = inside & (data.stable == ok)
        traces.append(go.Scatter(x=data.poles_hz[m], y=data.orders[m], mode="markers", name=name,
                                 marker=dict(symbol=sym, color=color, size=size),
                                 hovertemplate="%{x:.4g} Hz, order %{y}<extra></extra>"))
    if len(f):
        ind = np.where(data.indicator > 0, data.indicator, np.nan)
        traces.append(go.Scatter(x=f, y=ind, yaxis="y2", mode="lines", name="indicator",
                                 line=dict(color="#333333", width=1), hoverinfo="skip"))
    fig = go.Figure(traces)
    shapes = [dict(type="line", xref="x", yref="paper", x0=float(s), x1=float(s), y0=0, y1=1,
                   line=dict(color="#d62728", dash="dash", width=1)) for s in data.selected_hz]
    if len(data.selected_hz):  # legend entry for the selected lines
        fig.add_trace(go.Scatter(x=[None], y=[None], mode="lines", name="selected",
                                 line=dict(color="#d62728", dash="dash")))
    _layout(fig, title, 460, shapes=shapes, xaxis=dict(title="frequency [Hz]", range=[lo, hi]),
            yaxis=dict(title="model order", rangemode="tozero"),
            yaxis2=dict(title="indicator", type="log", overlaying="y", side="right", showgrid=False,
                        dtick=1, tickformat="~g", automargin=True),
            legend=dict(orientation="h", y=-0.18))
    fig.update_layout(margin=dict(r=80))
    return fig


def mac_matrices(section: ConfigurationSection):
    """Heatmaps of the initial and updated MAC (test modes in rows, FE modes in columns)."""
    go = _go()
    from plotly.subplots import make_subplots

    mats = [(t, m) for t, m in (("initial", section.mac_initial), ("updated", section.mac_updated))
            if m is not None]
    if not mats:
        return None
    rows, cols = [_esc(s) for s in section.measured_labels], [_esc(s) for s in section.analytical_labels]
    fig = make_subplots(1, len(mats), subplot_titles=[f"MAC {t}" for t, _ in mats], horizontal_spacing=0.12)
    for k, (t, m) in enumerate(mats):
        fig.add_trace(go.Heatmap(z=m, x=list(range(len(cols))), y=list(range(len(rows))), zmin=0, zmax=1,
                                 colorscale="Blues", texttemplate="%{z:.2f}", textfont=dict(size=10),
                                 showscale=k == len(mats) - 1, name=t,
                                 hovertemplate="test %{y}, FE %{x}: MAC %{z:.3f}<extra></extra>"), 1, k + 1)
        fig.update_xaxes(tickvals=list(range(len(cols))), ticktext=cols, title="FE mode", row=1, col=k + 1)
        fig.update_yaxes(tickvals=list(range(len(rows))), ticktext=rows, autorange="reversed",
                         row=1, col=k + 1, title="test mode" if k == 0 else None)
    n = max(len(rows), 4)
    _layout(fig, f"{section.name}: MAC matrices", min(300 + 28 * n, 900))
    return fig


def frequency_errors(rows: list[dict], title: str):
    """Grouped bars of the initial and updated frequency errors [%] per mode."""
    go = _go()
    keys = [("initial_error_percent", "initial", "#aaaaaa"), ("updated_error_percent", "updated", "#1f5fbf")]
    labels = [_esc(r.get("label") or r.get("mode", i + 1)) for i, r in enumerate(rows)]
    traces = []
    for key, name, color in keys:
        vals = [r.get(key) for r in rows]
        if any(v is not None for v in vals):
            traces.append(go.Bar(x=list(range(len(rows))), y=[np.nan if v is None else float(v) for v in vals],
                                 name=name, marker_color=color,
                                 hovertemplate="%{y:.2f} %<extra>" + name + "</extra>"))
    if not traces:
        return None
    fig = go.Figure(traces)
    _layout(fig, title, 400, barmode="group",
            xaxis=dict(tickvals=list(range(len(rows))), ticktext=labels, title="mode"),
            yaxis=dict(title="frequency error [%]", zeroline=True, zerolinecolor="#444"),
            legend=dict(orientation="h", y=1.08, x=0.99, xanchor="right"))
    return fig


def _mode_scale(mode: ModeShape, deformed: Geometry, amplitude: float):
    """Analytical and measured displacements scaled for display: analytical largest = amplitude [m];
    measured by the least-squares factor against the analytical shape at the nearest nodes."""
    d = mode.displacement
    peak = float(np.linalg.norm(d, axis=1).max(initial=0.0))
    a = d * (amplitude / peak) if peak > 0 else d * 0.0
    if mode.measured_xyz is None:
        return a, None
    m = mode.measured_displacement
    near = np.argmin(((mode.measured_xyz[:, None, :] - deformed.xyz[None, :, :]) ** 2).sum(-1), axis=1)
    mm = float((m * m).sum())
    msf = float((a[near] * m).sum()) / mm if mm > 0 else 0.0
    mpeak = float(np.linalg.norm(m, axis=1).max(initial=0.0))
    if mpeak > 0 and abs(msf) * mpeak < 0.2 * amplitude:  # uncorrelated: same peak, sign kept
        msf = np.copysign(amplitude / mpeak, msf if msf != 0 else 1.0)
    return a, m * msf


def _mode_title(section: str, k: int, mode: ModeShape) -> str:
    parts = [f"FE {mode.analytical_hz:.4g} Hz"]
    if mode.measured_hz is not None:
        parts.append(f"test {mode.measured_hz:.4g} Hz")
    if mode.mac is not None:
        parts.append(f"MAC {mode.mac:.2f}")
    return _esc(f"{section}: mode {k + 1} {mode.label} - " + ", ".join(parts))


def mode_animation(section: ConfigurationSection, amplitude_fraction: float = 0.10,
                   frames_per_cycle: int = FRAMES_PER_CYCLE):
    """Animated mode shapes of one configuration in one 3D figure: the analytical wireframe on the
    deformed geometry (blue) oscillating about it (grey), the measured points (red markers) moving
    with the measured shape. A dropdown picks and plays a mode; Pause stops. Amplitude: the given
    fraction of the geometry's span."""
    go = _go()
    if not section.modes:
        return None
    geom = section.deformed
    amp = amplitude_fraction * geom.span
    phases = np.cos(2 * np.pi * np.arange(frames_per_cycle) / frames_per_cycle)
    frames, extent, menu = [], [geom.xyz], []
    first = None
    for k, mode in enumerate(section.modes):
        a, m = _mode_scale(mode, geom, amp)
        extent += [geom.xyz + a, geom.xyz - a]
        if m is not None:
            extent += [mode.measured_xyz + m, mode.measured_xyz - m]
        title = _mode_title(section.name, k, mode)
        names = []
        for j, c in enumerate(phases):
            x, y, z = _segments(geom.xyz + c * a, geom.edges)
            wire = go.Scatter3d(x=x, y=y, z=z)
            if m is not None:
                p = mode.measured_xyz + c * m
                pts = go.Scatter3d(x=p[:, 0], y=p[:, 1], z=p[:, 2])
            else:
                pts = go.Scatter3d(x=[], y=[], z=[])
            name = f"m{k}f{j}"
            names.append(name)
            frames.append(go.Frame(name=name, data=[wire, pts], traces=[1, 2], layout=dict(title_text=title)))
            if first is None:
                first = (wire, pts, title)
        seq = names * CYCLES + names[:1]
        menu.append(dict(label=_esc(f"{k + 1}: {mode.label} ({mode.analytical_hz:.4g} Hz)"), method="animate",
                         args=[seq, dict(mode="immediate", frame=dict(duration=FRAME_MS, redraw=True),
                                         transition=dict(duration=0), fromcurrent=False)]))
    wire0, pts0, title0 = first
    data = [
        _wire(go, geom.xyz, geom.edges, "deformed (static)", "#bbbbbb", 2),
        go.Scatter3d(x=wire0.x, y=wire0.y, z=wire0.z, mode="lines", name="analytical",
                     line=dict(color="#1f5fbf", width=5), hoverinfo="skip"),
        go.Scatter3d(x=pts0.x, y=pts0.y, z=pts0.z, mode="markers", name="measured",
                     marker=dict(color="#d62728", size=4)),
    ]
    fig = go.Figure(data=data, frames=frames)
    pause = dict(label="&#10074;&#10074; Pause", method="animate",
                 args=[[None], dict(mode="immediate", frame=dict(duration=0, redraw=False),
                                    transition=dict(duration=0))])
    menus = [dict(type="dropdown", buttons=menu, x=0.01, y=1.0, xanchor="left", yanchor="top",
                  showactive=True, active=0),
             dict(type="buttons", buttons=[pause], x=0.99, y=1.0, xanchor="right", yanchor="top")]
    _layout(fig, "", 600, scene=_scene(np.vstack(extent)), updatemenus=menus,
            legend=dict(x=0.01, y=0.86))
    fig.update_layout(title=dict(text=title0, y=0.99, x=0.5, xanchor="center"), margin=dict(t=70))
    return fig


def design_variables(rows: list[dict]):
    """Bars of the design-variable changes [%] with one-sigma error bars on a readable scale, coloured
    by status (report.figures.variable_bars: clipped bars annotated with their sigma; the hover
    gives every sigma in full)."""
    go = _go()
    from .figures import STATUS_COLOURS, sigma_text, variable_bars

    if not rows:
        return None
    d = variable_bars(rows)
    names = [_esc(n) for n in d["names"]]
    x = list(range(len(rows)))
    change = [float(v) if np.isfinite(v) else 0.0 for v in d["change"]]
    sigma = [f"{v:.3g} %" if np.isfinite(v) else "none (not identifiable)" if st == "not identifiable" else "unknown"
             for v, st in zip(d["std"], d["status"])]
    traces = []
    for st, colour in STATUS_COLOURS.items():
        ks = [k for k in x if d["status"][k] == st]
        if not ks:
            continue
        traces.append(go.Bar(
            x=ks, y=[change[k] for k in ks], name=st, marker=dict(
                color=colour, line=dict(color="#555555", width=0.5),
                pattern=dict(shape="/" if st == "not identifiable" else "")),
            error_y=dict(type="data", array=[float(d["shown"][k]) for k in ks], color="#333333", thickness=1.2,
                         visible=True),
            customdata=[[names[k], sigma[k]] for k in ks],
            hovertemplate="%{customdata[0]}: %{y:.2f} % (\u03c3 %{customdata[1]})<extra>" + st + "</extra>"))
    notes = [dict(x=k, y=change[k] + float(d["shown"][k]), text=sigma_text(d["std"][k]), showarrow=False,
                  yshift=6, textangle=-90, yanchor="bottom", font=dict(size=10)) for k in np.flatnonzero(d["clipped"])]
    notes += [dict(x=k, y=max(change[k], 0.0), text="not identifiable", showarrow=False, yshift=6, textangle=-90,
                   yanchor="bottom", font=dict(size=10, color="#666666"))
              for k in x if d["status"][k] == "not identifiable"]
    fig = go.Figure(traces)
    _layout(fig, "Design-variable changes, \u00b1 one standard deviation (a \u03c3 wider than the bounds or twice "
            "the largest change is clipped and written)", 480,
            barmode="overlay", annotations=notes,
            xaxis=dict(tickvals=x, ticktext=names, tickangle=-35),
            yaxis=dict(title="change from the initial value [%]", zeroline=True, zerolinecolor="#444",
                       range=list(d["range"])),
            legend=dict(orientation="h", y=1.1, x=0.99, xanchor="right"))
    return fig


def auto_mac(section: ConfigurationSection):
    """Heatmap of the auto-MAC of the test modes."""
    go = _go()
    m = section.auto_mac
    if m is None:
        return None
    labels = [_esc(s) for s in section.measured_labels]
    idx = list(range(len(labels)))
    fig = go.Figure(go.Heatmap(z=m, x=idx, y=idx, zmin=0, zmax=1, colorscale="Blues", texttemplate="%{z:.2f}",
                               textfont=dict(size=10),
                               hovertemplate="test %{y}, test %{x}: MAC %{z:.3f}<extra></extra>"))
    fig.update_xaxes(tickvals=idx, ticktext=labels, title="test mode")
    fig.update_yaxes(tickvals=idx, ticktext=labels, autorange="reversed", title="test mode")
    _layout(fig, f"{section.name}: auto-MAC of the test modes", min(320 + 28 * max(len(idx), 4), 900),
            width=min(420 + 40 * max(len(idx), 4), 1100))
    return fig


def comac(rows: list[dict], name: str):
    """COMAC per sensor DOF (bars, below 0.8 red)."""
    go = _go()
    if not rows:
        return None
    v = [np.nan if r.get("comac") is None else float(r["comac"]) for r in rows]
    labels = [_esc(r.get("sensor", k + 1)) for k, r in enumerate(rows)]
    fig = go.Figure(go.Bar(x=list(range(len(rows))), y=v, marker_color=["#d62728" if c < 0.8 else "#1f5fbf"
                                                                         for c in np.nan_to_num(v, nan=1.0)],
                           customdata=labels, hovertemplate="%{customdata}: COMAC %{y:.3f}<extra></extra>"))
    _layout(fig, f"{name}: COMAC per sensor over the paired modes (below 0.8 in red)", 380,
            xaxis=dict(tickvals=list(range(len(rows))), ticktext=labels, tickangle=-90, tickfont=dict(size=9),
                       title="sensor (test point and direction)"),
            yaxis=dict(title="COMAC", range=[0, 1.02]),
            shapes=[dict(type="line", xref="paper", x0=0, x1=1, y0=0.8, y1=0.8, line=dict(dash="dot", width=1))])
    return fig


def _round_curve(y: np.ndarray) -> list:
    """Magnitudes as JSON-light numbers (4 significant digits)."""
    return [float(f"{v:.4g}") for v in y]


def frf_comparison(comp, name: str):
    """Measured (solid) against synthesised (dashed) FRF magnitudes of one reference on a log axis,
    and its MIF below; the identified modes as dotted lines."""
    go = _go()
    from plotly.subplots import make_subplots

    has_mif = comp.mif_measured is not None
    fig = make_subplots(2 if has_mif else 1, 1, shared_xaxes=True, vertical_spacing=0.06,
                        row_heights=[0.68, 0.32] if has_mif else None)
    colours = ["#1f5fbf", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"]
    f = [float(v) for v in comp.frequencies_hz]
    for k, lab in enumerate(comp.labels):
        c = colours[k % len(colours)]
        for data, kind, dash in ((comp.measured, "measured", None), (comp.synthesised, "synthesised", "dash")):
            fig.add_trace(go.Scatter(x=f, y=_round_curve(np.abs(data[:, k])), mode="lines",
                                     name=_esc(f"{lab} {kind}"), line=dict(color=c, width=1.2, dash=dash),
                                     hovertemplate="%{x:.4g} Hz: %{y:.3g}<extra>" + _esc(kind) + "</extra>"), 1, 1)
    if has_mif:
        for data, kind, dash in ((comp.mif_measured, "MIF measured", None),
                                 (comp.mif_synthesised, "MIF synthesised", "dash")):
            if data is not None:
                fig.add_trace(go.Scatter(x=f, y=_round_curve(data), mode="lines", name=kind,
                                         line=dict(color="#333333", width=1, dash=dash)), 2, 1)
        fig.update_yaxes(title="MIF", range=[-0.02, 1.02], row=2, col=1)
        fig.update_xaxes(title="frequency [Hz]", row=2, col=1)
    else:
        fig.update_xaxes(title="frequency [Hz]", row=1, col=1)
    fig.update_yaxes(title="|H|", type="log", exponentformat="e", row=1, col=1)
    shapes = [dict(type="line", xref="x", yref="paper", x0=float(fm), x1=float(fm), y0=0, y1=1,
                   line=dict(color="#999999", dash="dot", width=1)) for fm in comp.modes_hz]
    _layout(fig, f"{name}: reference {comp.reference}, measured and synthesised FRFs", 560 if has_mif else 420,
            shapes=shapes, legend=dict(orientation="h", y=-0.12))
    return fig


def history(values: list[float]):
    """Objective per optimiser iteration (log axis when all positive)."""
    go = _go()
    if not values:
        return None
    v = np.asarray(values, float)
    fig = go.Figure(go.Scatter(x=np.arange(len(v)), y=v, mode="lines+markers", marker=dict(size=5),
                               line=dict(color="#1f5fbf"), name="objective"))
    _layout(fig, "Optimiser history", 380, xaxis=dict(title="iteration"),
            yaxis=dict(title="objective", type="log" if np.all(v > 0) else "linear"))
    return fig


def load_evolution(ev: dict | None):
    """Frequencies [Hz] versus load factor, one line per mode."""
    go = _go()
    if ev is None or len(ev["load_factors"]) == 0:
        return None
    fig = go.Figure([go.Scatter(x=ev["load_factors"], y=ev["frequencies_hz"][:, j], mode="lines+markers",
                                marker=dict(size=4), name=_esc(lab))
                     for j, lab in enumerate(ev["labels"])])
    _layout(fig, "Frequencies versus load", 440, xaxis=dict(title="load factor"),
            yaxis=dict(title="frequency [Hz]"))
    return fig
