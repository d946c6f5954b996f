"""Report-ready matplotlib figures of static shapes, mode shapes and frequency-versus-load charts, and
of experimental modal analysis: stabilisation diagram over the sum FRF, CMIF, FRF fits."""

from __future__ import annotations

import numpy as np

from ..ema.indicators import cmif, synthesize_from_modes


def _figure(*args, **kwargs):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.figure(*args, **kwargs)


def static_shape(states, title: str = "Static shape"):
    """Side (span-z) and plan (span-chord) views of one or more states against the undeformed geometry."""
    states = list(states)
    fig = _figure(figsize=(9, 5.5))
    side, plan = fig.subplots(2, 1, sharex=True)
    xyz0 = states[0].system.cm.xyz
    order = np.argsort(xyz0[:, 1])
    side.plot(xyz0[order, 1], xyz0[order, 2], "k--", lw=1, label="undeformed")
    plan.plot(xyz0[order, 1], xyz0[order, 0], "k--", lw=1)
    for st in states:
        p = st.positions[order]
        lab = f"{st.configuration.name} (load factor {st.load_factor:g})"
        side.plot(p[:, 1], p[:, 2], lw=2, label=lab)
        plan.plot(p[:, 1], p[:, 0], lw=2)
    side.set_ylabel("z [m]")
    plan.set_ylabel("x [m]")
    plan.set_xlabel("y (span) [m]")
    side.set_title(title)
    side.legend(fontsize=8)
    for ax in (side, plan):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def mode_shapes(modes, n: int = 6, title: str = "Mode shapes"):
    """Translations (x, z) and twist of the first n modes along the span."""
    state = modes.state
    y = state.positions[:, 1]
    order = np.argsort(y)
    n = min(n, modes.n_modes)
    fig = _figure(figsize=(11, 2.2 * ((n + 1) // 2)))
    axes = fig.subplots((n + 1) // 2, 2, squeeze=False).ravel()
    for k in range(n):
        ax = axes[k]
        s = modes.shapes[k][order]
        scale = max(np.abs(s[:, :3]).max(), 1e-300)
        ax.plot(y[order], s[:, 2] / scale, label="z")
        ax.plot(y[order], s[:, 0] / scale, label="x (chord)")
        twist = s[:, 4] / max(np.abs(s[:, 3:]).max(), 1e-300)
        ax.plot(y[order], twist, ":", label="twist (scaled)")
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
    """Poles per model order (stable: filled) over the sum of |FRF| in the fitted band.

    clusters: the kept candidate clusters (`select_ml(..., return_info=True)[1]["kept"]`): their poles
    ringed (strong clusters orange, weak ones, stable over a narrow band of orders, purple). modes: the
    identified modes as dashed lines, with a +-2 sigma band where frequency_std_hz is known."""
    fig = _figure(figsize=(9, 5))
    ax = fig.subplots()
    lo, hi = stab.band
    band = (stab.frequencies_hz >= lo) & (stab.frequencies_hz <= hi)
    for p, s, st in zip(stab.orders, stab.poles, stab.stable):
        f = np.abs(s) / (2 * np.pi)
        keep = (f >= lo) & (f <= hi)
        ax.plot(f[keep & ~st], np.full((keep & ~st).sum(), p), "o", ms=2.5, mfc="none", color="0.6")
        ax.plot(f[keep & st], np.full((keep & st).sum(), p), "o", ms=3, color="tab:green")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax2 = ax.twinx()
    ax2.semilogy(stab.frequencies_hz[band], np.abs(stab.H[band]).sum(axis=(1, 2)), color="tab:blue", lw=1)
    ax2.set_ylabel("sum |FRF|")
    if clusters:
        for c in clusters:
            color = "tab:orange" if c.strong else "tab:purple"
            orders = np.asarray(stab.orders)[np.asarray(c.orders)]
            ax.plot(c.frequencies_hz, orders, "o", ms=7, mfc="none", color=color, mew=1.0)
        from matplotlib.lines import Line2D

        ax.legend(handles=[Line2D([], [], marker="o", ls="", mfc="none", color="tab:orange", label="strong cluster"),
                           Line2D([], [], marker="o", ls="", mfc="none", color="tab:purple",
                                  label="weak cluster (narrow band of orders)")], fontsize=8, loc="lower right")
    if modes is not None:
        sd = getattr(modes, "frequency_std_hz", None)
        for k, f in enumerate(modes.frequencies_hz):
            ax.axvline(f, color="tab:red", lw=0.8, ls="--")
            if sd is not None and np.isfinite(sd[k]):
                ax.axvspan(f - 2 * sd[k], f + 2 * sd[k], color="tab:red", alpha=0.15, lw=0)
    ax.set_title(title)
    fig.tight_layout()
    return fig


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
