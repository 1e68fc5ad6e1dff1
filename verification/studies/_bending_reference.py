"""Exact bending load of a membrane on a prescribed surface, independent of the C++ code.

The surface is the image x = c + A X of a sphere (3D) or circle (2D, a z-invariant cylinder
surface) |X| = R0. On a fine parametrisation every quantity is formed in Cartesian
components with spectral (FFT) derivatives:

    n      unit normal (into the body; the load does not depend on its orientation)
    kappa  = -grad_s n                     curvature tensor, (grad_s v)_ij = sum_a d_a v_i a^a_j
    m      = Eb (kappa - kappa_R P_b)      P_b = P in 3D, the in-plane tangent t t in 2D
    q      = P . div_s m                   (div_s T)_j = sum_a a^a_k d_a T_kj
    f      = -div_s(q n)                   the bending load on the fluid (energy-consistent
                                           sign, docs/method.md "Membrane bending")

(a^a: the dual basis of the tangents a_a = dx/du^a). 3D: theta runs over the doubled
circle (0, 2 pi), on which every smooth function of the surface point is smooth and
periodic (X(2 pi - theta, phi) = X(theta, phi + pi)), so FFT derivatives in theta and phi
are spectrally accurate; the grid is shifted by half a step so no node is at a pole. The
bump integrals int_S f.w dA are exact for trigonometric polynomials in theta (the signed
area element makes the phi-integrated integrand odd about theta = 0) and trapezoidal in
phi. 2D: the circle's angle t, periodic; per unit length along z.
"""
import numpy as np


