"""Maximum-likelihood refinement of a modal model (ML-MM style) with frequency and damping uncertainty.

Model of every FRF (output o, reference i) at the lines w_k [rad/s] of the band:

    H_oi(w) = sum_m [ psi_om L_mi / (i w - lambda_m) + conj(psi_om L_mi) / (i w - conj(lambda_m)) ]
              - lr_oi / w^2 + ur_oi

poles lambda_m = -zeta_m w_m + i w_m sqrt(1 - zeta_m^2), participation factors L_m (n_i,) with one
entry fixed to 1 (the largest), mode shapes psi_m (n_o,) complex, lower/upper residuals lr, ur real.
The cost is the weighted least-squares (maximum-likelihood for complex Gaussian noise) criterion

    C = sum_{k,o,i} 2 |H_oi(w_k) - model|^2 / var_oi(w_k),

whose expected value at the optimum is the number of real residuals minus the number of parameters
when the variances are right. The shapes and residuals enter linearly: for given poles and
participations they are solved per output (normal equations batched over outputs), and the
Gauss-Newton step of the nonlinear parameters (w_m, zeta_m, L_m) uses the Schur complement of the
full normal matrix (linear parameters solved alongside, analytic Jacobian), with Levenberg-Marquardt
damping. The inverse of that Schur complement at the optimum is the covariance (inverse Fisher
information) of the nonlinear parameters with the linear ones marginalised; it is scaled by
C / dof when the noise level is estimated from the fit residual.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

import numpy as np

from ..errors import EMAError

_CHUNK = 1 << 22  # complex entries per block of outputs in the Jacobian products


@dataclass(frozen=True)
class RefineInfo:
    """Diagnostics of a refinement: cost (weighted, chi-square scaled) before/after, degrees of freedom,
    iterations, whether it converged and was accepted, the variance source and chi2/dof."""

    cost_start: float
    cost: float
    dof: int
    iterations: int
    converged: bool
    accepted: bool
    variance_source: str
    scale: float  # chi2 / dof at the optimum (1 expected for correct variances)
    significance: np.ndarray  # per mode: cost increase when the mode is removed (likelihood ratio)
    variance: np.ndarray | None = None  # the weights' variances on the whole frequency axis (1 outside the band)


def frf_variance_from_coherence(H, coherence, n_averages: int):
    """Variance E|H_est - H|^2 of averaged single-input H1 FRFs from the ordinary coherence:
    |H|^2 (1 - coh) / (coh (n_averages - 1)) [units of H squared]; coherence (n_freq, n_out)."""
    H = np.asarray(H)
    g = np.clip(np.asarray(coherence, float), 1e-6, 1.0)[:, :, None]
    if n_averages < 2:
        raise EMAError("the FRF variance from coherence needs at least two averages")
    return np.abs(H) ** 2 * (1 - g) / (g * (n_averages - 1))


def _lambda(wn, z):
    return -z * wn + 1j * wn * np.sqrt(1 - z ** 2)


class _Problem:
    """Weighted modal-model least squares on fixed data: H (R, n_o) rows (k, i), weights u (R, n_o)."""

    def __init__(self, w, H, u, n_modes, ref_fixed):
        self.w = w
        n_f, n_o, n_i = H.shape
        self.n_f, self.n_o, self.n_i, self.M = n_f, n_o, n_i, n_modes
        self.h = H.transpose(0, 2, 1).reshape(n_f * n_i, n_o)  # rows (k, i)
        self.u = u.transpose(0, 2, 1).reshape(n_f * n_i, n_o)
        self.hh = np.einsum("ro,ro->o", self.u, np.abs(self.h) ** 2)
        self.ref_fixed = np.asarray(ref_fixed)
        self.iw = np.repeat(1j * w, n_i)  # (R,)
        self.ref = np.tile(np.arange(n_i), n_f)  # reference of each row
        self.onehot = (self.ref[:, None] == np.arange(n_i)[None, :]).astype(float)  # (R, n_i)
        self.n_free_L = n_i - 1

    # parameters: theta = [wn (M), zeta (M), (Re L_free, Im L_free) per mode]
    def unpack(self, theta):
        M, n_i = self.M, self.n_i
        wn, z = theta[:M], theta[M:2 * M]
        L = np.ones((M, n_i), complex)
        if n_i > 1:
            free = theta[2 * M:].reshape(M, n_i - 1, 2)
            vals = free[..., 0] + 1j * free[..., 1]
            for m in range(M):
                others = [j for j in range(n_i) if j != self.ref_fixed[m]]
                L[m, others] = vals[m]
        return wn, z, L

    def pack(self, wn, z, L):
        parts = [wn, z]
        if self.n_i > 1:
            free = np.array([[L[m, j] for j in range(self.n_i) if j != self.ref_fixed[m]] for m in range(self.M)])
            parts.append(np.stack([free.real, free.imag], axis=-1).ravel())
        return np.concatenate([np.ravel(p) for p in parts])

    def design(self, theta):
        """Linear columns A (R, n_lin) complex and their scale; the pole terms 1/(iw - lambda)."""
        wn, z, L = self.unpack(theta)
        lam = _lambda(wn, z)
        Pa = 1.0 / (self.iw[:, None] - lam[None, :])  # (R, M)
        Pb = 1.0 / (self.iw[:, None] - lam.conj()[None, :])
        Lr = L[:, self.ref].T  # (R, M): L_m at each row's reference
        a, b = Lr * Pa, Lr.conj() * Pb
        wr = np.abs(self.iw)
        cols = [a + b, 1j * (a - b), -self.onehot / wr[:, None] ** 2, self.onehot.astype(complex)]
        A = np.hstack(cols)
        scale = 1.0 / np.sqrt(np.mean(np.abs(A) ** 2, axis=0))
        return A * scale, scale, (lam, L, Pa, Pb, Lr)

    def linear(self, A):
        """Per-output normal equations: x (n_o, n_lin) real, Gram G (n_o, n_lin, n_lin), cost (n_o,)."""
        n_lin = A.shape[1]
        P = np.ascontiguousarray((A.conj()[:, :, None] * A[:, None, :]).real.reshape(len(A), n_lin * n_lin))
        G = (np.ascontiguousarray(self.u.T) @ P).reshape(self.n_o, n_lin, n_lin)  # contiguous: BLAS
        b = (A.conj().T @ (self.u * self.h)).real.T  # (n_o, n_lin)
        d = np.sqrt(np.maximum(np.einsum("oii->oi", G), 1e-300))
        Gs = G / d[:, :, None] / d[:, None, :] + 1e-12 * np.eye(n_lin)
        try:
            x = np.linalg.solve(Gs, (b / d)[:, :, None])[:, :, 0] / d
        except np.linalg.LinAlgError:
            raise EMAError("refinement: the modal model's linear least squares is singular (two identical poles?); "
                           "remove duplicate modes before refining") from None
        cost = self.hh - np.einsum("oi,oi->o", b, x)
        return x, G, cost

    def _fit(self, theta):
        """Design, scale and linear solution at theta (the last one cached: a trial step's cost
        evaluation is reused by the next normal())."""
        key = theta.tobytes()
        if getattr(self, "_key", None) != key:
            A, scale, terms = self.design(theta)
            x, G, cost_o = self.linear(A)
            self._key, self._cache = key, (A, scale, terms, x, G, cost_o)
        return self._cache

    def cost(self, theta):
        return float(np.sum(self._fit(theta)[5]))

    def normal(self, theta):
        """Cost, gradient g = J^T r and reduced (Schur complement) normal matrix S over theta."""
        A, scale, (lam, L, Pa, Pb, Lr), x, G, cost_o = self._fit(theta)
        M, n_o, R = self.M, self.n_o, len(A)
        p, q = x[:, :M] * scale[:M], x[:, M:2 * M] * scale[M:2 * M]  # psi = p + i q, (n_o, M)
        wn, z, _ = self.unpack(theta)
        dlam_dw = lam / wn
        dlam_dz = wn * (-1 - 1j * z / np.sqrt(1 - z ** 2))
        # Columns of d(model)/d(theta) = psi_om D + conj(psi_om) E = p F + q K, each column one mode.
        Da, Eb = Lr * Pa ** 2, Lr.conj() * Pb ** 2
        D = [Da * dlam_dw, Da * dlam_dz]
        E = [Eb * dlam_dw.conj(), Eb * dlam_dz.conj()]
        owner = [np.arange(M), np.arange(M)]
        if self.n_i > 1:
            for m in range(M):
                for j in range(self.n_i):
                    if j == self.ref_fixed[m]:
                        continue
                    sel = self.onehot[:, j]
                    D += [(sel * Pa[:, m])[:, None], (1j * sel * Pa[:, m])[:, None]]
                    E += [(sel * Pb[:, m])[:, None], (-1j * sel * Pb[:, m])[:, None]]
                    owner += [np.array([m]), np.array([m])]
        # theta's layout: [wn (M), zeta (M), per mode (Re, Im) per free reference].
        D, E, owner = np.hstack(D), np.hstack(E), np.concatenate(owner)
        F, K = D + E, 1j * (D - E)
        Fr, Kr = np.vstack([F.real, F.imag]), np.vstack([K.real, K.imag])  # (2R, n_t) real stacking
        Ar = np.vstack([A.real, A.imag])
        n_t, n_lin = D.shape[1], A.shape[1]
        model_lin = A @ x.T  # (R, n_o) model at the LS optimum
        r = self.h - model_lin
        u2 = np.ascontiguousarray(np.vstack([self.u, self.u]))  # (2R, n_o)
        ur = u2 * np.vstack([r.real, r.imag])
        # J_o = Fr diag(p_o[owner]) + Kr diag(q_o[owner]): every sum over outputs and lines becomes a
        # few large matrix products (no per-output Jacobian is formed).
        # sum_o J_o^T U_o J_o: weights summed over outputs per line and mode pair first.
        pp = (p[:, :, None] * p[:, None, :]).reshape(n_o, M * M)
        pq = (p[:, :, None] * q[:, None, :]).reshape(n_o, M * M)
        qq = (q[:, :, None] * q[:, None, :]).reshape(n_o, M * M)
        Wpp, Wpq, Wqq = [(u2 @ c).reshape(2 * R, M, M) for c in (pp, pq, qq)]
        # Columns in (type, mode) order: every mode has T columns (w, zeta, participation parts).
        T = n_t // M
        typ = np.zeros(n_t, int)
        for m in range(M):
            typ[owner == m] = np.arange(T)
        perm = np.lexsort((owner, typ))
        F3, K3 = Fr[:, perm].reshape(2 * R, T, M), Kr[:, perm].reshape(2 * R, T, M)
        JJp = np.empty((T, M, T, M))
        for i in range(T):
            for j in range(T):
                JJp[i, :, j, :] = (np.einsum("rm,rn,rmn->mn", F3[:, i], F3[:, j], Wpp)
                                   + np.einsum("rm,rn,rmn->mn", F3[:, i], K3[:, j], Wpq)
                                   + np.einsum("rm,rn,rnm->mn", K3[:, i], F3[:, j], Wpq)
                                   + np.einsum("rm,rn,rmn->mn", K3[:, i], K3[:, j], Wqq))
        JJ = np.empty((n_t, n_t))
        JJ[np.ix_(perm, perm)] = JJp.reshape(n_t, n_t)
        # C_o = Ar^T U_o J_o = AF_o diag(p_o) + AK_o diag(q_o), AF_o = Ar^T U_o Fr for every output at once.
        AF = (u2.T @ (Ar[:, :, None] * Fr[:, None, :]).reshape(2 * R, n_lin * n_t)).reshape(n_o, n_lin, n_t)
        AK = (u2.T @ (Ar[:, :, None] * Kr[:, None, :]).reshape(2 * R, n_lin * n_t)).reshape(n_o, n_lin, n_t)
        C = AF * p[:, owner][:, None, :] + AK * q[:, owner][:, None, :]
        ridge = 1e-12 * np.einsum("cii->ci", G).max(axis=1)[:, None, None] * np.eye(n_lin)
        Y = np.linalg.solve(G + ridge, C)
        S = JJ - np.einsum("olt,ols->ts", C, Y)
        S = 0.5 * (S + S.T)
        g = np.einsum("ra,ra->a", Fr, (ur @ p)[:, owner]) + np.einsum("ra,ra->a", Kr, (ur @ q)[:, owner])
        psi = p + 1j * q
        return float(np.sum(cost_o)), g, S, (x, scale, psi, L, lam, model_lin)


def _significance(prob, theta):
    """Per mode: the weighted cost increase when its shape is set to zero and the other linear
    parameters refitted (poles fixed): the Wald / likelihood-ratio statistic of the mode, chi-square
    with 2 n_outputs degrees of freedom if the mode is absent and the variances are right."""
    A, scale, _, x, G, _ = prob._fit(theta)
    M = prob.M
    Ginv = np.linalg.pinv(G)
    out = np.zeros(M)
    for m in range(M):
        idx = [m, M + m]
        blk = Ginv[:, idx][:, :, idx]
        xm = x[:, idx]
        out[m] = float(np.sum(xm * np.linalg.solve(blk, xm[:, :, None])[:, :, 0]))
    return out


def mode_significance(frfs, modal_set, variance, frequency_band=None) -> np.ndarray:
    """Likelihood-ratio significance of each mode of modal_set at its pole (not refined), with the
    given FRF variances (n_freq, n_out, n_in): see `_significance`."""
    freq, H = (frfs if isinstance(frfs, tuple) else (frfs.frequencies_hz, frfs.H))
    freq, H, V = np.asarray(freq, float), np.asarray(H), np.asarray(variance, float)
    lo, hi = frequency_band if frequency_band is not None else (freq[freq > 0].min(), freq.max())
    keep = (freq >= lo) & (freq <= hi) & (freq > 0)
    L0 = np.asarray(modal_set.participation)
    M = len(L0)
    ref = np.argmax(np.abs(L0), axis=1)
    L0 = L0 / L0[np.arange(M), ref][:, None]
    prob = _Problem(2 * np.pi * freq[keep], H[keep], 2.0 / V[keep], M, ref)
    theta = prob.pack(2 * np.pi * np.asarray(modal_set.frequencies_hz, float),
                      np.clip(np.asarray(modal_set.damping_ratio, float), 1e-6, 0.9), L0)
    return _significance(prob, theta)


def _variance_from_residual(model, H, iterations: int = 6):
    """Per FRF, var = a |model|^2 + b (a, b >= 0: noise proportional to the signal plus a floor) fitted
    to e^2 = |H - model|^2 over the lines by iteratively reweighted least squares with weights 1/var^2
    (e^2 of complex Gaussian noise is exponential with mean var and standard deviation var).
    The proportional term follows the measured |H|^2 (an averaged FRF's variance is |H|^2 (1 - coh) /
    (coh n_avg)), which stays right where the model is still wrong (the start)."""
    m2 = np.abs(H) ** 2
    e2 = np.abs(H - model) ** 2
    var = np.broadcast_to(np.mean(e2, axis=0, keepdims=True), e2.shape)
    for _ in range(iterations):
        q = 1.0 / np.maximum(var, 1e-300) ** 2
        s_mm, s_m, s_1 = np.sum(q * m2 * m2, axis=0), np.sum(q * m2, axis=0), np.sum(q, axis=0)
        s_em, s_e = np.sum(q * e2 * m2, axis=0), np.sum(q * e2, axis=0)
        det = s_mm * s_1 - s_m ** 2
        ok = det > 1e-12 * s_mm * s_1
        a = np.where(ok, (s_em * s_1 - s_m * s_e) / np.where(ok, det, 1.0), 0.0)
        b = np.where(ok, (s_mm * s_e - s_m * s_em) / np.where(ok, det, 1.0), s_e / s_1)
        # Clip: whichever term would go negative is dropped and the other refitted alone.
        a, b = np.where(b < 0, s_em / np.maximum(s_mm, 1e-300), a), np.where(b < 0, 0.0, b)
        a, b = np.where(a < 0, 0.0, a), np.where(a < 0, s_e / s_1, b)
        var = a * m2 + b
        floor = 1e-9 * np.maximum(np.max(var, axis=0, keepdims=True), 1e-300)
        var = np.maximum(var, floor)
    return var


def _solve(prob, theta0, max_iter, tol):
    theta = theta0.copy()
    cost, g, S, extra = prob.normal(theta)
    cost0 = cost
    mu = 1e-3
    converged = False
    it = 0
    for it in range(1, max_iter + 1):
        d = np.maximum(np.diag(S), 1e-300)
        while True:
            try:
                step = np.linalg.solve(S + mu * np.diag(d), g)
            except np.linalg.LinAlgError:
                step = np.zeros_like(g)
            trial = theta + step
            M = prob.M
            ok = np.all(trial[M:2 * M] > 0) and np.all(trial[M:2 * M] < 0.95) and np.all(trial[:M] > 0)
            c_trial = prob.cost(trial) if ok else np.inf
            if c_trial < cost:
                break
            mu *= 10
            if mu > 1e8:
                break
        if not c_trial < cost:
            # No descent: at the optimum within the tolerance, or stuck.
            converged = float(g @ np.linalg.lstsq(S, g, rcond=None)[0]) < max(tol, 1e-9 * cost)
            break
        predicted = float(step @ g)
        theta = trial
        drop = cost - c_trial
        cost, g, S, extra = prob.normal(theta)
        mu = max(mu / 10, 1e-9)
        if drop < tol and predicted < 10 * tol:
            converged = True
            break
    return theta, cost, cost0, g, S, extra, converged, it


def refine(frfs, modal_set, variance=None, frequency_band=None, max_iter: int = 30, tol: float = 1e-3,
           return_info: bool = False):
    """Maximum-likelihood refinement of poles, participation factors, shapes and residuals.

    frfs: FRFs container (frequencies_hz, H, outputs, inputs; optional `variance`) or a tuple
    (frequencies_hz, H). modal_set: the start (PolyMAX + LSFD, e.g. `Stabilisation.select()`).
    variance: E|H_measured - H|^2 per line (n_freq, n_out, n_in) [H units squared], e.g.
    FRFEstimate.variance from averaging or `frf_variance_from_coherence`; default: the frfs'
    own `variance`, else estimated from the fit residual per FRF as a |H_model|^2 + b (then the
    covariance is scaled by chi2/dof). frequency_band: (f_min, f_max) [Hz], default the whole axis.

    Returns a ModalSet with frequency_std_hz [Hz] and damping_std (standard deviations from the
    inverse Fisher information at the optimum, scaled by chi2/dof when the variances are estimated,
    and by max(1, chi2/dof) when given). The refined set is accepted only if it lowers the
    weighted cost and every mode stays sane (damping in (0, 0.95), frequency within the band and
    within three half-power bandwidths of the start); else the start is returned with its standard
    deviations evaluated at the start and a warning. With return_info, returns (ModalSet, RefineInfo).
    """
    from .polymax import ModalSet

    if isinstance(frfs, tuple):
        freq, H = frfs
        var_given = variance
    else:
        freq, H = frfs.frequencies_hz, frfs.H
        var_given = variance if variance is not None else getattr(frfs, "variance", None)
    freq = np.asarray(freq, float)
    H = np.asarray(H)
    if H.ndim != 3 or H.shape[0] != len(freq):
        raise EMAError(f"refine: H must have shape (n_freq, n_out, n_in) matching {len(freq)} frequencies, got {H.shape}")
    if not np.all(np.isfinite(H)):
        raise EMAError("refine: the FRFs contain NaN or infinite values; remove the bad channels first")
    lo, hi = frequency_band if frequency_band is not None else (freq[freq > 0].min(), freq.max())
    keep = (freq >= lo) & (freq <= hi) & (freq > 0)
    w, Hk = 2 * np.pi * freq[keep], H[keep]
    n_f, n_o, n_i = Hk.shape
    M = len(modal_set.frequencies_hz)
    if M == 0:
        raise EMAError("refine: the modal set is empty; select modes first")
    L0 = np.asarray(modal_set.participation)
    if L0.shape != (M, n_i):
        if np.asarray(modal_set.residues).shape == (M, n_o, n_i):
            L0 = np.linalg.svd(modal_set.residues)[2][:, 0, :].conj()
        else:
            raise EMAError(f"refine: participation factors of shape {L0.shape} do not match {M} modes x {n_i} references")
    ref_fixed = np.argmax(np.abs(L0), axis=1)
    L0 = L0 / L0[np.arange(M), ref_fixed][:, None]
    wn0 = 2 * np.pi * np.asarray(modal_set.frequencies_hz, float)
    z0 = np.clip(np.asarray(modal_set.damping_ratio, float), 1e-6, 0.9)

    if var_given is not None:
        V = np.asarray(var_given, float)
        if V.shape != H.shape:
            raise EMAError(f"refine: variance of shape {V.shape} does not match the FRFs {H.shape}")
        V = V[keep]
        if not np.all(np.isfinite(V)) or np.any(V <= 0):
            raise EMAError("refine: the FRF variances must be finite and positive (a zero variance is a line "
                           "without noise: floor them, e.g. at 1e-6 of their largest value)")
        source, estimated = "given", False
    else:
        source, estimated = "residual", True

    def problem(V):
        return _Problem(w, Hk, 2.0 / V, M, ref_fixed)

    theta0 = None
    passes = 2 if estimated else 1
    result = None
    for p in range(passes):
        if estimated:
            # Noise model from the residual of the current fit (the start's on the first pass).
            start_theta = theta0 if result is None else result[0]
            # Linear fit weighted by 1/|H|^2 (every line by its relative error) for the residual.
            h2 = np.abs(Hk) ** 2
            tmp = problem(np.maximum(h2, 1e-12 * h2.max(axis=0, keepdims=True)) + 1e-300)
            if start_theta is None:
                start_theta = tmp.pack(wn0, z0, L0)
            A, _, _ = tmp.design(start_theta)
            x, _, _ = tmp.linear(A)
            model = (A @ x.T).reshape(n_f, n_i, n_o).transpose(0, 2, 1)
            V = _variance_from_residual(model, Hk)
        prob = problem(V)
        if theta0 is None:
            theta0 = prob.pack(wn0, z0, L0)
        start = theta0 if result is None else result[0]
        try:
            result = _solve(prob, start, max_iter, tol)
        except (np.linalg.LinAlgError, FloatingPointError) as exc:
            raise EMAError(f"refine: the Gauss-Newton iteration failed ({exc}); check for duplicate or "
                           "out-of-band modes") from None
    theta, cost, _, g, S, extra, converged, iters = result
    cost_start = prob.cost(theta0)  # with the final weights: a fair comparison
    wn, z, L = prob.unpack(theta)
    bw = 2 * z0 * wn0  # half-power bandwidth [rad/s]
    sane = (z > 0) & (z < 0.95) & (wn / (2 * np.pi) >= lo) & (wn / (2 * np.pi) <= hi) & \
        (np.abs(wn - wn0) <= 3 * np.maximum(bw, 2 * np.pi * (freq[1] - freq[0]) if len(freq) > 1 else bw))
    accepted = converged and cost <= cost_start and bool(np.all(sane))
    if not accepted:
        why = ("did not converge" if not converged else "did not lower the weighted cost" if cost > cost_start
               else f"moved mode(s) {list(np.flatnonzero(~sane) + 1)} out of bounds")
        warnings.warn(f"refine: the maximum-likelihood refinement {why}; the PolyMAX estimate is kept (with its "
                      "standard deviations at the start). Check the selected modes (duplicates, modes at the band "
                      "edge) or pass the FRF variances", stacklevel=2)
        theta = theta0
        cost, g, S, extra = prob.normal(theta)
        wn, z, L = prob.unpack(theta)
    x, scale, psi, L, lam, model_lin = extra
    V_full = np.ones(H.shape)
    V_full[keep] = 2.0 / prob.u.reshape(n_f, n_i, n_o).transpose(0, 2, 1)
    n_par = len(theta) + x.size
    dof = max(2 * n_f * n_i * n_o - n_par, 1)
    # Estimated noise: scale by chi2/dof. Given variances: scale only when the fit is worse than they
    # allow (chi2/dof > 1: model error or optimistic variances), never below what the fit supports.
    s2 = cost / dof if estimated else max(1.0, cost / dof)
    try:
        cov = np.linalg.inv(S) * s2
    except np.linalg.LinAlgError:
        cov = np.linalg.pinv(S) * s2
    var_w = np.clip(np.diag(cov)[:M], 0, None)
    var_z = np.clip(np.diag(cov)[M:2 * M], 0, None)
    f_std = np.sqrt(var_w) / (2 * np.pi)
    z_std = np.sqrt(var_z)
    # Significance of each mode: the cost increase (chi-square units) when its shape is set to zero and
    # the other linear parameters refitted (Wald = likelihood-ratio statistic of the linear part).
    signif = _significance(prob, theta) / max(s2, 1e-300)
    R = psi[:, :, None] * L[None, :, :]  # (n_o, M, n_i)
    R = R.transpose(1, 0, 2)
    imax = np.argmax(np.abs(psi), axis=0)
    pk = psi[imax, np.arange(M)]
    shapes = (psi / pk[None, :]).T
    part = L * pk[:, None]
    outputs = np.zeros((0, 2)) if isinstance(frfs, tuple) else getattr(frfs, "outputs", np.zeros((0, 2)))
    inputs = np.zeros((0, 2)) if isinstance(frfs, tuple) else getattr(frfs, "inputs", np.zeros((0, 2)))
    out = ModalSet(wn / (2 * np.pi), z, shapes, part, R, outputs, inputs, frequency_std_hz=f_std, damping_std=z_std)
    if return_info:
        return out, RefineInfo(float(cost_start), float(cost), int(dof), int(iters), bool(converged), bool(accepted),
                               source, float(cost / dof), signif, V_full)
    return out


def with_std(modal_set, frequency_std_hz, damping_std):
    """A copy of a ModalSet with standard deviations set."""
    return replace(modal_set, frequency_std_hz=np.asarray(frequency_std_hz, float),
                   damping_std=np.asarray(damping_std, float))
