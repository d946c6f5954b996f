"""Report-ready matplotlib figures of static shapes, mode shapes and frequency-versus-load charts, of
experimental modal analysis (stabilisation diagram over the sum FRF, CMIF, FRF fits), and of the
command line's suspension and verification results.

Object API only (matplotlib.figure.Figure, written with fig.savefig): no pyplot state, no backend
chosen here, so a script's own matplotlib setup is left alone."""

from __future__ import annotations

import numpy as np

from ..ema.indicators import cmif, synthesize_from_modes
from . import figures
from .content import StabilisationData


def _figure(*args, **kwargs):
    from matplotlib.figure import Figure

    return Figure(*args, **kwargs)


def _stations(state):
    """For a model with shells: (y of each span station, the node rows at each) from the undeformed
    positions, else None. A built-up
    box has a whole section of nodes at every y: drawn node by node in storage order it is a zigzag
    (the CLI's figures of the wingbox were), so its sections are drawn by their centroids."""
    system = state.system
    if system is None or not any("shells" in f.value_fields and len(f.nodes) for f in system.families):
        return None
    y0 = system.cm.xyz[:, 1]
    order = np.argsort(y0, kind="stable")
    # A gap of 1e-3 of the span starts a new station: an imperfection's offsets (0.8 mm on the
    # wingbox's skins, with a spanwise part) must not split a section.
    breaks = np.flatnonzero(np.diff(y0[order]) > 1e-3 * max(float(np.ptp(y0)), 1e-300)) + 1
    rows = np.split(order, breaks)
    return np.array([y0[r].mean() for r in rows]), rows


def static_shape(states, title: str = "Static shape"):
    """Side (span-z) and plan (span-chord) views of one or more states against the undeformed geometry
    (a shell model: each span station's centroid, with the band its nodes span in z)."""
    states = list(states)
    fig = _figure(figsize=(9, 5.5))
    side, plan = fig.subplots(2, 1, sharex=True)
    xyz0 = states[0].system.cm.xyz
    stations = _stations(states[0])
    if stations is None:
        order = np.argsort(xyz0[:, 1])

        def lines(p):
            return p[order], None
    else:
        _, rows = stations

        def lines(p):
            mean = np.array([p[r].mean(axis=0) for r in rows])
            band = np.array([(p[r, 2].min(), p[r, 2].max(), p[r, 0].min(), p[r, 0].max()) for r in rows])
            return mean, band
    p0, band0 = lines(xyz0)
    centroids = " (section centroids)" if band0 is not None else ""
    side.plot(p0[:, 1], p0[:, 2], "k--", lw=1, label=f"undeformed{centroids}")
    plan.plot(p0[:, 1], p0[:, 0], "k--", lw=1)
    for st in states:
        p, band = lines(st.positions)
        lab = f"{st.configuration.name} (load factor {st.load_factor:g})"
        line, = side.plot(p[:, 1], p[:, 2], lw=2, label=lab)
        plan.plot(p[:, 1], p[:, 0], lw=2, color=line.get_color())
        if band is not None:  # the band the section's nodes span: depth (side), chord (plan)
            side.fill_between(p[:, 1], band[:, 0], band[:, 1], color=line.get_color(), alpha=0.15, lw=0)
            plan.fill_between(p[:, 1], band[:, 2], band[:, 3], color=line.get_color(), alpha=0.15, lw=0)
    side.set_ylabel("z [m]")
    plan.set_ylabel("x [m]")
    plan.set_xlabel("y (span) [m]")
    side.set_title(title)
    side.legend(fontsize=8)
    for ax in (side, plan):
        ax.grid(alpha=0.3)
        ax.ticklabel_format(axis="y", useOffset=False)
    fig.tight_layout()
    return fig


def _section_motion(shape: np.ndarray, xyz: np.ndarray, rows) -> np.ndarray:
    """(stations, 3): each station's mean x and z translation and its rotation about y, the least-
    squares rigid rotation of its nodes' translations about their centroid [rad per unit shape]."""
    out = np.zeros((len(rows), 3))
    for k, r in enumerate(rows):
        u = shape[r, :3]
        d = xyz[r] - xyz[r].mean(axis=0)
        arm = d[:, 0] ** 2 + d[:, 2] ** 2
        spin = np.sum(d[:, 2] * u[:, 0] - d[:, 0] * u[:, 2])
        twist = float(spin / arm.sum()) if arm.sum() > 0 else float(shape[r, 4].mean())
        out[k] = u[:, 0].mean(), u[:, 2].mean(), twist
    return out


