"""Corotational flat shells (fem._shell_corotational): rigid-body invariance, the tangent against
central finite differences in the solver's variables (dx, spatial spin), the linear limit, and the
cantilever strip rolled up by an end moment against the elastica."""

import numpy as np
import pytest

from flexgvt.errors import ModelError
from flexgvt.fem._shell_corotational import (CorotationalTerms, corotational_setup, corotational_terms,
                                             corotational_terms_numpy)
from flexgvt.fem._shell_elements import shell_matrices
from flexgvt.fem._shell_section import mat1, pshell, section_arrays
from flexgvt.fem.rotations import expm_so3, spin

AL = pshell(0.01, mat1(7e10, nu=0.3), mat1(7e10, nu=0.3))
QUAD = np.array([[0.0, 0.0, 0.0], [1.1, 0.1, 0.03], [1.25, 0.9, -0.03], [-0.1, 1.0, 0.02]])  # distorted, warped
TRI = np.array([[0.0, 0.0, 0.0], [1.1, 0.15, 0.0], [0.3, 0.95, 0.0]])


def setup(X, sec=AL):
    C, _ = section_arrays([sec], np.zeros(len(X), int))
    return corotational_setup(X, C)


def strained_state(X, seed, strain=0.02, rotation=0.3):
    """A large rigid motion of X with strains of order ``strain`` and node rotations differing from
    the rigid one by ``rotation`` rad (a large-rotation, strained state)."""
    rng = np.random.default_rng(seed)
    Q = expm_so3(np.array([0.9, -1.7, 0.6]))
    x = (X + strain * rng.standard_normal(X.shape)) @ Q.T + np.array([1.0, -2.0, 3.0])
    R = expm_so3(rotation * rng.standard_normal(X.shape)) @ Q
    return x, R


def fd_tangent(data, x, R, h):
    n, p = x.shape[:2]
    K = np.zeros((n, 6 * p, 6 * p))
    for b in range(6 * p):
        a, c = divmod(b, 6)
        f = []
        for s in (h, -h):
            xx, RR = x.copy(), R.copy()
            if c < 3:
                xx[:, a, c] += s
            else:
                w = np.zeros((n, 3))
                w[:, c - 3] = s
                RR[:, a] = spin(R[:, a], w)
            f.append(corotational_terms(data, xx, RR, tangent=False).forces)
        K[:, :, b] = (f[0] - f[1]) / (2 * h)
    return K


@pytest.mark.parametrize("X", [QUAD, TRI], ids=["quad", "triangle"])
def test_tangent_matches_central_differences(X):
    """At a strained state under a large rotation the tangent equals central differences of the
    forces (spins applied as R <- exp(skew(w)) R). Measured: 2e-10 of max |K| at h = 1e-6 m or rad
    (the round-off of forces ~1e8 N over 2h); the geometric part alone is ~1e-2 of |K|."""
    Xs = np.stack([X, X * [1.3, 0.8, 1.0], X[::-1] * [1.0, 1.0, -1.0]])
    data = setup(Xs)
    x, R = strained_state(Xs, 1)
    t = corotational_terms(data, x, R)
    K_fd = fd_tangent(data, x, R, 1e-6)
    scale = np.abs(t.tangent).max()
    assert np.abs(t.tangent - K_fd).max() < 1e-8 * scale
    # the stress-dependent part is there and large enough for the check to see it if it were missing
    x0, R0 = strained_state(Xs, 1, strain=0.0, rotation=0.0)
    t0 = corotational_terms(data, x0, R0)
    assert np.abs(t.tangent - t0.tangent).max() > 1e-3 * scale


@pytest.mark.parametrize("X", [QUAD, TRI], ids=["quad", "triangle"])
def test_rigid_motion_invariance(X):
    """A rigid rotation (2.4 rad) and translation of a deformed element leaves its local deformations
    and local forces unchanged and turns its nodal forces with it; a rigidly moved undeformed
    element has no forces (round-off: ~1e-7 N against forces of 1e6-1e8 N when strained)."""
    data = setup(X[None])
    x, R = strained_state(X[None], 2)
    t = corotational_terms(data, x, R)
    Q = expm_so3(np.array([1.5, 0.4, -1.8]))
    x2 = x @ Q.T + np.array([5.0, 0.0, -7.0])
    R2 = Q @ R
    t2 = corotational_terms(data, x2, R2)
    assert np.allclose(t2.d, t.d, rtol=0, atol=1e-12)
    assert np.allclose(t2.f_local, t.f_local, rtol=1e-10, atol=1e-10 * np.abs(t.f_local).max())
    f = t.forces.reshape(-1, 3)
    f2 = t2.forces.reshape(-1, 3)
    assert np.allclose(f2, f @ Q.T, rtol=0, atol=1e-10 * np.abs(f).max())
    x0, R0 = strained_state(X[None], 3, strain=0.0, rotation=0.0)
    t0 = corotational_terms(data, x0, R0)
    assert np.abs(t0.d).max() < 1e-14 and np.abs(t0.forces).max() < 1e-12 * np.abs(t.forces).max()


