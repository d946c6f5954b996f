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
from .._threads import serial_blas
from .modal_set import ModalSet, as_frfs, checked_frfs, warn_flag

_BLOCK = 1 << 17  # entries (products x lines) of one block of the weighted products: 1 MB, cache-sized


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


def _real_stack(A):
    """[Re A^T, Im A^T] (n, 2R) of A (R, n) complex, row-major: the rows the weighted products gather."""
    out = np.empty((A.shape[1], 2 * len(A)))
    out[:, :len(A)] = A.real.T
    out[:, len(A):] = A.imag.T
    return out


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
        self.uT = np.ascontiguousarray(self.u.T)  # (n_o, R): the weights as the left factor of BLAS products
        self.h2 = np.vstack([self.h.real, self.h.imag])  # (2R, n_o) real stacking
        self.u2 = np.vstack([self.u, self.u])
        self.uh2 = self.h2 * self.u2
        self.ref_fixed = np.asarray(ref_fixed)
        self.iw = np.repeat(1j * w, n_i)  # (R,)
        self.ref = np.tile(np.arange(n_i), n_f)  # reference of each row
        self.onehot = (self.ref[:, None] == np.arange(n_i)[None, :]).astype(float)  # (R, n_i)
        self.n_free_L = n_i - 1
        self._fits, self._normal = {}, (None, None)  # caches of _fit and normal, keyed by theta

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

    def design(self, theta, residuals=True):
        """Linear columns A (R, n_lin) complex and their scale; the pole terms 1/(iw - lambda)."""
        wn, z, L = self.unpack(theta)
        lam = _lambda(wn, z)
        Pa = 1.0 / (self.iw[:, None] - lam[None, :])  # (R, M)
        Pb = 1.0 / (self.iw[:, None] - lam.conj()[None, :])
        Lr = L[:, self.ref].T  # (R, M): L_m at each row's reference
        a, b = Lr * Pa, Lr.conj() * Pb
        wr = np.abs(self.iw)
        cols = [a + b, 1j * (a - b)]
        if residuals:
            cols += [-self.onehot / wr[:, None] ** 2, self.onehot.astype(complex)]
        A = np.hstack(cols)
        scale = 1.0 / np.sqrt(np.mean(np.abs(A) ** 2, axis=0))
        return A * scale, scale, (lam, L, Pa, Pb, Lr)

    def _gram(self, A2T, pairs=None):
        """Re(A^H U_o A) for every output o, upper triangle (n_o, n(n+1)/2) (or the entries (I, J) of
        pairs), from the real stacking A2T = [Re A^T, Im A^T] (n, 2R): Re(conj(a) b) = Re a Re b + Im a Im b.
        The products are formed in cache-sized blocks of lines, one row per pair (contiguous along the
        lines) in reused buffers, and summed over the lines by one BLAS matrix product per block."""
        R = self.n_f * self.n_i
        I, J = np.triu_indices(len(A2T)) if pairs is None else pairs
        out = np.zeros((self.n_o, len(I)))
        step = max(64, _BLOCK // len(I))
        P, Q, T = (np.empty((len(I), min(step, R))) for _ in range(3))
        for s in range(0, R, step):
            e = min(s + step, R)
            if e - s < P.shape[1]:  # the last, shorter block
                P, Q, T = (np.empty((len(I), e - s)) for _ in range(3))
            a, b = A2T[:, s:e], A2T[:, R + s:R + e]
            np.take(a, I, axis=0, out=P, mode="clip")  # mode "clip": no buffering (the indices are valid)
            P *= np.take(a, J, axis=0, out=Q, mode="clip")
            np.take(b, I, axis=0, out=Q, mode="clip")
            Q *= np.take(b, J, axis=0, out=T, mode="clip")
            P += Q
            out += self.uT[:, s:e] @ P.T
        return out

    def gram(self, A2T):
        """Re(A^H U_o A) (n_o, n, n) of the real stacking A2T = [Re A^T, Im A^T] (n, 2R)."""
        n = len(A2T)
        I, J = np.triu_indices(n)
        Gt = self._gram(A2T)
        G = np.empty((self.n_o, n, n))
        G[:, I, J] = Gt
        G[:, J, I] = Gt
        return G

    def _cross_grams(self, A2T, X2T):
        """Re(A^H U_o X) (n_o, n_a, n_x) and Re(X^H U_o X) (n_o, n_x, n_x) for every output o from the real
        stackings A2T (n_a, 2R) and X2T (n_x, 2R), in one pass over the lines (`_gram`)."""
        n_a, n_x = len(A2T), len(X2T)
        I, J = np.triu_indices(n_x)
        pairs = (np.r_[np.repeat(np.arange(n_a), n_x), n_a + I], np.r_[np.tile(np.arange(n_x), n_a) + n_a, n_a + J])
        out = self._gram(np.vstack([A2T, X2T]), pairs)
        B = np.empty((self.n_o, n_x, n_x))
        B[:, I, J] = out[:, n_a * n_x:]
        B[:, J, I] = out[:, n_a * n_x:]
        return out[:, :n_a * n_x].reshape(self.n_o, n_a, n_x), B

    def linear(self, A):
        """Per-output normal equations: x (n_o, n_lin) real, Gram G (n_o, n_lin, n_lin), cost (n_o,) and
        the model at x as the real stacking [Re; Im] (2R, n_o)."""
        n_lin = A.shape[1]
        A2T = _real_stack(A)  # (n_lin, 2R): real BLAS products only
        G = self.gram(A2T)
        b = (A2T @ self.uh2).T  # (n_o, n_lin) = Re(A^H U_o h_o)
        d = np.sqrt(np.maximum(np.einsum("oii->oi", G), 1e-300))
        Gs = G / d[:, :, None] / d[:, None, :] + 1e-12 * np.eye(n_lin)
        try:
            x = np.linalg.solve(Gs, (b / d)[:, :, None])[:, :, 0] / d
        except np.linalg.LinAlgError:
            raise EMAError("refinement: the modal model's linear least squares is singular (two identical poles?); "
                           "remove duplicate modes before refining") from None
        # The cost from the residual itself (not hh - b.x, whose cancellation leaves round-off noise of
        # ~1e-11 of the cost that would decide the last Gauss-Newton steps).
        model = A2T.T @ x.T  # (2R, n_o)
        r = self.h2 - model
        r *= r
        return x, G, np.einsum("ro,ro->o", self.u2, r), model

    def _fit(self, theta):
        """Design, scale and linear solution at theta. The last two are cached: a trial step's cost
        evaluation is reused by the next normal(), the optimum's survives the start's cost evaluation."""
        key = theta.tobytes()
        if key not in self._fits:
            A, scale, terms = self.design(theta)
            self._fits[key] = (A, scale, terms, *self.linear(A))
            if len(self._fits) > 2:
                del self._fits[next(iter(self._fits))]
        return self._fits[key]

    def cost(self, theta):
        return float(np.sum(self._fit(theta)[5]))

    def _derivative_basis(self, theta, terms):
        """The model's derivative along parameter t for output o is alpha_ot beta_k + conj(alpha_ot) gamma_k,
        alpha_ot = psi_om c_t (m = owner[t], k = basis[t]): every pair of parameters of one mode and kind
        (w and zeta; Re and Im of a participation) shares one basis function.
        Returns beta, gamma (R, n_b) complex, c (n_t,) complex, basis (n_t,), owner (n_t,)."""
        lam, _, Pa, Pb, Lr = terms
        wn, z, _ = self.unpack(theta)
        M = self.M
        beta, gamma = [Lr * Pa ** 2], [Lr.conj() * Pb ** 2]
        c = [lam / wn, wn * (-1 - 1j * z / np.sqrt(1 - z ** 2))]  # d(lambda)/d(wn), d(lambda)/d(zeta)
        basis, owner = [np.arange(M)] * 2, [np.arange(M)] * 2
        n_b = M
        for m in range(M):
            for j in range(self.n_i):
                if j != self.ref_fixed[m]:
                    sel = self.onehot[:, j]
                    beta.append((sel * Pa[:, m])[:, None])
                    gamma.append((sel * Pb[:, m])[:, None])
                    c.append(np.array([1.0, 1j]))
                    basis.append(np.array([n_b, n_b]))
                    owner.append(np.array([m, m]))
                    n_b += 1
        return np.hstack(beta), np.hstack(gamma), np.concatenate(c), np.concatenate(basis), np.concatenate(owner)

    def normal(self, theta):
        """Cost, gradient g = J^T r and reduced (Schur complement) normal matrix S over theta.

        The Jacobian column of parameter t for output o is alpha_ot beta_k + conj(alpha_ot) gamma_k
        (`_derivative_basis`), = Re(alpha_ot) (beta_k + gamma_k) + Im(alpha_ot) i (beta_k - gamma_k): a real
        combination J_o = X V_o of the 2 n_b columns X = [beta + gamma, i (beta - gamma)], V_o (2 n_b, n_t)
        real. With real parameters J^T U J = Re(J^H U J), so every sum over lines is one of the real parts
        Re(X^H U_o X) and Re(A^H U_o X), formed for all outputs at once (`_cross_grams`); the per-output
        Jacobians are never formed. The last one is cached."""
        key = theta.tobytes()
        if self._normal[0] != key:
            self._normal = key, self._normal_at(theta)
        return self._normal[1]

    def _normal_at(self, theta):
        A, scale, terms, x, G, cost_o, model_lin = self._fit(theta)
        M, n_o, n_lin = self.M, self.n_o, A.shape[1]
        psi = x[:, :M] * scale[:M] + 1j * x[:, M:2 * M] * scale[M:2 * M]  # (n_o, M)
        beta, gamma, c, basis, owner = self._derivative_basis(theta, terms)
        n_b, n_t = beta.shape[1], len(c)
        X = np.hstack([beta + gamma, 1j * (beta - gamma)])
        X2T = _real_stack(X)  # (2 n_b, 2R)
        AX, B = self._cross_grams(_real_stack(A), X2T)  # one pass over the lines
        alpha = psi[:, owner] * c  # (n_o, n_t)
        V = np.zeros((n_o, 2 * n_b, n_t))
        V[:, basis, np.arange(n_t)] = alpha.real
        V[:, n_b + basis, np.arange(n_t)] = alpha.imag
        JJ = np.einsum("obt,obs->ts", V, B @ V)  # sum_o J_o^T U_o J_o
        C = AX @ V  # C_o = A_o^T U_o J_o (n_o, n_lin, n_t)
        ridge = 1e-12 * np.einsum("cii->ci", G).max(axis=1)[:, None, None] * np.eye(n_lin)
        Y = np.linalg.solve(G + ridge, C)
        S = JJ - np.einsum("olt,ols->ts", C, Y)
        S = 0.5 * (S + S.T)
        # Gradient: sum_o J_o^T U_o r_o = sum_o V_o^T Re(X^H U_o r_o), the residual at the linear optimum.
        g = np.einsum("obt,bo->t", V, X2T @ (self.u2 * (self.h2 - model_lin)))
        return float(np.sum(cost_o)), g, S, (x, scale, psi, terms[1], terms[0])


def _significance(prob, theta):
    """Per mode: the weighted cost increase when its shape is set to zero and the other linear
    parameters refitted (poles fixed): the Wald / likelihood-ratio statistic of the mode, chi-square
    with 2 n_outputs degrees of freedom if the mode is absent and the variances are right."""
    A, scale, _, x, G, _, _ = prob._fit(theta)
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
    given FRF variances (n_freq, n_out, n_in): see `_significance` (and `SignificanceScreen` for one
    candidate mode added to a fixed set, many candidates in turn)."""
    frfs = as_frfs(frfs)
    freq, H, keep, _ = checked_frfs(frfs.frequencies_hz, frfs.H, frequency_band, "mode_significance")
    V = np.asarray(variance, float)
    L0 = np.asarray(modal_set.participation)
    M = len(L0)
    ref = np.argmax(np.abs(L0), axis=1)
    L0 = L0 / L0[np.arange(M), ref][:, None]
    prob = _Problem(2 * np.pi * freq[keep], H[keep], 2.0 / V[keep], M, ref)
    theta = prob.pack(2 * np.pi * np.asarray(modal_set.frequencies_hz, float),
                      np.clip(np.asarray(modal_set.damping_ratio, float), 1e-6, 0.9), L0)
    return _significance(prob, theta)


class SignificanceScreen:
    """`mode_significance` of one candidate mode added to a fixed set of modes, for many candidates (the
    screening of weak clusters): the fixed set's weighted Gram is formed and inverted once per output; a
    candidate adds two columns, whose statistic is (b_c - G_cb y)^T S_c^-1 (b_c - G_cb y) summed over
    outputs, S_c = G_cc - G_cb G_bb^-1 G_bc the Schur complement (= the inverse of the candidate's block
    of the full inverse Gram), y = G_bb^-1 b_b. Poles s [rad/s], participations L."""

    def __init__(self, frfs, poles, participation, variance, frequency_band=None):
        frfs = as_frfs(frfs)
        freq, H, keep, _ = checked_frfs(frfs.frequencies_hz, frfs.H, frequency_band, "significance screen")
        V = np.asarray(variance, float)
        self.prob = _Problem(2 * np.pi * freq[keep], H[keep], 2.0 / V[keep], len(poles), np.zeros(len(poles), int))
        A, _, _ = self.prob.design(self._theta(self.prob, poles, participation))
        self.A2T = _real_stack(A)
        G = self.prob.gram(self.A2T)
        n = G.shape[1]
        d = np.sqrt(np.maximum(np.einsum("oii->oi", G), 1e-300))
        Gs = G / d[:, :, None] / d[:, None, :] + 1e-12 * np.eye(n)
        self.Ginv = np.linalg.inv(Gs) / d[:, :, None] / d[:, None, :]
        self.bb = (self.A2T @ self.prob.uh2).T
        self.y = np.einsum("oij,oj->oi", self.Ginv, self.bb)

    @staticmethod
    def _theta(prob, poles, participation):
        s, L = np.atleast_1d(poles), np.atleast_2d(participation)
        ref = np.argmax(np.abs(L), axis=1)
        prob.ref_fixed = ref
        L = L / L[np.arange(len(L)), ref][:, None]
        wn, z = np.abs(s), np.clip(-s.real / np.abs(s), 1e-6, 0.9)
        return prob.pack(wn, z, L)

    def __call__(self, pole, participation) -> float:
        return float(self.many([pole], [participation])[0])

    def many(self, poles, participations) -> np.ndarray:
        """The statistic of each candidate (pole, participation) in turn, all in one pass over the lines."""
        prob, n, nc = self.prob, len(self.A2T), len(poles)
        M = prob.M
        prob.M = nc
        try:
            ac, _, _ = prob.design(self._theta(prob, poles, participations), residuals=False)  # (R, 2 nc)
        finally:
            prob.M = M
        ac = ac.reshape(-1, 2, nc).transpose(0, 2, 1).reshape(-1, 2 * nc)  # candidate k: columns 2k, 2k + 1
        X2T = np.vstack([self.A2T, _real_stack(ac)])
        cols = n + 2 * np.arange(nc)[:, None]  # (nc, 1): each candidate's first column
        I = np.hstack([np.repeat(np.arange(n), 2)[None, :].repeat(nc, 0), cols, cols, cols + 1])
        J = np.hstack([cols + np.tile([0, 1], n), cols, cols + 1, cols + 1])
        prods = prob._gram(X2T, (I.ravel(), J.ravel())).reshape(-1, nc, 2 * n + 3)
        Gbc = prods[:, :, :2 * n].reshape(-1, nc, n, 2)
        Gcc = prods[:, :, 2 * n:][:, :, [0, 1, 1, 2]].reshape(-1, nc, 2, 2)
        bc = (X2T[n:] @ prob.uh2).T.reshape(-1, nc, 2)
        Sc = Gcc - np.einsum("okic,oij,okjd->okcd", Gbc, self.Ginv, Gbc, optimize=True)
        e = bc - np.einsum("okic,oi->okc", Gbc, self.y)
        return np.einsum("okc,okc->k", e, np.linalg.solve(Sc, e[..., None])[..., 0])


def _variance_from_residual(model, H, iterations: int = 6):
    """Per FRF, var = a |model|^2 + b (a, b >= 0: noise proportional to the signal plus a floor) fitted
    to e^2 = |H - model|^2 over the lines by iteratively reweighted least squares with weights 1/var^2
    (e^2 of complex Gaussian noise is exponential with mean var and standard deviation var).
    The proportional term follows the measured |H|^2 (an averaged FRF's variance is |H|^2 (1 - coh) /
    (coh n_avg)), which stays right where the model is still wrong (the start)."""
    shape = H.shape
    H, model = H.reshape(len(H), -1), model.reshape(len(H), -1)  # (lines, FRFs): long inner loops
    m2 = np.abs(H) ** 2
    e2 = np.abs(H - model) ** 2
    products = (m2 * m2, m2, e2 * m2, e2)  # the weighted sums' factors (fixed)
    var, q = np.empty_like(e2), np.empty_like(e2)
    var[:] = np.mean(e2, axis=0)
    for _ in range(iterations):
        np.maximum(var, 1e-300, out=q)
        q *= q
        np.divide(1.0, q, out=q)
        s_mm, s_m, s_em, s_e = (np.einsum("kc,kc->c", q, f) for f in products)
        s_1 = np.sum(q, axis=0)
        det = s_mm * s_1 - s_m ** 2
        ok = det > 1e-12 * s_mm * s_1
        a = np.where(ok, (s_em * s_1 - s_m * s_e) / np.where(ok, det, 1.0), 0.0)
        b = np.where(ok, (s_mm * s_e - s_m * s_em) / np.where(ok, det, 1.0), s_e / s_1)
        # Clip: whichever term would go negative is dropped and the other refitted alone.
        a, b = np.where(b < 0, s_em / np.maximum(s_mm, 1e-300), a), np.where(b < 0, 0.0, b)
        a, b = np.where(a < 0, 0.0, a), np.where(a < 0, s_e / s_1, b)
        np.multiply(m2, a, out=var)
        var += b
        np.maximum(var, 1e-9 * np.maximum(np.max(var, axis=0), 1e-300), out=var)
    return var.reshape(shape)


def _variance_from_fit(prob, theta, H):
    """`_variance_from_residual` of the FRFs H (n_f, n_o, n_i) about prob's linear fit at theta."""
    A, _, _ = prob.design(theta)
    model = prob.linear(A)[3]
    model = (model[:len(A)] + 1j * model[len(A):]).reshape(prob.n_f, prob.n_i, prob.n_o).transpose(0, 2, 1)
    return _variance_from_residual(model, H)


def _solve(prob, theta0, max_iter, tol):
    """Levenberg-Marquardt from theta0: (theta, cost, converged, iterations). The normal matrix at the
    converged theta is left to the caller (prob.normal, cached), which needs it only on the last pass."""
    theta = theta0.copy()
    cost, g, S, _ = prob.normal(theta)
    mu = 1e-3
    converged = False
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 - the count is read after the loop
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
        cost = c_trial
        if drop < tol and predicted < 10 * tol:
            converged = True
            break
        cost, g, S, _ = prob.normal(theta)
        mu = max(mu / 10, 1e-9)
    return theta, cost, converged, it


@serial_blas  # as polymax: medium products (outputs x lines x a few hundred), one BLAS thread
def refine(frfs, modal_set, variance=None, frequency_band=None, max_iterations: int = 30, tolerance: float = 1e-3,
           return_info: bool = False, *, max_iter: int | None = None, tol: float | None = None) -> ModalSet:
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
    deviations evaluated at the start and a warning. The diagnostics are ``result.info['refine']``
    (a RefineInfo); return_info=True (deprecated) returns (ModalSet, RefineInfo) as before.
    max_iterations, tolerance: at most this many Levenberg-Marquardt iterations; stop when a step
    lowers the (noise-weighted) cost by less than tolerance (max_iter, tol: their deprecated names).
    """
    if max_iter is not None or tol is not None:
        warnings.warn("refine(max_iter=, tol=) are deprecated; use max_iterations=, tolerance= (the names used "
                      "across flexgvt)", DeprecationWarning, stacklevel=2)
        max_iterations = max_iterations if max_iter is None else max_iter
        tolerance = tolerance if tol is None else tol
    frfs = as_frfs(frfs)
    freq, H = frfs.frequencies_hz, frfs.H
    var_given = variance if variance is not None else frfs.variance
    freq, H, keep, (lo, hi) = checked_frfs(freq, H, frequency_band, "refine")
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
            raise EMAError(f"refine: participation factors of shape {L0.shape} do not match {M} modes x {n_i} "
                           "references")
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

    if estimated:  # the noise model's linear fits weight every line by its relative error (1/|H|^2)
        h2 = np.abs(Hk) ** 2
        relative = problem(np.maximum(h2, 1e-12 * h2.max(axis=0, keepdims=True)) + 1e-300)
    theta0 = theta = None
    passes = 2 if estimated else 1
    for k in range(passes):
        if estimated:  # noise model from the residual of the current fit (the start's on the first pass)
            V = _variance_from_fit(relative, relative.pack(wn0, z0, L0) if theta is None else theta, Hk)
        prob = problem(V)
        if theta0 is None:
            theta0 = prob.pack(wn0, z0, L0)
        try:
            theta, cost, converged, iters = _solve(prob, theta0 if theta is None else theta, max_iterations, tolerance)
            if k == passes - 1:  # the first pass only moves the start of the second
                cost, g, S, extra = prob.normal(theta)
        except (np.linalg.LinAlgError, FloatingPointError) as exc:
            raise EMAError(f"refine: the Gauss-Newton iteration failed ({exc}); check for duplicate or "
                           "out-of-band modes") from None
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
    x, scale, psi, L, lam = extra
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
    outputs, inputs = frfs.outputs, frfs.inputs
    info = RefineInfo(float(cost_start), float(cost), int(dof), int(iters), bool(converged), bool(accepted),
                      source, float(cost / dof), signif, V_full)
    out = ModalSet(wn / (2 * np.pi), z, shapes, part, R, outputs, inputs, frequency_std_hz=f_std, damping_std=z_std,
                   info={"refine": info})
    if return_info:
        warn_flag("refine", "return_info", "result.info['refine']")
        return out, info
    return out


def with_std(modal_set, frequency_std_hz, damping_std):
    """A copy of a ModalSet with standard deviations set."""
    return replace(modal_set, frequency_std_hz=np.asarray(frequency_std_hz, float),
                   damping_std=np.asarray(damping_std, float))