def mode_shapes(modes, n: int = 6, title: str = "Mode shapes"):
    """Translations (x, z) and twist of the first n modes along the span (a shell model: of each span
    station's section, its mean translation and rigid rotation)."""
    state = modes.state
    stations = _stations(state)
    n = min(n, modes.n_modes)
    fig = _figure(figsize=(11, 2.2 * ((n + 1) // 2)))
    axes = fig.subplots((n + 1) // 2, 2, squeeze=False).ravel()
    for k in range(n):
        ax = axes[k]
        if stations is None:
            y = state.positions[:, 1]
            order = np.argsort(y)
            s = modes.shapes[k][order]
            y, x_, z_, twist = y[order], s[:, 0], s[:, 2], s[:, 4]
        else:
            y, rows = stations
            m = _section_motion(modes.shapes[k], state.positions, rows)
            x_, z_, twist = m[:, 0], m[:, 1], m[:, 2]
        scale = max(np.abs(np.r_[x_, z_]).max(), 1e-300)
        ax.plot(y, z_ / scale, label="z")
        ax.plot(y, x_ / scale, label="x (chord)")
        ax.plot(y, twist / max(np.abs(twist).max(), 1e-300), ":", label="twist (scaled)")
        lab = modes.labels[k] if modes.labels else ""
        ax.set_title(f"mode {k + 1}: {modes.frequencies_hz[k]:.3f} Hz {lab}", fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    for ax in axes[n:]:
        ax.set_visible(False)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def frequency_versus_load(tracking, title: str = "Frequencies versus load"):
    """One line per tracked mode, labelled with its class at the first load level."""
    fig = _figure(figsize=(7, 5))
    ax = fig.subplots()
    for j in range(tracking.frequencies_hz.shape[1]):
        lab = tracking.labels[j] if tracking.labels else f"mode {j + 1}"
        ax.plot(tracking.load_factors, tracking.frequencies_hz[:, j], "o-", ms=3, label=lab)
    ax.set_xlabel("load factor")
    ax.set_ylabel("frequency [Hz]")
    ax.set_yscale("log")
    ax.set_title(title)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    return fig


def stabilisation_diagram(stab, modes=None, title: str = "Stabilisation diagram", clusters=None):
    """The stabilisation diagram of a `flexgvt.ema.Stabilisation` in its fitted band (drawn by
    `report.figures.stabilisation`, as in the HTML report).

    clusters: the kept candidate clusters (`select_ml(...).info["kept"]`): their poles ringed (strong
    clusters orange, weak ones, stable over a narrow band of orders, purple). modes: the identified
    modes as dashed lines, with a +-2 sigma band where frequency_std_hz is known."""
    data = StabilisationData.from_stabilisation(
        stab, None if modes is None else modes.frequencies_hz,
        None if modes is None else getattr(modes, "frequency_std_hz", None), clusters, band=True)
    return figures.stabilisation(data, title)


def cmif_plot(frequencies_hz, H, modes=None, title: str = "CMIF"):
    fig = _figure(figsize=(9, 4))
    ax = fig.subplots()
    sv = cmif(H)
    for k in range(sv.shape[1]):
        ax.semilogy(frequencies_hz, sv[:, k], lw=1, label=f"singular value {k + 1}")
    if modes is not None:
        for f in modes.frequencies_hz:
            ax.axvline(f, color="tab:red", lw=0.8, ls="--")
    ax.set_xlabel("frequency [Hz]")
    ax.legend(fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    return fig


def frf_fit(frequencies_hz, H, modes, output: int, reference: int = 0, title: str = ""):
    """Measured FRF against the one synthesised from the identified modes: magnitude and phase."""
    fig = _figure(figsize=(8, 5))
    mag, ph = fig.subplots(2, 1, sharex=True)
    Hs = synthesize_from_modes(modes, frequencies_hz)
    mag.semilogy(frequencies_hz, np.abs(H[:, output, reference]), lw=1, label="measured")
    mag.semilogy(frequencies_hz, np.abs(Hs[:, output, reference]), "--", lw=1, label="identified modes")
    ph.plot(frequencies_hz, np.degrees(np.angle(H[:, output, reference])), lw=1)
    ph.plot(frequencies_hz, np.degrees(np.angle(Hs[:, output, reference])), "--", lw=1)
    mag.legend(fontsize=8)
    mag.set_title(title or f"FRF output {output + 1} / reference {reference + 1}")
    ph.set_xlabel("frequency [Hz]")
    ph.set_ylabel("phase [deg]")
    fig.tight_layout()
    return fig


def suspension_response(point):
    """Normalised receptance |x / x_static| of a suspension point (flexgvt.suspension SuspensionPoint:
    mass [kg], stiffness [N/m], damping [N s/m], frequency_hz)."""
    f = np.linspace(0.01, 4 * point.frequency_hz, 600)
    w, wn = 2 * np.pi * f, 2 * np.pi * point.frequency_hz
    H = 1 / (point.stiffness - point.mass * w**2 + 1j * w * point.damping)
    fig = _figure(figsize=(6, 3.5))
    ax = fig.subplots()
    ax.semilogy(f, np.abs(H) * point.stiffness)
    ax.axvline(point.frequency_hz, ls=":", c="k")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|x / x_static|")
    ax.set_title(f"suspension point: K = {point.stiffness:.3g} N/m, C = {point.damping:.3g} N s/m, "
                 f"f_n = {wn / 2 / np.pi:.3g} Hz", fontsize=9)
    fig.tight_layout()
    return fig


def hung_shapes(name: str, results, xyz):
    """Span (y) against height (z) [m] of each suspension layout's hung state (plan_suspension's
    results) over the jig shape xyz (n, 3)."""
    fig = _figure(figsize=(7, 3.5))
    ax = fig.subplots()
    for r in results:
        if r.state is not None:
            ax.plot(r.state.positions[:, 1], r.state.positions[:, 2], label=r.layout.name)
    ax.plot(xyz[:, 1], xyz[:, 2], "k:", label="jig shape")
    ax.set_xlabel("y [m]")
    ax.set_ylabel("z [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7)
    ax.set_title(f"{name}: hung shapes under self-weight")
    fig.tight_layout()
    return fig


def verification_mac(result):
    """MAC after multi-configuration updating, one panel per configuration with shapes
    (flexgvt.updating.verify's result: .multi.mac {name: (initial, updated) or None})."""
    names = [n for n, m in result.multi.mac.items() if m is not None]
    k = max(len(names), 1)
    fig = _figure(figsize=(4.2 * k + 1, 3.8))
    axes = fig.subplots(1, k, squeeze=False)
    im = None
    for ax, name in zip(axes[0], names):
        mac = result.multi.mac[name][1]
        im = ax.imshow(mac, vmin=0, vmax=1, cmap="viridis",
                       extent=(0.5, mac.shape[1] + 0.5, mac.shape[0] + 0.5, 0.5))
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("analytical mode")
        ax.set_ylabel("measured mode")
    fig.suptitle(f"verification '{result.case}', seed {result.seed}: MAC after multi-configuration updating",
                 fontsize=10)
    if im is not None:
        fig.colorbar(im, ax=axes[0].tolist(), shrink=0.8, label="MAC")
    return fig


def verification_errors(result, floor: float = 1e-4):
    """The verification's evidence (the original work's Figs. 4.14-4.21): |frequency error| [%] per
    mode of the initial, single-configuration and multi-configuration models in every configuration
    (the unseen one last; a panel title says which models saw it; LOCAL-labelled modes marked), and
    the design variables' |error| [%]. Log scale, errors below ``floor`` [%] drawn at it; a mode with
    no partner is drawn as an empty marker at the top."""
    rows = result.configurations
    k = len(rows) + 1
    fig = _figure(figsize=(3.3 * k, 4.2))
    axes = fig.subplots(1, k, sharey=True)
    style = {"initial": ("0.6", "initial"), "single": ("tab:red", "single-configuration"),
             "multi": ("tab:blue", "multi-configuration")}
    top = 1e2
    for ax, (name, row) in zip(axes, rows.items()):
        n = len(row["reference_hz"])
        modes = np.arange(1, n + 1)
        for j, (key, (colour, label)) in enumerate(style.items()):
            e = np.abs(np.asarray(row[f"{key}_error_percent"], float))
            lost = np.isnan(e)
            ax.bar(modes + (j - 1) * 0.27, np.maximum(np.where(lost, floor, e), floor), 0.27, color=colour,
                   label=label)
            if lost.any():
                ax.plot(modes[lost] + (j - 1) * 0.27, np.full(lost.sum(), top / 2), "v", mfc="none", color=colour)
        labels = row.get("labels") or [""] * n
        ax.set_xticks(modes, [f"{m}: {lab}" for m, lab in zip(modes, labels)], fontsize=7, rotation=90)
        for tick, lab in zip(ax.get_xticklabels(), labels):
            if "LOCAL" in lab:
                tick.set_color("tab:purple")
        seen = "unseen by both" if row["unseen"] else ("seen by both" if "single" in row["seen_by"]
                                                          else "seen by multi only")
        ax.set_title(f"{name}\n({seen})", fontsize=9)
        ax.set_yscale("log")
        ax.set_ylim(floor / 2, top)
        ax.grid(True, axis="y", which="major", alpha=0.3)
    axes[0].set_ylabel("|frequency error| [%]")
    handles, keys = axes[0].get_legend_handles_labels()
    ax = axes[-1]
    e = result.variable_errors_percent
    names = list(result.names) or [f"x{i + 1}" for i in range(len(e["initial"]))]
    pos = np.arange(len(names))
    for j, (key, (colour, _)) in enumerate(style.items()):
        ax.bar(pos + (j - 1) * 0.27, np.maximum(np.abs(np.asarray(e[key], float)), floor), 0.27, color=colour)
    ax.set_xticks(pos, names, rotation=60, ha="right", fontsize=7)
    ax.set_title("design variables\n|error| against the reference [%]", fontsize=9)
    ax.grid(True, axis="y", which="major", alpha=0.3)
    fig.suptitle(f"verification '{result.case}', seed {result.seed}: frequency errors per configuration "
                 f"(mode: reference label below; errors under {floor:g} % drawn at it)", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.88))
    fig.legend(handles[:3], keys[:3], loc="upper center", bbox_to_anchor=(0.5, 0.94), ncol=3, fontsize=8,
               frameon=False)
    return fig
