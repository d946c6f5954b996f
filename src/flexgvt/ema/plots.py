"""Report figures of experimental modal analysis: stabilisation diagram over the sum FRF, CMIF, FRF fits."""

from __future__ import annotations

import numpy as np

from .indicators import cmif, synthesize_from_modes


def _figure(**kw):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.figure(**kw)


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