@pytest.mark.parametrize("X", [QUAD, TRI], ids=["quad", "triangle"])
def test_linear_limit(X):
    """At the reference state the forces vanish to round-off and the tangent is the linear element's
    global stiffness (relative 1e-12),
    also for a reference frame in which the kernel's frame is turned (quad: diagonal bisector)."""
    Q = expm_so3(np.array([0.3, -0.5, 1.1]))
    Xs = np.stack([X, X @ Q.T])
    C, _ = section_arrays([AL], np.zeros(2, int))
    data = corotational_setup(Xs, C)
    t = corotational_terms(data, Xs, np.broadcast_to(np.eye(3), Xs.shape[:2] + (3, 3)))
    K = shell_matrices(Xs, C).K
    assert np.abs(t.forces).max() < 1e-14 * np.abs(K).max()  # round-off of d (1e-16 m) times K
    assert np.abs(t.tangent - K).max() < 1e-12 * np.abs(K).max()


def test_quad_frame_is_symmetric_in_the_corners():
    """Renumbering a quad's corners cyclically turns its corotated frame by 90 deg about the normal
    and leaves its forces (renumbered) unchanged."""
    data = setup(QUAD[None])
    x, R = strained_state(QUAD[None], 4)
    t = corotational_terms(data, x, R)
    order = [1, 2, 3, 0]
    data2 = setup(QUAD[None][:, order])
    t2 = corotational_terms(data2, x[:, order], R[:, order])
    turn = t.frames[0].T @ t2.frames[0]
    assert np.allclose(turn, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-14)
    f = t.forces.reshape(4, 6)[order]
    assert np.allclose(t2.forces.reshape(4, 6), f, rtol=0, atol=1e-9 * np.abs(f).max())


@pytest.mark.parametrize("X", [QUAD, TRI], ids=["quad", "triangle"])
@pytest.mark.parametrize("initial_stress", [False, True])
def test_compiled_kernel_equals_numpy_reference(X, initial_stress):
    """The numba kernel (threaded chunks: 300 elements) gives what the NumPy reference gives, to
    round-off (measured 2e-15 relative)."""
    rng = np.random.default_rng(6)
    Xs = X[None] * (1 + 0.2 * rng.random((300, 1, 3)))
    C, _ = section_arrays([AL], np.zeros(len(Xs), int))
    data = corotational_setup(Xs, C, initial_stress=initial_stress)
    x, R = strained_state(Xs, 7)
    R0 = expm_so3(0.1 * rng.standard_normal(Xs.shape))
    for a, b in ((corotational_terms(data, x, R, R0=R0), corotational_terms_numpy(data, x, R, R0=R0)),
                 (corotational_terms(data, x, R, tangent=False), corotational_terms_numpy(data, x, R, False))):
        for name in ("forces", "tangent", "frames", "d", "f_local"):
            u, v = getattr(a, name), getattr(b, name)
            if v is None:
                assert u is None
                continue
            assert np.abs(u - v).max() <= 1e-13 * np.abs(v).max(), name


