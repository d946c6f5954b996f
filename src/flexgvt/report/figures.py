"""Static PNG figures of the report (matplotlib, object API, no pyplot state).

Each function takes the plain data of report.content and returns a `matplotlib.figure.Figure`
(or None when there is nothing to draw); `save(fig, path)` writes it. Units: m, Hz, %.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .content import ConfigurationSection, FRFComparison, StabilisationData

BLUE, GREY, RED, ORANGE, PURPLE = "#1f5fbf", "#999999", "#d62728", "#ff7f0e", "#9467bd"


def _figure(figsize):
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, layout="constrained")


def save(fig, path: Path, dpi: int = 110) -> Path:
    """Write a figure as PNG and return the path."""
    fig.savefig(path, dpi=dpi)
    return Path(path)


def _lines(xyz, edges):
    """(m, 2, 3) segments of a wireframe, or a single polyline when there are no edges."""
    if len(edges):
        return xyz[edges]
    return np.stack([xyz[:-1], xyz[1:]], axis=1)


def deformed_shape(section: ConfigurationSection):
    """3D view (equal scales) and front view (span y against z) of the undeformed (grey dashed) and
    deformed (blue) wireframes."""
    from matplotlib.collections import LineCollection
    from matplotlib.ticker import MaxNLocator
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    fig = _figure((12, 4.6))
    grid = fig.add_gridspec(1, 2, width_ratios=(1.5, 1))
    ax3 = fig.add_subplot(grid[0], projection="3d")
    front = fig.add_subplot(grid[1])
    und, dfm = section.undeformed, section.deformed
    for geom, color, style, lw, lab in ((und, GREY, "--", 1.0, "undeformed"), (dfm, BLUE, "-", 2.0, "deformed")):
        seg = _lines(geom.xyz, geom.edges)
        ax3.add_collection3d(Line3DCollection(seg, colors=color, linestyles=style, linewidths=lw, label=lab))
        front.add_collection(LineCollection(seg[:, :, [1, 2]], colors=color, linestyles=style,
                                            linewidths=lw, label=lab))
    allxyz = np.vstack([und.xyz, dfm.xyz])
    lo, hi = allxyz.min(0), allxyz.max(0)
    mid, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-9) * 1.05
    ranges = np.maximum(hi - lo, 1e-3 * 2 * half) * 1.05
    for k, setter in enumerate((ax3.set_xlim, ax3.set_ylim, ax3.set_zlim)):
        setter(mid[k] - ranges[k] / 2, mid[k] + ranges[k] / 2)
    ratio = ranges / ranges.max()
    ax3.set_box_aspect(tuple(ratio), zoom=1.3)
    for axis, r in zip((ax3.xaxis, ax3.yaxis, ax3.zaxis), ratio):  # few ticks on short axes, none on tiny
        if r < 0.15:
            axis.set_ticks([])
        else:
            axis.set_major_locator(MaxNLocator(nbins=max(2, int(round(8 * r)))))
    ax3.set_xlabel("x [m]")
    ax3.set_ylabel("y [m]", labelpad=12)
    ax3.set_zlabel("z [m]")
    ax3.view_init(elev=22, azim=-35)
    front.set_aspect("equal", adjustable="datalim")
    front.autoscale_view()
    front.set_xlabel("y (span) [m]")
    front.set_ylabel("z [m]")
    front.set_title("front view (equal scales)")
    front.grid(alpha=0.3)
    front.legend(fontsize=8)
    fig.suptitle(f"{section.name}: static deformed shape")
    return fig


def stabilisation(data: StabilisationData, title: str = "Stabilisation diagram"):
    """The stabilisation diagram (the one drawing of it: the HTML report's and `flexgvt ema
    identify`'s): poles by order (stable filled blue, others open grey), the kept clusters' poles
    ringed (strong orange, weak purple), selected modes as red dashed lines with a +-2 sigma band
    where known, and the indicator on a secondary log axis."""
    fig = _figure((9, 4.8))
    ax = fig.add_subplot()
    f = data.frequencies_hz
    if len(f):
        ax2 = ax.twinx()
        ind = np.where(data.indicator > 0, data.indicator, np.nan)
        ax2.semilogy(f, ind, color="#333333", lw=0.8)
        ax2.set_ylabel("indicator")
        ax.set_xlim(f.min(), f.max())
    ns, st = ~data.stable, data.stable
    ax.scatter(data.poles_hz[ns], data.orders[ns], s=10, facecolors="none", edgecolors=GREY, label="not stable")
    ax.scatter(data.poles_hz[st], data.orders[st], s=10, color=BLUE, label="stable")
    if len(data.ringed_hz):
        for strong, color, lab in ((True, ORANGE, "strong cluster"),
                                   (False, PURPLE, "weak cluster (narrow band of orders)")):
            pick = data.ringed_strong == strong
            if pick.any():
                ax.scatter(data.ringed_hz[pick], data.ringed_orders[pick], s=45, facecolors="none",
                           edgecolors=color, linewidths=1.0, label=lab)
    for k, s in enumerate(data.selected_hz):
        ax.axvline(s, color=RED, ls="--", lw=0.8, label="selected" if k == 0 else None)
        sd = None if data.selected_std_hz is None else data.selected_std_hz[k]
        if sd is not None and np.isfinite(sd):
            ax.axvspan(s - 2 * sd, s + 2 * sd, color=RED, alpha=0.15, lw=0)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.set_title(title)
    ax.legend(fontsize=8, loc="upper left")
    return fig


def mac_matrices(section: ConfigurationSection):
    """Initial and updated MAC matrices with their values."""
    mats = [(t, m) for t, m in (("initial", section.mac_initial), ("updated", section.mac_updated))
            if m is not None]
    if not mats:
        return None
    nr, nc = mats[0][1].shape
    w = min(max(3.2 + 0.45 * nc, 4.5), 9.0)
    fig = _figure((w * len(mats), min(max(2.5 + 0.4 * nr, 3.5), 9.0)))
    axes = fig.subplots(1, len(mats), squeeze=False)[0]
    for ax, (t, m) in zip(axes, mats):
        im = ax.imshow(m, vmin=0, vmax=1, cmap="Blues")
        for (i, j), v in np.ndenumerate(m):
            ax.text(j, i, f"{v:.2f}", ha="center", va="center", fontsize=7,
                    color="white" if v > 0.6 else "black")
        ax.set_xticks(range(nc), section.analytical_labels, rotation=45, ha="right", fontsize=8)
        ax.set_yticks(range(nr), section.measured_labels, fontsize=8)
        ax.set_xlabel("FE mode")
        ax.set_ylabel("test mode")
        ax.set_title(f"MAC {t}")
    fig.colorbar(im, ax=list(axes), shrink=0.8)
    fig.suptitle(f"{section.name}: MAC matrices")
    return fig


def frequency_errors(rows: list[dict], title: str):
    """Grouped bars of the initial and updated frequency errors [%] per mode."""
    keys = [("initial_error_percent", "initial", GREY), ("updated_error_percent", "updated", BLUE)]
    keys = [k for k in keys if any(r.get(k[0]) is not None for r in rows)]
    if not rows or not keys:
        return None
    fig = _figure((max(6.0, 0.6 * len(rows) + 2), 4))
    ax = fig.add_subplot()
    x = np.arange(len(rows))
    w = 0.8 / len(keys)
    for k, (key, name, color) in enumerate(keys):
        v = [np.nan if r.get(key) is None else float(r[key]) for r in rows]
        ax.bar(x + (k - (len(keys) - 1) / 2) * w, v, w, color=color, label=name)
    ax.set_xticks(x, [str(r.get("label") or r.get("mode", i + 1)) for i, r in enumerate(rows)],
                  rotation=30, ha="right", fontsize=8)
    ax.axhline(0, color="#444", lw=0.8)
    ax.set_ylabel("frequency error [%]")
    ax.set_title(title)
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    return fig


def variable_bars(rows: list[dict]) -> dict:
    """What the design-variable chart draws, as plain data (the PNG and the HTML figure share it).

    Per variable: name (with its unit), change [%], std [%] and the std drawn: clipped at the
    variable's bound half-range (a one-sigma band wider than the bounds says only that the data do
    not pin the variable inside them) and at twice the largest change, so one huge sigma cannot
    squash the others; clipped bars are annotated with their sigma. status: 'identifiable',
    'at bound', 'sigma > bounds' (wider than its bounds), 'sigma unknown' (identifiable, but the data
    give no standard deviation, e.g. no more residuals than variables) or 'not identifiable' (the
    data cannot see it: identifiable False). range: the change axis [%] (the bars and their
    drawn sigmas, padded)."""
    change = np.array([np.nan if r.get("change_percent") is None else float(r["change_percent"]) for r in rows])
    std = np.array([np.nan if r.get("std_percent") is None else float(r["std_percent"]) for r in rows])
    core = max(float(np.nanmax(np.abs(change), initial=0.0)), 5.0)
    status, clip, names = [], [], []
    for r, s in zip(rows, std):
        bounds = r.get("bounds")
        half = 100 * (float(bounds[1]) - float(bounds[0])) / 2 if bounds is not None and len(bounds) == 2 else np.inf
        clip.append(min(half, 2 * core))
        if r.get("identifiable") is False:
            status.append("not identifiable")
        elif not np.isfinite(s):  # e.g. no more residuals than variables and no measured standard deviations
            status.append("at bound" if r.get("at_bound") else "sigma unknown")
        elif s > half:
            status.append("sigma > bounds")
        elif r.get("at_bound"):
            status.append("at bound")
        else:
            status.append("identifiable")
        unit = r.get("unit")
        names.append(f"{r.get('name', len(names) + 1)}" + (f" [{unit}]" if unit else ""))
    clip = np.asarray(clip)
    shown = np.where(np.isfinite(std), np.minimum(std, clip), 0.0)
    clipped = np.isfinite(std) & (std > clip)
    c = np.nan_to_num(change)
    lo, hi = min(float((c - shown).min(initial=0.0)), 0.0), max(float((c + shown).max(initial=0.0)), 0.0)
    pad = 0.15 * max(hi - lo, core)
    written = 0.35 * max(hi - lo, core) if clipped.any() or "not identifiable" in status else 0.0  # room for text
    return {"names": names, "change": change, "std": std, "shown": shown, "clipped": clipped,
            "status": status, "range": (lo - pad, hi + pad + written)}


def sigma_text(v: float) -> str:
    """A standard deviation [%] as written on a clipped bar: 'σ 2434 %', 'σ 31.5 %'."""
    return f"\u03c3 {v:.0f} %" if abs(v) >= 100 else f"\u03c3 {v:.3g} %"


STATUS_COLOURS = {"identifiable": BLUE, "at bound": ORANGE, "sigma > bounds": "#8fb3e6",
                  "sigma unknown": "#c9d6e8", "not identifiable": "#bbbbbb"}


def design_variables(rows: list[dict]):
    """Bars of the design-variable changes [%] with one-sigma error bars on a readable scale
    (variable_bars: clipped bars annotated with their sigma), coloured by status."""
    if not rows:
        return None
    from matplotlib.patches import Patch

    d = variable_bars(rows)
    fig = _figure((max(6.0, 0.5 * len(rows) + 2), 4.6))
    ax = fig.add_subplot()
    x = np.arange(len(rows))
    colours = [STATUS_COLOURS[s] for s in d["status"]]
    hatches = ["//" if s == "not identifiable" else "" for s in d["status"]]
    bars = ax.bar(x, np.nan_to_num(d["change"]), color=colours, edgecolor="#555555", linewidth=0.5)
    for b, h in zip(bars, hatches):
        b.set_hatch(h)
    ok = d["shown"] > 0
    ax.errorbar(x[ok], np.nan_to_num(d["change"])[ok], yerr=d["shown"][ok], fmt="none", ecolor="#222222",
                capsize=3, lw=1)
    for k in np.flatnonzero(d["clipped"]):
        top = np.nan_to_num(d["change"][k]) + d["shown"][k]
        ax.annotate(sigma_text(d["std"][k]), (k, top), (0, 3), textcoords="offset points", ha="center",
                    va="bottom", fontsize=6.5, rotation=90, color="#222222")
    for k, st in enumerate(d["status"]):
        if st == "not identifiable":  # written upwards from the bar's top (or from 0)
            ax.annotate("not identifiable", (k, max(np.nan_to_num(d["change"][k]), 0.0)), (0, 4),
                        textcoords="offset points", ha="center", va="bottom", fontsize=6.5, rotation=90,
                        color="#666666")
    ax.set_ylim(*d["range"])
    ax.set_xticks(x, d["names"], rotation=35, ha="right", fontsize=7.5)
    ax.axhline(0, color="#444", lw=0.8)
    ax.set_ylabel("change from the initial value [%]")
    ax.set_title("Design-variable changes, \u00b1 one standard deviation\n(a \u03c3 wider than the bounds or twice "
                 "the largest change is clipped and written)", fontsize=9)
    present = [s for s in STATUS_COLOURS if s in d["status"]]
    ax.legend([Patch(facecolor=STATUS_COLOURS[s], edgecolor="#555555", hatch="//" if s == "not identifiable"
                     else "") for s in present], present, fontsize=7, loc="upper right", ncol=len(present))
    ax.grid(alpha=0.3, axis="y")
    return fig


def _heatmap(ax, m, row_labels, col_labels, title):
    im = ax.imshow(m, vmin=0, vmax=1, cmap="Blues")
    if m.size <= 400:
        for (i, j), v in np.ndenumerate(m):
            ax.text(j, i, f"{v:.2f}", ha="center", va="center", fontsize=7, color="white" if v > 0.6 else "black")
    ax.set_xticks(range(m.shape[1]), col_labels, rotation=45, ha="right", fontsize=8)
    ax.set_yticks(range(m.shape[0]), row_labels, fontsize=8)
    ax.set_title(title)
    return im


def auto_mac(section: ConfigurationSection):
    """The auto-MAC of the test modes (measured x measured) with its values."""
    m = section.auto_mac
    if m is None:
        return None
    n = m.shape[0]
    size = min(max(3.5 + 0.42 * n, 4.5), 10.0)
    fig = _figure((size + 1.0, size))
    ax = fig.add_subplot()
    labels = section.measured_labels
    im = _heatmap(ax, m, labels, labels, f"{section.name}: auto-MAC of the test modes")
    ax.set_xlabel("test mode")
    ax.set_ylabel("test mode")
    fig.colorbar(im, ax=ax, shrink=0.8, label="MAC")
    return fig


def comac(rows: list[dict], name: str):
    """COMAC per sensor DOF (bars, low values red)."""
    if not rows:
        return None
    v = np.array([np.nan if r.get("comac") is None else float(r["comac"]) for r in rows])
    fig = _figure((max(6.0, 0.16 * len(rows) + 2), 3.8))
    ax = fig.add_subplot()
    ax.bar(np.arange(len(rows)), v, color=[RED if c < 0.8 else BLUE for c in np.nan_to_num(v, nan=1.0)])
    ax.set_xticks(np.arange(len(rows)), [str(r.get("sensor", k + 1)) for k, r in enumerate(rows)], rotation=90,
                  fontsize=6.5)
    ax.axhline(0.8, color="#444", lw=0.8, ls=":")
    ax.set_ylim(0, 1.02)
    ax.set_ylabel("COMAC")
    ax.set_xlabel("sensor (test point and direction)")
    ax.set_title(f"{name}: COMAC per sensor over the paired modes (below 0.8 in red)", fontsize=10)
    ax.grid(alpha=0.3, axis="y")
    return fig


def frf_comparison(comps: list[FRFComparison], name: str):
    """Per reference (one column each): measured (solid) against synthesised (dashed) FRF magnitudes,
    and the MIF below; the identified modes as dotted lines."""
    if not comps:
        return None
    has_mif = any(c.mif_measured is not None for c in comps)
    n = len(comps)
    fig = _figure((min(6.5 * n, 16.0), 6.2 if has_mif else 4.2))
    axes = fig.subplots(2 if has_mif else 1, n, sharex=True, squeeze=False,
                        gridspec_kw=dict(height_ratios=(2, 1)) if has_mif else None)
    colours = [BLUE, RED, "#2ca02c", PURPLE, ORANGE]
    for col, comp in enumerate(comps):
        f = comp.frequencies_hz
        top = axes[0, col]
        for k, lab in enumerate(comp.labels):
            c = colours[k % len(colours)]
            top.semilogy(f, np.abs(comp.measured[:, k]), color=c, lw=1, label=f"{lab} measured")
            top.semilogy(f, np.abs(comp.synthesised[:, k]), color=c, lw=1, ls="--", label="synthesised")
        top.set_title(f"reference {comp.reference}", fontsize=10)
        top.legend(fontsize=6.5, ncol=2)
        if has_mif and comp.mif_measured is not None:
            low = axes[1, col]
            low.plot(f, comp.mif_measured, color="#333333", lw=1, label="measured")
            if comp.mif_synthesised is not None:
                low.plot(f, comp.mif_synthesised, color="#333333", lw=1, ls="--", label="synthesised")
            low.set_ylim(-0.02, 1.02)
            low.legend(fontsize=7)
        for ax in axes[:, col]:
            for fm in comp.modes_hz:
                ax.axvline(fm, color=GREY, lw=0.6, ls=":")
            ax.grid(alpha=0.3)
        axes[-1, col].set_xlabel("frequency [Hz]")
    axes[0, 0].set_ylabel("|H|")
    if has_mif:
        axes[1, 0].set_ylabel("MIF")
    fig.suptitle(f"{name}: measured (solid) and synthesised (dashed) FRFs, MIF below")
    return fig


def history(values: list[float]):
    """Objective per iteration (log axis when all positive)."""
    if not values:
        return None
    v = np.asarray(values, float)
    fig = _figure((6.5, 3.8))
    ax = fig.add_subplot()
    ax.plot(np.arange(len(v)), v, "o-", ms=3, color=BLUE)
    if np.all(v > 0):
        ax.set_yscale("log")
    ax.set_xlabel("iteration")
    ax.set_ylabel("objective")
    ax.set_title("Optimiser history")
    ax.grid(alpha=0.3, which="both")
    return fig


def load_evolution(ev: dict | None):
    """Frequencies [Hz] versus load factor, one line per mode."""
    if ev is None or len(ev["load_factors"]) == 0:
        return None
    fig = _figure((7, 4.5))
    ax = fig.add_subplot()
    for j, lab in enumerate(ev["labels"]):
        ax.plot(ev["load_factors"], ev["frequencies_hz"][:, j], "o-", ms=3, label=str(lab))
    ax.set_xlabel("load factor")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title("Frequencies versus load")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    return fig
