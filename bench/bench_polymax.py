"""Benchmark: PolyMAX + LSFD on 100 FRFs x 4,000 lines, model orders up to 100 with stabilisation,
against sdypy-EMA (LSCF + LSFD) run in the same script on the same synthetic data.

The structure: 10 modes between 3 and 95 Hz with a pair 1 % apart, a heavily damped mode (5 %)
and lightly damped ones (0.5-2 %), 100 response points, one reference (sdypy-EMA is
single-reference), accelerance with complex noise at 30 dB SNR (relative to each line's level).
flexgvt picks its poles automatically from the stabilisation diagram; sdypy-EMA is given the true
natural frequencies to pick the poles closest to them (its non-interactive selection), which is an
advantage. Accuracy: frequency and damping errors and MAC against the true modes, per mode.

Usage:  python bench/bench_polymax.py [--no-write] [--repeats 3]
Rewrites the section "## PolyMAX" of docs/benchmarks.md (other sections are kept).
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import io
import time
import warnings

import numpy as np

from benchdoc import machine_info, write_section
from flexgvt.ema import polymax
from flexgvt.ema.synthetic import ModalModel, synthesize_frfs

SECTION = "## PolyMAX"
F_TRUE = np.array([3.1, 8.7, 17.2, 17.37, 28.5, 41.0, 55.3, 63.9, 80.2, 94.0])
Z_TRUE = np.array([0.02, 0.01, 0.005, 0.005, 0.05, 0.008, 0.01, 0.015, 0.007, 0.01])
N_OUT, N_LINES, F_MAX, MAX_ORDER = 100, 4000, 100.0, 100


def system(seed: int = 1):
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 1.0, N_OUT)
    shapes = np.array([np.sin((k + 1) * np.pi * x + 0.3 * k) + 0.2 * rng.normal(size=N_OUT)
                       for k in range(len(F_TRUE))])
    model = ModalModel(F_TRUE, Z_TRUE, shapes)
    freq = np.linspace(F_MAX / N_LINES, F_MAX, N_LINES)
    frfs = synthesize_frfs(model, freq, np.arange(N_OUT), [7], quantity="accelerance", snr_db=30.0, seed=seed)
    return model, frfs


def mac(a, b):
    return abs(np.vdot(a, b)) ** 2 / (np.vdot(a, a).real * np.vdot(b, b).real)


def score(model, f, z, shapes):
    """Per true mode: nearest identified mode's frequency error [%], damping error [%], MAC."""
    rows = []
    for k, (ft, zt) in enumerate(zip(model.frequencies_hz, model.damping_ratio)):
        if len(f) == 0:
            rows.append((np.nan, np.nan, np.nan))
            continue
        j = int(np.argmin(np.abs(np.asarray(f) - ft)))
        rows.append((100 * (f[j] / ft - 1), 100 * (z[j] / zt - 1), mac(model.shapes[k], shapes[j])))
    return np.array(rows)


def run_flexgvt(frfs, max_order=MAX_ORDER):
    stab = polymax(frfs, max_order=max_order, frequency_band=(1.0, F_MAX))
    modes = stab.select()
    return modes.frequencies_hz, modes.damping_ratio, modes.shapes


def run_flexgvt_ml(frfs, max_order=MAX_ORDER):
    """PolyMAX + ML-refined automatic selection (weak clusters, likelihood-ratio test) + LSFD, with sigmas."""
    stab = polymax(frfs, max_order=max_order, frequency_band=(1.0, F_MAX))
    modes = stab.select(refine=True)
    return modes.frequencies_hz, modes.damping_ratio, modes.shapes


def run_sdypy(frfs, model):
    import sdypy.EMA as E
    H = frfs.H[:, :, 0].T  # (n_out, n_freq)
    with warnings.catch_warnings(), contextlib.redirect_stderr(io.StringIO()):
        warnings.simplefilter("ignore")  # its notes on deprecated arguments and band clamping, progress bars
        m = E.Model(frf=H, freq=frfs.frequencies_hz, lower=1.0, upper=F_MAX, pol_order_high=MAX_ORDER,
                    frf_form="accelerance")
        m.get_poles(method="lscf", show_progress=False)
        m.select_closest_poles(list(model.frequencies_hz), f_window=2.0)
        _, A = m.get_constants(method="lsfd")
    return np.asarray(m.nat_freq), np.asarray(m.nat_xi), A.T