@pytest.mark.parametrize("X", [QUAD, TRI], ids=["quad", "triangle"])
@pytest.mark.parametrize("initial_stress", [False, True])
def test_reference_stresses_in_the_tangent(X, initial_stress):
    """reference: another state's local forces and deformations in the stress-dependent parts. The
    element's own give its tangent; the tangent is affine in the reference (the material part plus
    parts linear in f_l and d); the forces stay the state's; compiled = NumPy."""
    Xs = np.stack([X, X * [1.2, 0.9, 1.0]])
    C, _ = section_arrays([AL], np.zeros(2, int))
    data = corotational_setup(Xs, C, initial_stress=initial_stress)
    x, R = strained_state(Xs, 8)
    xb, Rb = strained_state(Xs, 9, strain=0.05)
    own = corotational_terms(data, x, R)
    other = corotational_terms(data, xb, Rb)

    def ref(a):
        return CorotationalTerms(other.forces, None, other.frames, a * other.d, a * other.f_local)

    scale = np.abs(own.tangent).max()
    same = corotational_terms(data, x, R, reference=own)
    assert np.abs(same.tangent - own.tangent).max() < 1e-14 * scale
    K = [corotational_terms(data, x, R, reference=ref(a)).tangent for a in (0.0, 0.5, 1.0)]
    assert np.abs(K[1] - 0.5 * (K[0] + K[2])).max() < 1e-12 * scale
    assert np.abs(K[2] - own.tangent).max() > 1e-4 * scale  # the reference matters
    t = corotational_terms(data, x, R, reference=ref(1.0))
    assert np.array_equal(t.forces, own.forces)
    t_np = corotational_terms_numpy(data, x, R, reference=ref(1.0))
    assert np.abs(t_np.tangent - t.tangent).max() < 1e-13 * scale
    with pytest.raises(ModelError, match="reference"):
        corotational_terms(corotational_setup(Xs[:1], C[:1]), x[:1], R[:1], reference=own)


def test_wrong_shapes_raise():
    data = setup(QUAD[None])
    with pytest.raises(ModelError, match="corotational shells"):
        corotational_terms(data, QUAD[None, :3], np.broadcast_to(np.eye(3), (1, 3, 3, 3)))


def test_degenerate_element_is_named():
    X = np.array([[[0.0, 0, 0], [1, 0, 0], [2, 0, 0]]])
    C, _ = section_arrays([AL], np.zeros(1, int))
    with pytest.raises(ModelError):
        corotational_setup(X, C)


def newton_path(xyz, conn, data, fixed, loads, steps, tol=1e-9, max_iter=25):
    """Load-controlled Newton on nodal loads (n_nodes, 6) scaled by the factors ``steps``; returns the
    states (x, R) at the steps. Dense solves (small test models only)."""
    nn = len(xyz)
    free = np.setdiff1d(np.arange(6 * nn), fixed)
    dofs = (6 * conn[:, :, None] + np.arange(6)).reshape(len(conn), -1)
    x, R = xyz.copy(), np.broadcast_to(np.eye(3), (nn, 3, 3)).copy()
    out = []
    for lam in steps:
        for _ in range(max_iter):
            t = corotational_terms(data, x[conn], R[conn])
            f = np.zeros(6 * nn)
            np.add.at(f, dofs, t.forces)
            K = np.zeros((6 * nn, 6 * nn))
            np.add.at(K, (dofs[:, :, None], dofs[:, None, :]), t.tangent)
            r = (lam * loads.ravel() - f)[free]
            if np.linalg.norm(r) <= tol * max(np.linalg.norm(lam * loads), 1.0):
                break
            delta = np.zeros(6 * nn)
            delta[free] = np.linalg.solve(K[np.ix_(free, free)], r)
            delta = delta.reshape(nn, 6)
            x, R = x + delta[:, :3], spin(R, delta[:, 3:])
        else:
            raise AssertionError(f"no convergence at load factor {lam}")
        out.append((x.copy(), R.copy()))
    return out


def _strip(L, b, t, E, nx, tri):
    """A cantilever strip of nx x 1 quads (or 2 nx triangles) along x, width b along y: its nodes,
    connectivity and corotational data (PSHELL of thickness t, E, nu 0)."""
    s = np.linspace(0, L, nx + 1)
    xyz = np.concatenate([np.c_[s, 0 * s, 0 * s], np.c_[s, b + 0 * s, 0 * s]])
    i = np.arange(nx)
    j = i + nx + 1
    quads = np.c_[i, i + 1, j + 1, j]
    conn = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]) if tri else quads
    sec = pshell(t, mat1(E, nu=0.0), mat1(E, nu=0.0))
    C, _ = section_arrays([sec], np.zeros(len(conn), int))
    return xyz, conn, corotational_setup(xyz[conn], C)


