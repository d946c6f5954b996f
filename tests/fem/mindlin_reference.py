"""Mindlin (Reissner-Mindlin) plate references for the thick-plate tests, independent of flexgvt's
elements (numpy only):

- the simply supported (hard: w = 0 and the tangential rotation held) square plate by Navier's
  double series: centre deflection under uniform load, and the closed-form frequencies (Mindlin
  1951: the lowest root of the cubic in omega^2 for each (m, n), with rotary inertia);
- the clamped square plate by the pb-2 Ritz method of Liew, Xiang & Kitipornchai (1993): each field
  a boundary function times a double Legendre series of degree p (exponentially convergent; the
  tests use p = 16, whose values agree with p = 20 to 1e-7 relative, and the same Ritz reproduces the
  simply supported closed forms to 1e-9).

- the thin (Kirchhoff) square plate, completely free or clamped along one edge (cantilever), by a
  Ritz series of double Legendre polynomials of degree p (times (1 + xi)^2 for the clamped edge;
  p = 12 agrees with p = 20 to 1e-7 on the first frequencies). Leissa's (1969) free and
  cantilever values are Ritz upper bounds with few terms, up to 1.0 % above these.

Imported by name: pyproject's pytest pythonpath holds this folder."""

import numpy as np
import scipy.linalg as sl


def _moduli(E, nu, t, k):
    return E * t**3 / (12 * (1 - nu**2)), k * E / (2 * (1 + nu)) * t