def best(fn, repeats, spread=None):
    times, out = [], None
    for _ in range(repeats):
        gc.collect()
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    if spread is not None:
        spread.extend(times)
    return min(times), out


def two_reference_system(seed: int = 2):
    """The same structure measured from two references (200 FRFs): flexgvt only (poly-reference)."""
    model, _ = system(seed)
    freq = np.linspace(F_MAX / N_LINES, F_MAX, N_LINES)
    return model, synthesize_frfs(model, freq, np.arange(N_OUT), [7, 61], quantity="accelerance", snr_db=30.0,
                                  seed=seed)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    cpu, ncores, vers = machine_info()
    model, frfs = system()
    run_flexgvt(frfs)  # warm-up
    t_fg, res_fg = best(lambda: run_flexgvt(frfs), args.repeats)
    s_fg = score(model, *res_fg)
    run_flexgvt_ml(frfs)  # warm-up
    ml_times = []
    t_ml, res_ml = best(lambda: run_flexgvt_ml(frfs), args.repeats, ml_times)
    s_ml = score(model, *res_ml)
    t_pm, _ = best(lambda: polymax(frfs, max_order=MAX_ORDER, frequency_band=(1.0, F_MAX)), args.repeats)
    model2, frfs2 = two_reference_system()
    t_fg2, res_fg2 = best(lambda: run_flexgvt(frfs2), args.repeats)
    s_fg2 = score(model2, *res_fg2)
    try:
        t_sd, res_sd = best(lambda: run_sdypy(frfs, model), args.repeats)
        s_sd, sd_note = score(model, *res_sd), ""
    except Exception as exc:  # noqa: BLE001
        t_sd, s_sd, sd_note = np.nan, np.full((len(F_TRUE), 3), np.nan), f"failed: {type(exc).__name__}: {exc}"
    lines = [f"machine: {cpu}, {ncores} cores; " + ", ".join(f"{k} {v}" for k, v in vers.items()),
             f"flexgvt PolyMAX orders 1..{MAX_ORDER} + automatic selection + LSFD: {t_fg:.2f} s, "
             f"{len(res_fg[0])} modes",
             f"flexgvt, two references (200 FRFs): {t_fg2:.2f} s, {len(res_fg2[0])} modes",
             f"sdypy-EMA LSCF orders 1..{MAX_ORDER} + poles closest to the true frequencies + LSFD: "
             f"{t_sd:.2f} s {sd_note}",
             f"time ratio sdypy-EMA / flexgvt: {t_sd / t_fg:.1f}",
             f"flexgvt PolyMAX + ML refinement (select(refine=True)): {t_ml:.2f} s "
             f"(repeats {', '.join(f'{t:.2f}' for t in ml_times)}), "
             f"{len(res_ml[0])} modes; sdypy-EMA / flexgvt-ML: {t_sd / t_ml:.1f}",
             f"of which PolyMAX alone: {t_pm:.2f} s"]
    print("\n".join(lines))
    rows = ["| mode | f true [Hz] | zeta true | flexgvt df | flexgvt dzeta | flexgvt MAC | ML-refined df | "
            "ML-refined dzeta | "
            "ML-refined MAC | 2 refs df | 2 refs dzeta | 2 refs MAC | sdypy-EMA df | sdypy-EMA dzeta | sdypy-EMA MAC |",
            "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for k in range(len(F_TRUE)):
        cells = [f"{k + 1}", f"{F_TRUE[k]:.2f}", f"{100 * Z_TRUE[k]:.1f} %"]
        for s in (s_fg, s_ml, s_fg2, s_sd):
            cells += [f"{s[k, 0]:+.3f} %", f"{s[k, 1]:+.1f} %", f"{s[k, 2]:.4f}"]
        rows.append("| " + " | ".join(cells) + " |")
    print("\n".join(rows))
    if not args.no_write:
        worst = lambda s: (np.nanmax(np.abs(s[:, 0])), np.nanmax(np.abs(s[:, 1])), np.nanmin(s[:, 2]))  # noqa: E731
        wf, ws, wm = worst(s_fg), worst(s_sd), worst(s_ml)
        ml_verdict = ("met by every repeat" if max(ml_times) < 1 else "met by the median, not by every repeat"
                      if np.median(ml_times) < 1 else "met by the best run only, not by the median" if t_ml < 1
                      else "NOT met")
        text = "\n".join([
            SECTION, "",
            "`python bench/bench_polymax.py` (about a minute). " + __doc__.split("\n\n")[1].replace("\n", " "), "",
            f"Machine: {cpu}, {ncores} cores (shared). " + ", ".join(f"{k} {v}" for k, v in vers.items()) + ".", "",
            "| | time | modes found | worst frequency error | worst damping error | lowest MAC |",
            "|---|---:|---:|---:|---:|---:|",
            f"| flexgvt `polymax` + `select()` (automatic) + LSFD | **{t_fg:.2f} s** | {len(res_fg[0])} | "
            f"{wf[0]:.3f} % | {wf[1]:.1f} % | {wf[2]:.4f} |",
            f"| flexgvt `polymax` + `select(refine=True)` (ML refinement, likelihood-ratio selection, sigmas) | "
            f"**{t_ml:.2f} s** (repeats {', '.join(f'{t:.2f}' for t in ml_times)} s) | {len(res_ml[0])} | "
            f"{wm[0]:.3f} % | "
            f"{wm[1]:.1f} % | {wm[2]:.4f} |",
            f"| sdypy-EMA `get_poles('lscf')` + `select_closest_poles(true f)` + `get_constants('lsfd')` | "
            f"**{t_sd:.2f} s** | {len(F_TRUE)} (given) | {ws[0]:.3f} % | {ws[1]:.1f} % | {ws[2]:.4f} |",
            "",
            f"**sdypy-EMA / flexgvt time: {t_sd / t_fg:.1f}x**. DESIGN.md target: under 2 s and at least 5x faster "
            "with equal or better accuracy -> "
            f"{'met' if t_fg < 2 and t_sd / t_fg >= 5 and wf[2] >= ws[2] else 'NOT met'}. "
            f"With two references (200 FRFs, poly-reference) flexgvt takes {t_fg2:.2f} s. "
            f"DESIGN.md target for PolyMAX + maximum-likelihood refinement + LSFD: under 1 s -> "
            f"{ml_verdict} (best {t_ml:.2f} s, median {np.median(ml_times):.2f} s of {len(ml_times)}; "
            f"sdypy-EMA / flexgvt-ML {t_sd / t_ml:.1f}x).", "",
            "Per mode (errors of the identified mode nearest each true one):", ""] + rows + [
            "",
            "How: every entry of PolyMAX's normal matrices depends only on the lag between basis powers, so they are "
            "built from 2P + 1 lag sums; only their real parts enter, and a lag and its negative come from the same "
            "two real BLAS products over the lines (cosine and sine of the phase). The reduced normal matrices of all "
            "orders come from one Cholesky factor, one triangular solve at the highest order and a running sum of rank "
            "updates (src/flexgvt/ema/polymax.py). With one reference the companion eigenproblems (one per order) are "
            "solved for eigenvalues only: every participation factor is 1. What remains is mostly those eigenproblems.",
            "",
            "ML refinement (src/flexgvt/ema/refine.py): every output shares the pole basis, so the per-output weighted "
            "Grams Re(A^H U_o A) (upper triangle) and, for the Gauss-Newton step, Re(A^H U_o X) and Re(X^H U_o X) are "
            "formed for all outputs at once by BLAS products over cache-sized blocks of lines. X holds two derivative "
            "basis columns per mode and kind, beta + gamma and i (beta - gamma): every Jacobian column is a real "
            "combination of them, so every sum over lines is a real part (half the products of the complex form). The "
            "Schur complement over the shapes is batched over outputs; no per-output Jacobian is formed. The cost is "
            "taken from the residual (the former hh - b.x cancelled to ~1e-11 and its noise decided the last steps). "
            "The first noise-estimation pass ends without the normal matrix at its optimum (only the last pass needs "
            "it), the fit at the optimum is kept while the start's cost is evaluated, the refinement starts from the "
            "PolyMAX poles and participations without an LSFD, and the weak clusters are screened together against the "
            "kept set's Gram in one pass over the lines. BLAS runs on one thread: the products are medium-sized and "
            "on this shared machine a second thread's hand-off cost more than it saved (under load 0.6-1.1 s per run "
            "against 0.6-2.3 s with two threads). Left: 6 Gauss-Newton normal matrices and 10 weighted linear solves "
            f"(2 of them for the noise model), and PolyMAX itself ({t_pm:.2f} s of the total, mostly the companion "
            "eigenvalues).",
        ])
        write_section(SECTION, text)
        print("wrote docs/benchmarks.md")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