@pytest.mark.parametrize("tri", [False, True], ids=["quads", "triangles"])
def test_strip_rolled_up_by_end_moment(tri):
    """Cantilever strip (L 10, b 1, t 0.1, E 1.2e6, nu 0; Sze, Liu & Lo 2004) under an end moment
    M = k 2 pi EI / L: the tip at L sin(theta)/theta, L (1 - cos theta)/theta with theta = M L / EI,
    up to the full circle (tip back at the root). Measured with 20 x 1 quads: tip error 1.2e-3 L at
    theta = pi (chords of the circle: (pi/20)^2 / 24 ~ 1e-3)."""
    L, b, t, E = 10.0, 1.0, 0.1, 1.2e6
    nx = 20
    xyz, conn, data = _strip(L, b, t, E, nx, tri)
    EI = E * b * t**3 / 12
    M = 2 * np.pi * EI / L
    loads = np.zeros((len(xyz), 6))
    loads[[nx, 2 * nx + 1], 4] = -M / 2  # about -y: the tip lifts towards +z
    fixed = np.concatenate([np.arange(6), 6 * (nx + 1) + np.arange(6)])
    steps = np.linspace(0, 1, 33)[1:]
    path = newton_path(xyz, conn, data, fixed, loads, steps)
    errors = []
    for k in (8, 16, 24, 32):
        theta = 2 * np.pi * steps[k - 1]
        x, R = path[k - 1]
        tip = 0.5 * (x[nx] + x[2 * nx + 1])
        exact = np.array([L * np.sin(theta) / theta, 0.5 * b, L * (1 - np.cos(theta)) / theta])
        errors.append(np.linalg.norm(tip - exact) / L)
        # the tip section turned by theta about -y (up to 2 pi)
        assert np.allclose(R[nx], expm_so3(np.array([0.0, -theta, 0.0])), atol=2e-3)
    # measured: quads 2.3e-4, 6.5e-4, 7.0e-4, 1e-14 (the circle closes); triangles 2.3e-4, 6.7e-4, 8.2e-4, 8.7e-4
    assert max(errors) < 1.5e-3
    assert tri or errors[-1] < 1e-8


def test_initial_stress_tangent_matches_central_differences():
    """With the initial-stress energy (membrane resultants on the element's own slopes) the tangent
    stays exact: measured 2e-10 of max |K|, as without."""
    Xs = np.stack([QUAD, QUAD * [1.3, 0.8, 1.0]])
    Ts = np.stack([TRI, TRI[::-1] * [1.0, 1.0, -1.0]])
    for X in (Xs, Ts):
        C, _ = section_arrays([AL], np.zeros(len(X), int))
        data = corotational_setup(X, C, initial_stress=True)
        x, R = strained_state(X, 5)
        t = corotational_terms(data, x, R)
        assert np.abs(t.tangent - fd_tangent(data, x, R, 1e-6)).max() < 1e-8 * np.abs(t.tangent).max()
        plain = corotational_terms(corotational_setup(X, C), x, R)
        assert np.abs(t.forces - plain.forces).max() > 1e-6 * np.abs(plain.forces).max()


def square_grid(n, tri):
    """Unit square in n x n quads, or two triangles each."""
    s, t = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    xyz = np.c_[s.ravel(), t.ravel(), 0 * s.ravel()]
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    q = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    return xyz, (np.vstack([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]) if tri else q)


def plate_buckling(n, tri, initial_stress):
    """k = N_cr a^2 / (pi^2 D) of a simply supported square plate under Nx from the tangent at a
    uniformly compressed state (in-plane DOFs held, as the linear buckling test of the kernels)."""
    import scipy.linalg as sl

    from flexgvt.fem._shell_elements import assemble
    a, t, E, nu = 1.0, 0.01, 7e10, 0.3
    D = E * t**3 / (12 * (1 - nu**2))
    sec = pshell(t, mat1(E, nu=nu), mat1(E, nu=nu))
    xyz, conn = square_grid(n, tri)
    x, y = xyz[:, 0], xyz[:, 1]
    onx = np.isclose(x, 0) | np.isclose(x, a)
    ony = np.isclose(y, 0) | np.isclose(y, a)
    fix = np.unique(np.concatenate([6 * np.arange(len(x)) + k for k in (0, 1, 5)] + [
        6 * np.flatnonzero(onx | ony) + 2, 6 * np.flatnonzero(onx) + 3, 6 * np.flatnonzero(ony) + 4]))
    C, _ = section_arrays([sec], np.zeros(len(conn), int))
    data = corotational_setup(xyz[conn], C, initial_stress=initial_stress)
    eps = -1.0 / (E * t)  # Nx = -1 N/m, Ny = 0
    R = np.broadcast_to(np.eye(3), (len(x), 3, 3))
    K0 = assemble(conn, corotational_terms(data, xyz[conn], R[conn]).tangent, len(x)).toarray()
    xs = xyz + np.c_[eps * x, -nu * eps * y, 0 * x]
    KT = assemble(conn, corotational_terms(data, xs[conn], R[conn]).tangent, len(x)).toarray()
    free = np.setdiff1d(np.arange(K0.shape[0]), fix)
    Kg = (KT - K0)[np.ix_(free, free)]
    mu = sl.eigh(-0.5 * (Kg + Kg.T), K0[np.ix_(free, free)], eigvals_only=True, subset_by_index=[len(free) - 1] * 2)
    return 1 / mu[-1] * a**2 / (np.pi**2 * D)