def navier_centre_deflection(a, t, E, nu, k=5 / 6, q=1.0, terms=401):
    """Centre deflection [m] of the hard simply supported square Mindlin plate under uniform q [Pa]:
    w = sum over odd m, n of 16 q / (pi^2 m n) (1 / (D k2^2) + 1 / (S k2)) sin(m pi/2) sin(n pi/2),
    k2 = (m^2 + n^2) pi^2 / a^2 (the Kirchhoff series plus the shear part)."""
    D, S = _moduli(E, nu, t, k)
    m = np.arange(1, terms + 1, 2)[:, None]
    n = m.T
    k2 = (m**2 + n**2) * np.pi**2 / a**2
    sign = (-1.0) ** ((m - 1) // 2 + (n - 1) // 2)
    return float(np.sum(16 * q / (np.pi**2 * m * n) * (1 / (D * k2**2) + 1 / (S * k2)) * sign))


def navier_frequencies(a, t, E, nu, rho, k=5 / 6, count=6, order=8):
    """The lowest ``count`` angular frequencies [rad/s] of the hard simply supported square Mindlin
    plate: for each (m, n) the lowest root of det(K_mn - omega^2 M_mn) over (w, beta_x, beta_y)."""
    D, S = _moduli(E, nu, t, k)
    out = []
    for m in range(1, order + 1):
        for n in range(1, order + 1):
            am, bn = m * np.pi / a, n * np.pi / a
            # w = W sin sin, beta_x = X cos sin, beta_y = Y sin cos
            K = np.array([[S * (am**2 + bn**2), S * am, S * bn],
                          [S * am, D * am**2 + D * (1 - nu) / 2 * bn**2 + S, D * (1 + nu) / 2 * am * bn],
                          [S * bn, D * (1 + nu) / 2 * am * bn, D * bn**2 + D * (1 - nu) / 2 * am**2 + S]])
            M = np.diag([rho * t, rho * t**3 / 12, rho * t**3 / 12])
            out.append(np.sqrt(sl.eigh(K, M, eigvals_only=True)[0]))
    return np.sort(out)[:count]


def _basis(p, ends, nq):
    """1D functions g(x) P_i(x) on [-1, 1] (g = 1 - x^2 when both ends are held, else 1) and their
    derivatives at nq Gauss points, with the weights."""
    x, wq = np.polynomial.legendre.leggauss(nq)
    g, dg = (1 - x**2, -2 * x) if ends else (np.ones_like(x), np.zeros_like(x))
    P = np.array([np.polynomial.legendre.Legendre.basis(i)(x) for i in range(p + 1)])
    dP = np.array([np.polynomial.legendre.Legendre.basis(i).deriv()(x) for i in range(p + 1)])
    return g * P, dg * P + g * dP, wq


def ritz_square_plate(a, t, E, nu, rho=0.0, k=5 / 6, clamped=True, p=16, q=1.0, modes=0):
    """pb-2 Ritz solution of the square Mindlin plate of side a [m], clamped (w, beta_x, beta_y held
    on every edge) or hard simply supported: (centre deflection [m] under uniform q [Pa], the lowest
    ``modes`` angular frequencies [rad/s], consistent with rotary inertia rho t^3/12)."""
    D, S = _moduli(E, nu, t, k)
    nq = p + 8
    h = a / 2  # x = h (xi + 1)
    # (value, derivative) along one axis for: w (held at both ends), a rotation held at the ends, free
    fw = _basis(p, True, nq)
    fh = fw if clamped else fw
    ff = fw if clamped else _basis(p, False, nq)
    wq = fw[2]

    def mat(f, g, df, dg):
        A = (f[0] if not df else f[1]) * wq
        B = g[0] if not dg else g[1]
        return A @ B.T

    # fields: w = fw(x) fw(y); beta_x = ff(x) fh(y) (held on y edges); beta_y = fh(x) ff(y)
    fields = [(fw, fw), (ff, fh), (fh, ff)]
    n1 = p + 1
    N = n1 * n1

    def block(i, j, dxi, dyi, dxj, dyj):
        (fxi, fyi), (fxj, fyj) = fields[i], fields[j]
        return np.kron(mat(fxi, fxj, dxi, dxj), mat(fyi, fyj, dyi, dyj))

    s = 1 / h  # d/dx = (1/h) d/dxi; dA = h^2 dxi deta
    Kb = np.zeros((3 * N, 3 * N))
    sl_ = [slice(0, N), slice(N, 2 * N), slice(2 * N, 3 * N)]
    # bending: kx = bx,x; ky = by,y; kxy = bx,y + by,x
    curv = {0: [(1, 1, 0)], 1: [(2, 0, 1)], 2: [(1, 0, 1), (2, 1, 0)]}  # (field, d/dx, d/dy)
    Db = D * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    for r in range(3):
        for c in range(3):
            if Db[r, c] == 0:
                continue
            for fi, ax, ay in curv[r]:
                for fj, bx, by in curv[c]:
                    Kb[sl_[fi], sl_[fj]] += Db[r, c] * s * s * h * h * block(fi, fj, ax, ay, bx, by)
    # shear: gx = w,x + bx; gy = w,y + by
    shear = {0: [(0, 1, 0, s), (1, 0, 0, 1.0)], 1: [(0, 0, 1, s), (2, 0, 0, 1.0)]}
    for r in range(2):
        for fi, ax, ay, ci in shear[r]:
            for fj, bx, by, cj in shear[r]:
                Kb[sl_[fi], sl_[fj]] += S * ci * cj * h * h * block(fi, fj, ax, ay, bx, by)
    Kb = 0.5 * (Kb + Kb.T)
    f = np.zeros(3 * N)
    f[:N] = q * h * h * np.kron(fw[0] @ wq, fw[0] @ wq)
    u = sl.solve(Kb, f, assume_a="pos")
    centre = np.kron(*[np.array([np.polynomial.legendre.Legendre.basis(i)(0.0) for i in range(n1)])] * 2)
    w0 = float(u[:N] @ centre)
    if not modes:
        return w0, None
    M = np.zeros_like(Kb)
    for fi, m in ((0, rho * t), (1, rho * t**3 / 12), (2, rho * t**3 / 12)):
        M[sl_[fi], sl_[fi]] = m * h * h * block(fi, fi, 0, 0, 0, 0)
    lam = sl.eigh(Kb, M, eigvals_only=True, subset_by_index=[0, modes - 1])
    return w0, np.sqrt(lam)


def free_kirchhoff_square_plate(nu: float, p: int = 16, count: int = 9, clamped_edge: bool = False) -> np.ndarray:
    """The lowest ``count`` frequency parameters lambda = omega a^2 sqrt(rho t / D) of the thin square
    plate, completely free (three rigid modes first, at round-off) or clamped along one edge
    (``clamped_edge``: the cantilever plate CFFF), by the Ritz method on w = g(xi) sum P_i(xi) P_j(eta),
    i, j <= p, g = 1 or (1 + xi)^2 (w and its slope zero at xi = -1), over the square [-1, 1]^2
    (side a = 2, D = rho t = 1)."""
    nq = p + 8
    x, wq = np.polynomial.legendre.leggauss(nq)
    P = [np.array([np.polynomial.legendre.Legendre.basis(i).deriv(d)(x) for i in range(p + 1)]) for d in (0, 1, 2)]
    g = (1 + x) ** 2 if clamped_edge else np.ones_like(x)
    dg, ddg = (2 * (1 + x), 2 + 0 * x) if clamped_edge else (0 * x, 0 * x)
    X = [g * P[0], dg * P[0] + g * P[1], ddg * P[0] + 2 * dg * P[1] + g * P[2]]  # along xi, with g

    def m(A, i, B, j):
        return (A[i] * wq) @ B[j].T

    K = (np.kron(m(X, 2, X, 2), m(P, 0, P, 0)) + np.kron(m(X, 0, X, 0), m(P, 2, P, 2))
         + nu * (np.kron(m(X, 2, X, 0), m(P, 0, P, 2)) + np.kron(m(X, 0, X, 2), m(P, 2, P, 0)))
         + 2 * (1 - nu) * np.kron(m(X, 1, X, 1), m(P, 1, P, 1)))
    M = np.kron(m(X, 0, X, 0), m(P, 0, P, 0))
    w2 = sl.eigh(0.5 * (K + K.T), M, eigvals_only=True, subset_by_index=[0, count - 1])
    return 4.0 * np.sqrt(np.abs(w2))  # omega a^2 with a = 2
