"""PolyMAX (poly-reference least-squares complex frequency-domain, pLSCF) with a stabilisation
diagram, automatic selection of physical poles, and LSFD mode shapes with residual terms.

Model per output o: H_o(w) = B_o(w) A(w)^-1 with z-domain polynomials (basis exp(i w dt r),
dt = 1 / (2 f_max)) and real matrix coefficients; the numerator coefficients are eliminated
(reduced normal equations), alpha_p = I fixes the scale, poles come from the block companion
matrix and participation factors from its eigenvectors.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import cholesky, lapack, solve_triangular
from scipy.linalg.blas import dtrsm

from ..errors import EMAError
from .._threads import serial_blas
from ..modal import mac_paired
from .modal_set import ModalSet, as_frfs, checked_frfs  # noqa: F401  (ModalSet re-exported: flexgvt.ema.polymax.ModalSet)
from .refine import refine as _refine
from .selection import select_ml


@dataclass
class Stabilisation:
    """Poles per model order with stability flags; `select()` picks the physical poles and fits shapes."""

    frequencies_hz: np.ndarray  # FRF frequency axis
    H: np.ndarray
    orders: list
    poles: list  # per order: complex s (n,) [rad/s]
    participations: list  # per order: (n, n_inputs)
    stable: list  # per order: bool (n,) stable in frequency, damping and participation
    outputs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    inputs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    band: tuple = (0.0, np.inf)
    weighting: str = "unit"  # of the fit; select() weights its LSFD the same way

    def select(self, frequencies_hz=None, min_fraction: float = 0.3, tol_f: float = 0.01, refine: bool = False,
               variance=None) -> ModalSet:
        """Physical poles: clusters of stable poles (frequency within tol_f relative) present in at
        least min_fraction of the orders; or, with frequencies_hz, the stable pole nearest each
        given frequency at the highest order (selection by hand).

        refine=True: maximum-likelihood refinement with frequency_std_hz and damping_std
        (flexgvt.ema.refine); automatic selection then follows flexgvt.ema.selection (weak clusters
        stable over a narrow band of orders kept if they pass a likelihood-ratio test, edge poles
        dropped). variance: FRF variances for the refinement (default: estimated from the residual)."""
        if refine and frequencies_hz is None:
            return select_ml(self, variance=variance, min_fraction=min_fraction, tol_f=tol_f)
        pts = [(s, L, k) for k, (ss, Ls, st) in enumerate(zip(self.poles, self.participations, self.stable))
               for s, L, ok in zip(ss, Ls, st) if ok]
        if not pts:
            raise EMAError("no stable pole in the diagram: raise max_order or widen the frequency band")
        f = np.array([abs(s) / (2 * np.pi) for s, _, _ in pts])
        if frequencies_hz is not None:
            chosen = []
            for target in np.atleast_1d(frequencies_hz):
                near = [i for i in range(len(pts)) if abs(f[i] / target - 1) < 0.05]
                if not near:
                    raise EMAError(f"no stable pole within 5 % of {target} Hz")
                chosen.append(max(near, key=lambda i: (pts[i][2], -abs(f[i] - target))))
            picks = [pts[i] for i in chosen]
        else:
            from .clustering import group_by_gap, representative, split_by_order
            need = max(2, int(np.ceil(min_fraction * len(self.orders))))
            picks = []
            for c in group_by_gap(np.argsort(f), f, lambda fi: tol_f * fi):
                for sub in split_by_order(c, pts, f):
                    if len({pts[i][2] for i in sub}) >= need:
                        picks.append(pts[representative(pts, list(sub), f, tol_f)])
        s = np.array([p[0] for p in picks])
        L = np.array([p[1] for p in picks])
        f_lo, f_hi = self.band
        band = (self.frequencies_hz >= f_lo) & (self.frequencies_hz <= f_hi)
        modes = lsfd(self.frequencies_hz[band], self.H[band], s, L, self.outputs, self.inputs, weighting=self.weighting)
        if refine:
            from ..modal import FRFs

            modes = _refine(FRFs(self.frequencies_hz, self.H, self.outputs, self.inputs), modes, variance=variance,
                            frequency_band=self.band)
        return modes


def _stability(prev_s, prev_L, s, L, df_hz=0.0, tol_f=0.01, tol_z=0.05, tol_mac=0.98):
    """Stable flags of poles s (participations L) against the nearest pole of the previous order:
    frequency within tol_f, damping within tol_z (relative) and participation MAC >= tol_mac.

    For a resolution-limited pole (half-power bandwidth 2 zeta f under five lines df [Hz]) whose
    frequency holds to a tenth of tol_f, the damping tolerance has a floor of df/(2 f): one line of
    bandwidth. Such a mode (impact tests at 1 Hz resolution) is not resolved better than that and
    its damping wanders by more than 5 % between orders; computational poles drifting along the
    band edge move in frequency and keep the strict test, as do well-resolved modes."""
    if prev_s is None or len(prev_s) == 0 or len(s) == 0:
        return np.zeros(len(s), bool)
    f, z = np.abs(s), -s.real / np.abs(s)
    fp, zp = np.abs(prev_s), -prev_s.real / np.abs(prev_s)
    j = np.argmin(np.abs(fp[None, :] - f[:, None]), axis=1)
    dfreq = np.abs(fp[j] - f)
    # f in rad/s: 2 zeta f_hz = zeta f / pi is the half-power bandwidth [Hz], df / (2 f_hz) = pi df / f.
    resolution_limited = (dfreq <= 0.1 * tol_f * f) & (z * f / np.pi < 5 * df_hz)
    floor = np.where(resolution_limited, np.pi * df_hz / f, 0.0)
    tol_dz = np.maximum(tol_z * np.maximum(z, 1e-12), floor)
    return (dfreq <= tol_f * f) & (np.abs(zp[j] - z) <= tol_dz) & (mac_paired(prev_L[j], L) >= tol_mac)


_GRAM_PIVOT = 1e-6  # smallest squared Cholesky pivot of the basis Gram matrix, relative to its diagonal


def _lag_sums(phase, w2, Hk, P):
    """Real parts of the lag sums over the lines, lags d = -P..P in rows P + d: r_o(d) = sum_k w_o^2 z^d,
    g_o(d) = sum_k w_o^2 z^d H_o and G(d) = sum_k z^d sum_o w_o^2 H_o^H H_o (z = exp(i phase_k)); only
    real parts enter the normal matrices. With z^(+-d) = cos(d phase) +- i sin(d phase), a lag and its
    negative come from the same two real products over the lines."""
    n_f, n_o, n_i = Hk.shape
    arg = np.outer(phase, np.arange(P + 1))
    cos, sin = np.cos(arg), np.sin(arg)

    def real_sums(x):  # Re sum_k z^d x_k, d = -P..P
        a, b = cos.T @ np.ascontiguousarray(x.real), sin.T @ np.ascontiguousarray(x.imag)
        return np.concatenate([(a + b)[:0:-1], a - b])

    same = bool(np.all(w2 == w2[:, :1]))  # unit weighting: one r for every output
    r = cos.T @ (w2[:, :1] if same else w2)
    r = np.broadcast_to(np.concatenate([r[:0:-1], r]), (2 * P + 1, n_o))
    g = real_sums((w2[:, :, None] * Hk).reshape(n_f, n_o * n_i)).reshape(-1, n_o, n_i)
    HH = np.einsum("ko,koj,kol->kjl", w2, Hk.conj(), Hk).reshape(n_f, n_i * n_i)
    return r, g, real_sums(HH).reshape(-1, n_i, n_i), same


def _well_posed_order(r, same, P):
    """Highest model order <= P whose basis Gram matrices R_o (Toeplitz in the lag; lag sums r) are
    positive definite: on a narrow band far from 0 Hz the basis exp(i w dt r) covers a short arc of the
    unit circle and its Gram matrix loses definiteness at high order."""
    idx = np.arange(P + 1)
    D = idx[None, :] - idx[:, None] + P
    best = P
    for o in [0] if same else range(r.shape[1]):
        L, info = lapack.dpotrf(r[D, o], lower=1)
        rows = info - 1 if info > 0 else P + 1  # the leading block that is positive definite
        # A squared pivot below 1e-6 of r(0): the basis is nearly dependent, and the factorisation
        # breaks down a few orders later at an order that depends on the BLAS build (25 or 27 seen).
        weak = np.flatnonzero(np.diag(L)[:rows] ** 2 < _GRAM_PIVOT * r[P, o])
        rows = min(rows, int(weak[0]) if weak.size else rows)
        best = min(best, rows - 1)  # order p uses p + 1 basis powers
    return best


def _reduced_normal_matrices(r, g, G, same, P):
    """Reduced normal matrices M_p = 2 (T - sum_o S_o^T R_o^-1 S_o) of every order p = 1..P.

    Every entry of R_o, S_o and T depends only on the lag s - r of the basis powers, so all are
    built for order P from the lag sums r, g, G (`_lag_sums`, rows P + lag). With R_o = L_o L_o^T,
    S_o^T R_o^-1 S_o = X_o^T X_o for X_o = L_o^-1 S_o; the Cholesky factor of a leading block is
    the leading block of the factor and the leading rows of X_o depend only on the leading rows
    of S_o, so order p takes the first p + 1 rows and (p + 1) n_i columns of the order-P X_o: a
    running sum over rows gives every order for about the cost of order P alone. Yields (p, M_p).
    """
    n_o, n_i = g.shape[1:]
    idx = np.arange(P + 1)
    D = idx[None, :] - idx[:, None] + P  # lag s - r
    c = (P + 1) * n_i
    S = -np.transpose(g[D], (0, 2, 1, 3)).reshape(P + 1, n_o, c)  # S[r, o, (s, j)]: row r of every S_o
    T = np.transpose(G[D], (0, 2, 1, 3)).reshape(c, c)  # T[(r, i), (s, j)]
    try:
        if same:  # X^T = S^T L^-T, solved in place from the right: X comes out row-major, no copy
            X = dtrsm(1.0, cholesky(r[D, 0], lower=True), S.reshape(P + 1, -1).T, side=1, lower=1, trans_a=1,
                      overwrite_b=1).T.reshape(P + 1, n_o, c)
        else:
            X = np.empty_like(S)
            for o in range(n_o):
                X[:, o] = solve_triangular(cholesky(r[D, o], lower=True), S[:, o], lower=True, check_finite=False)
    except np.linalg.LinAlgError as exc:
        raise EMAError(f"PolyMAX: the normal equations are singular at model order {P} ({exc}); use fewer "
                       "model orders than frequency lines, or a wider frequency band") from None
    N = np.zeros((c, c))
    for p in range(P + 1):
        N += X[p].T @ X[p]
        if p >= 1:
            m = (p + 1) * n_i
            yield p, 2 * (T[:m, :m] - N[:m, :m])


@serial_blas  # its products are small or medium: a second BLAS thread's hand-off costs more on a shared machine
def polymax(frfs, max_order: int = 40, frequency_band=None, orders=None, weighting: str = "unit") -> Stabilisation:
    """Stabilisation diagram of pLSCF poles for model orders 1..max_order (or ``orders``).

    frfs: FRFs (flexgvt.modal: read from a UFF file or estimated), or a tuple (frequencies_hz, H (n_freq, n_out, n_in)).
    frequency_band: (f_min, f_max) [Hz] to fit (default: the whole axis above 0).
    weighting: "unit", or "inverse" (each output's lines by 1/|H_o|, so every mode counts whatever
    its amplitude: receptances of very flexible structures span decades).
    """
    frfs = as_frfs(frfs)
    freq, H, outputs, inputs = frfs.frequencies_hz, frfs.H, frfs.outputs, frfs.inputs
    freq, H, keep, (lo, hi) = checked_frfs(freq, H, frequency_band)
    fk, Hk = freq[keep], H[keep]
    n_i = Hk.shape[2]
    dt = 1.0 / (2 * fk.max())
    df_hz = float(np.median(np.diff(fk))) if len(fk) > 1 else 0.0
    orders = list(range(1, int(max_order) + 1)) if orders is None else sorted({int(p) for p in orders})
    if not orders or orders[0] < 1:
        raise EMAError("model orders must be positive integers")
    P = orders[-1]
    if (P + 1) * n_i > len(fk):
        raise EMAError(f"model order {P} needs more than {len(fk)} frequency lines in the band {lo:g}-{hi:g} Hz; "
                       "lower max_order or widen the band")
    mag = np.sqrt(np.sum(np.abs(Hk) ** 2, axis=2))  # (n_f, n_o)
    if weighting == "unit":
        w2 = np.ones_like(mag)
    elif weighting == "inverse":
        w2 = 1.0 / np.maximum(mag, 1e-12 * mag.max()) ** 2
        w2 /= w2.mean(axis=0, keepdims=True)
    else:
        raise EMAError(f"weighting '{weighting}' must be 'unit' or 'inverse'")
    r, g, G, same = _lag_sums(2 * np.pi * fk * dt, w2, Hk, P)
    usable = _well_posed_order(r, same, P)
    if usable < P:
        kept = [p for p in orders if p <= usable]
        if not kept:
            raise EMAError(f"PolyMAX: the normal equations are singular from model order {usable + 1} on the band "
                           f"{lo:g}-{hi:g} Hz (a narrow band far from 0 Hz); widen the band towards 0 Hz")
        warnings.warn(f"PolyMAX: model orders above {usable} dropped: the basis is ill-conditioned on the band "
                      f"{lo:g}-{hi:g} Hz (narrow and far from 0 Hz); widen the band for higher orders", stacklevel=2)
        r, g, G = (a[P - usable: P + usable + 1] for a in (r, g, G))
        orders, P = kept, usable
    stab = Stabilisation(freq, H, orders, [], [], [], outputs, inputs, (lo, hi), weighting)
    _fill_diagram(stab, _reduced_normal_matrices(r, g, G, same, P), n_i, dt, df_hz)
    return stab


def _fill_diagram(stab, normal_matrices, n_i, dt, df_hz):
    """Poles, participations and stability flags of stab.orders from the reduced normal matrices (p, M_p)."""
    wanted = set(stab.orders)
    prev_s = prev_L = None
    for p, M in normal_matrices:
        if p not in wanted:
            continue
        found = _order_poles(M, p, n_i, dt)
        s, L = found if found is not None else (np.zeros(0, complex), np.zeros((0, n_i), complex))
        stab.poles.append(s)
        stab.participations.append(L)
        stab.stable.append(_stability(prev_s, prev_L, s, L, df_hz))
        if found is not None:  # a singular order is skipped by the stability test
            prev_s, prev_L = s, L


def _order_poles(M, p, n_i, dt):
    """Poles s [rad/s] (stable, upper half plane, by |s|) and unit participation factors L (n, n_i) of
    model order p from its reduced normal matrix M; None when M is singular."""
    m = p * n_i
    try:
        alpha = -np.linalg.solve(M[:m, :m], M[:m, m:])  # (p n_i, n_i), alpha_p = I
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(alpha)):  # numerically singular: skipped like a singular order
        return None
    C = np.zeros((m, m))
    if p > 1:
        C[:-n_i, n_i:] = np.eye(m - n_i)
    # Companion of A^T(z) = sum alpha_r^T z^r: same poles, and its eigenvectors' first block are the
    # left null vectors of A(s), i.e. the participation factors (H = B A^-1 ~ B v w^T / (s - lambda)).
    C[-n_i:, :] = -alpha.reshape(p, n_i, n_i).transpose(0, 2, 1).transpose(1, 0, 2).reshape(n_i, m)
    if n_i == 1:  # one reference: every participation factor is 1, the eigenvectors are not needed
        z = np.linalg.eigvals(C)
        L = np.ones((m, 1), complex)
    else:
        z, V = np.linalg.eig(C)
        L = V[:n_i].T  # participation factors (n, n_i)
    s = np.log(z.astype(complex)) / dt
    ok = (s.imag > 0) & (s.real < 0)
    s, L = s[ok], L[ok]
    L = L / np.linalg.norm(L, axis=1, keepdims=True)
    order = np.argsort(np.abs(s))
    return s[order], L[order]


def lsfd(frequencies_hz, H, poles, participation=None, outputs=None, inputs=None, residuals: bool = True,
         weighting: str = "unit") -> ModalSet:
    """Least-squares frequency-domain residues for given poles s (rad/s, upper half plane), with
    lower (1/w^2) and upper (constant) residual terms per FRF; one linear least-squares problem
    with every FRF as a right-hand side. Each mode's shape is the dominant left singular vector of
    its residue matrix (n_outputs x n_inputs), which uses all references and separates close
    modes; the right singular vector is its participation unless ``participation`` is given.

    weighting: "unit", or "inverse": each FRF's lines weighted by 1/|H| (floored at 1e-4 of its
    largest value), so a fit across decades of frequency is not ruled by the largest FRF values
    and the residues of weak high-frequency modes see their own lines (noise that follows the
    signal, as a measurement's does, is then evenly weighted).
    """
    if weighting not in ("unit", "inverse"):
        raise EMAError(f"weighting '{weighting}' must be 'unit' or 'inverse'")
    w = 2 * np.pi * np.asarray(frequencies_hz, float)
    keep = w > 0
    w, Hk = w[keep], np.asarray(H)[keep]
    n_f, n_o, n_i = Hk.shape
    iw = 1j * w[:, None]
    s = np.asarray(poles)
    nm = len(s)
    P = 1 / (iw - s[None, :])
    Pc = 1 / (iw - s.conj()[None, :])
    cols = [P + Pc, 1j * P - 1j * Pc]
    if residuals:
        cols += [(-1 / w**2)[:, None].astype(complex), np.ones((n_f, 1), complex)]
    A = np.hstack(cols)
    B = Hk.reshape(n_f, n_o * n_i)
    Ar = np.vstack([A.real, A.imag])
    if weighting == "unit":
        x, *_ = np.linalg.lstsq(Ar, np.vstack([B.real, B.imag]), rcond=None)
    else:
        mag = np.abs(B)
        wt = 1.0 / np.maximum(mag, 1e-4 * mag.max(axis=0, keepdims=True) + 1e-300)
        wt = np.vstack([wt, wt])
        Br = np.vstack([B.real, B.imag])
        x = np.column_stack([np.linalg.lstsq(Ar * wt[:, [c]], Br[:, c] * wt[:, c], rcond=None)[0]
                             for c in range(B.shape[1])])
    Rres = (x[:nm] + 1j * x[nm:2 * nm]).reshape(nm, n_o, n_i)
    U, sv, Vh = np.linalg.svd(Rres)
    shapes = U[:, :, 0]
    shapes = shapes / shapes[np.arange(nm), np.argmax(np.abs(shapes), axis=1)][:, None]
    L = np.asarray(participation) if participation is not None else Vh[:, 0, :].conj()
    f = np.abs(s) / (2 * np.pi)
    zeta = -s.real / np.abs(s)
    o = outputs if outputs is not None else np.zeros((0, 2))
    i = inputs if inputs is not None else np.zeros((0, 2))
    return ModalSet(f, zeta, shapes, L, Rres, o, i)


def identify(frfs, max_order: int = 40, frequency_band=None, variance=None, weighting: str = "unit",
             alpha: float = 1e-6, **select_kwargs) -> ModalSet:
    """PolyMAX (`polymax`) + automatic selection with maximum-likelihood refinement (`select_ml`) in one
    call: modes with frequency_std_hz [Hz] and damping_std. frfs: FRFs container or (frequencies_hz,
    H); variance as `refine` (default: the frfs' `variance` if any, else estimated from the residual)."""
    frfs = as_frfs(frfs)
    if variance is None:
        variance = frfs.variance
    stab = polymax(frfs, max_order=max_order, frequency_band=frequency_band, weighting=weighting)
    return select_ml(stab, variance=variance, alpha=alpha, **select_kwargs)