@pytest.mark.parametrize("tri", [False, True], ids=["quads", "triangles"])
def test_plate_buckling_from_the_tangent(tri):
    """Simply supported square plate under Nx: k = 4 (Timoshenko & Gere) from the corotational
    tangent at a compressed state. The frame's rotation alone carries the geometric stiffness of
    the mesh (k measured: quads 4.140, 4.033 on 8 x 8, 16 x 16; triangles 4.072, 4.017); with the
    initial-stress energy: quads 4.086, 4.020, triangles 3.922, 3.979. Both converge as h^2 (the
    error falls by 3.9-4.3 from 8 x 8 to 16 x 16) and their Richardson extrapolations are 3.997-4.001."""
    for initial_stress in (False, True):
        k8, k16 = (plate_buckling(n, tri, initial_stress) for n in (8, 16))
        assert abs(k16 / 4 - 1) < 0.01
        assert 3 < (k8 - 4) / (k16 - 4) < 5.5
        assert abs((k16 + (k16 - k8) / 3) / 4 - 1) < 0.002


def elastica_tip(alpha):
    """Tip (1 - x/L, z/L) of the inextensible cantilever elastica under a dead tip force with
    P L^2 / EI = alpha (theta'' = -alpha cos theta, theta(0) = 0, theta'(1) = 0), by shooting."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    def end(k0):
        return solve_ivp(lambda s, y: [y[1], -alpha * np.cos(y[0]), np.cos(y[0]), np.sin(y[0])], (0, 1),
                         [0, k0, 0, 0], rtol=1e-12, atol=1e-12).y[:, -1]

    y = end(brentq(lambda k: end(k)[1], 0.0, alpha))
    return 1 - y[2], y[3]


@pytest.mark.parametrize("tri", [False, True], ids=["quads", "triangles"])
def test_strip_under_end_shear_against_elastica(tri):
    """Cantilever strip (L 10, b 1, t 0.1, E 1.2e6, nu 0; Sze, Liu & Lo 2004's first case) under a
    dead tip force up to P L^2 / EI = 4 in 10 steps, 16 x 1 quads or 32 triangles: the tip against
    the elastica (at alpha = 4: u/L = 0.32894, w/L = 0.66996). Measured at alpha = 2 and 4: quads
    -0.15 / -0.04 % and -0.10 / -0.02 % (u, w), triangles +0.005 / +0.06 % and +0.02 / +0.07 %."""
    L, b, t, E = 10.0, 1.0, 0.1, 1.2e6
    nx = 16
    xyz, conn, data = _strip(L, b, t, E, nx, tri)
    P = 4 * E * b * t**3 / 12 / L**2
    loads = np.zeros((len(xyz), 6))
    loads[[nx, 2 * nx + 1], 2] = P / 2
    fixed = np.concatenate([np.arange(6), 6 * (nx + 1) + np.arange(6)])
    steps = np.linspace(0, 1, 11)[1:]
    path = newton_path(xyz, conn, data, fixed, loads, steps)
    for k in (4, 9):
        x, _ = path[k]
        tip = 0.5 * (x[nx] + x[2 * nx + 1])
        u_ref, w_ref = elastica_tip(4 * steps[k])
        assert abs((L - tip[0]) / L / u_ref - 1) < 0.003
        assert abs(tip[2] / L / w_ref - 1) < 0.003
    assert abs(elastica_tip(1e-3)[1] / (1e-3 / 3) - 1) < 1e-5  # the reference's small-load limit, P L^3 / 3EI
