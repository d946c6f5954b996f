"""Report-ready matplotlib figures of static shapes, mode shapes and frequency-versus-load charts."""

from __future__ import annotations

import numpy as np


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