def _deriv(f, axis, length=2 * np.pi):
    """Spectral derivative of samples periodic over `length` along `axis`."""
    n = f.shape[axis]
    k = np.fft.fftfreq(n, d=length / n) * 2 * np.pi
    if n % 2 == 0:
        k[n // 2] = 0.0
    shape = [1] * f.ndim
    shape[axis] = n
    return np.real(np.fft.ifft(1j * k.reshape(shape) * np.fft.fft(f, axis=axis), axis=axis))


def bending_load_3d(A, R0, c, eb, kappa_r, n_theta=256, n_phi=256):
    """Nodes, area weights and the bending load f on the surface x = c + A X, |X| = R0,
    with a uniform reference curvature kappa_r. Returns x (P,3), f (P,3), dA (P,) over the
    doubled grid (the signed weights make integrals over it those over the surface)."""
    A = np.asarray(A, float)
    N2 = 2 * n_theta
    th = (np.arange(N2) + 0.5) * 2 * np.pi / N2
    ph = np.arange(n_phi) * 2 * np.pi / n_phi
    T, F = np.meshgrid(th, ph, indexing="ij")
    Xr = R0 * np.stack([np.sin(T) * np.cos(F), np.sin(T) * np.sin(F), np.cos(T)], axis=-1)
    Xt = R0 * np.stack([np.cos(T) * np.cos(F), np.cos(T) * np.sin(F), -np.sin(T)], axis=-1)
    Xp = R0 * np.stack([-np.sin(T) * np.sin(F), np.sin(T) * np.cos(F), 0 * T], axis=-1)
    x = np.asarray(c, float) + Xr @ A.T
    at = Xt @ A.T
    ap = Xp @ A.T
    Ainv_T = np.linalg.inv(A).T
    nout = Xr @ Ainv_T.T  # A^-T X: outward normal direction, smooth on the doubled grid
    nout /= np.linalg.norm(nout, axis=-1, keepdims=True)
    n = -nout  # into the body
    # Dual basis.
    gtt = np.einsum("...i,...i", at, at)
    gtp = np.einsum("...i,...i", at, ap)
    gpp = np.einsum("...i,...i", ap, ap)
    det = gtt * gpp - gtp * gtp
    a_t = ((gpp / det)[..., None] * at - (gtp / det)[..., None] * ap)
    a_p = ((gtt / det)[..., None] * ap - (gtp / det)[..., None] * at)

    def dt(f):
        return _deriv(f, 0)

    def dp(f):
        return _deriv(f, 1)

    def grad_vec(v):  # (grad_s v)_ij = d_a v_i a^a_j
        return np.einsum("...i,...j->...ij", dt(v), a_t) + np.einsum("...i,...j->...ij", dp(v), a_p)

    def div_ten(Tn):  # (div_s T)_j = a^a_k d_a T_kj
        return np.einsum("...k,...kj->...j", a_t, dt(Tn)) + np.einsum("...k,...kj->...j", a_p, dp(Tn))

    I = np.eye(3)
    P = I - np.einsum("...i,...j->...ij", n, n)
    kappa = -grad_vec(n)
    kappa = 0.5 * (kappa + np.swapaxes(kappa, -1, -2))  # symmetric (Weingarten), to round-off
    m = eb * (kappa - kappa_r * P)
    q = np.einsum("...ij,...j->...i", P, div_ten(m))
    f = -div_ten(np.einsum("...i,...j->...ij", q, n))
    # Signed area element (a_t x a_p).nout: positive for theta < pi, negative beyond.
    dA = np.einsum("...i,...i", np.cross(at, ap), nout) * (2 * np.pi / N2) * (2 * np.pi / n_phi)
    return x, f, dA, th


def bump_integrals_3d(A, R0, c, eb, kappa_r, centres, ell, n_theta=256, n_phi=256):
    x, f, dA, th = bending_load_3d(A, R0, c, eb, kappa_r, n_theta, n_phi)
    N2 = len(th)
    out = []
    # int_0^pi G(theta) d theta from the samples of G on the doubled grid (G odd about 0
    # and pi): exact for trigonometric polynomials.
    k = np.fft.fftfreq(N2, d=1.0 / N2)
    phase = np.exp(-1j * np.outer(k, th))  # c_k = mean_j G_j e^{-i k theta_j}
    weights = np.where(k == 0, np.pi, (np.exp(1j * k * np.pi) - 1) / (1j * np.where(k == 0, 1, k)))
    if N2 % 2 == 0:
        weights[N2 // 2] = 0.0
    for xm in centres:
        w = np.exp(-np.sum((x - np.asarray(xm)) ** 2, axis=-1) / ell**2)
        vals = []
        for d in range(3):
            G = np.sum(f[..., d] * w * dA, axis=1) / (2 * np.pi / N2)  # phi-integrated, per d theta
            ck = phase @ G / N2
            vals.append(float(np.real(np.sum(ck * weights))))
        out.append(vals)
    return np.array(out)


def bending_load_2d(A, R0, c, eb, kappa_r, n_t=4096):
    """The z-invariant surface x = c + A (R0 cos t, R0 sin t) (2x2 block of A): nodes,
    load (per unit area = per unit length of the section and unit z) and ds dt weights."""
    A = np.asarray(A, float)[:2, :2]
    t = np.arange(n_t) * 2 * np.pi / n_t
    Xr = R0 * np.stack([np.cos(t), np.sin(t)], axis=-1)
    x2 = np.asarray(c, float)[:2] + Xr @ A.T
    at2 = (R0 * np.stack([-np.sin(t), np.cos(t)], axis=-1)) @ A.T
    nout2 = Xr @ np.linalg.inv(A)
    nout2 /= np.linalg.norm(nout2, axis=-1, keepdims=True)
    z = np.zeros((n_t, 1))
    x = np.hstack([x2, z])
    at = np.hstack([at2, z])
    n = -np.hstack([nout2, z])
    a_t = at / np.einsum("...i,...i", at, at)[:, None]  # dual of t; the z tangent is its own

    def grad_vec(v):
        return np.einsum("...i,...j->...ij", _deriv(v, 0), a_t)

    def div_ten(Tn):
        return np.einsum("...k,...kj->...j", a_t, _deriv(Tn, 0))

    I = np.eye(3)
    ez = np.array([0.0, 0.0, 1.0])
    P = I - np.einsum("...i,...j->...ij", n, n)
    Pb = P - np.outer(ez, ez)
    kappa = -grad_vec(n)
    kappa = 0.5 * (kappa + np.swapaxes(kappa, -1, -2))
    m = eb * (kappa - kappa_r * Pb)
    q = np.einsum("...ij,...j->...i", P, div_ten(m))
    f = -div_ten(np.einsum("...i,...j->...ij", q, n))
    ds = np.linalg.norm(at, axis=-1) * (2 * np.pi / n_t)
    return x, f, ds


def bump_integrals_2d(A, R0, c, eb, kappa_r, centres, ell, n_t=4096):
    x, f, ds = bending_load_2d(A, R0, c, eb, kappa_r, n_t)
    out = []
    for xm in centres:
        r2 = np.sum((x[:, :2] - np.asarray(xm)[:2]) ** 2, axis=-1)
        w = np.exp(-r2 / ell**2)
        out.append([float(np.sum(f[:, d] * w * ds)) for d in range(3)])
    return np.array(out)


def bump_integrals(run):
    """Exact bump integrals for one efsi_membrane_force_study JSON record (uniform kappa_R
    on the surface: `reference` gives 1/R0, a number gives itself)."""
    kr = 1.0 / run["R0"] if run["kappa_r"] == "reference" else None
    if run["kappa_r"] == "current":
        raise ValueError("'current' kappa_R is not uniform on a deformed surface")
    if kr is None:
        kr = float(run["kappa_r"])
    args = (run["A"], run["R0"], run["centre"], run["bending"], kr, run["bumps"], run["bump_width"])
    return bump_integrals_2d(*args) if run["dim"] == 2 else bump_integrals_3d(*args)


def self_check():
    """Closed forms the reference must reproduce: (1) a sphere or circle carries no bending
    load whatever its uniform kappa_R (m = M P_b with M uniform has q = 0); (2) a circle of
    radius R with kappa_R = 0 has kappa = t t / R, still uniform, so again zero; (3) the 2D
    ellipse x = (a cos t, b sin t) against the arclength formula of the same law,
    f = -M'' n + k M' t (n inward, t = dx/ds, M = Eb (k - k_R), ' = d/ds)."""
    res = {}
    x, f, _, _ = bending_load_3d(np.eye(3) * 1.2, 0.5, [0, 0, 0], 1.0, 0.0, 64, 64)
    res["sphere_kr0_max_load"] = float(np.abs(f).max())
    x, f, _ = bending_load_2d(np.eye(3) * 1.2, 0.5, [0, 0, 0], 1.0, 1 / 0.5, 512)
    res["circle_max_load"] = float(np.abs(f).max())
    a, b, eb, kr = 0.6, 0.4, 1.0, 2.0
    x, f, ds = bending_load_2d(np.diag([a / 0.5, b / 0.5, 1.0]), 0.5, [0, 0, 0], eb, kr, 2048)
    t = np.arange(2048) * 2 * np.pi / 2048
    sp = np.sqrt(a**2 * np.sin(t) ** 2 + b**2 * np.cos(t) ** 2)  # ds/dt
    k = a * b / sp**3
    M = eb * (k - kr)
    Ms = _deriv(M, 0) / sp
    Mss = _deriv(Ms, 0) / sp
    tang = np.stack([-a * np.sin(t), b * np.cos(t)], axis=-1) / sp[:, None]
    nin = -np.stack([b * np.cos(t), a * np.sin(t)], axis=-1) / sp[:, None]
    f_closed = -Mss[:, None] * nin + (k * Ms)[:, None] * tang
    res["ellipse_closed_form_error"] = float(np.abs(f[:, :2] - f_closed).max() / np.abs(f_closed).max())
    return res


if __name__ == "__main__":
    print(self_check())
