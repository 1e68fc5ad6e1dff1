#!/usr/bin/python3
"""3D capsule in unbounded simple shear by boundary integrals (Lagrangian membrane).

The 3D counterpart of ``capsule_bi_2d.py``: an initially spherical capsule (radius a) with a
neo-Hookean membrane (no bending), equal viscosity inside and outside, in Stokes flow
(Re = 0). With viscosity ratio 1 the velocity is the single-layer potential of the
membrane load alone,

    u(x) = u_inf(x) + 1/(8 pi mu) int_S G(x - y) . f(y) dS(y),   u_inf = (gamma y, 0, 0)
    G(r) = I/|r| + r r / |r|^3                                    (Stokeslet)

and the membrane's material points move with it. f is the load the membrane exerts on the
fluid.

Discretisation
==============
* membrane: the icosphere of ``--level`` subdivisions (10 * 4^level + 2 nodes), linear
  triangles. Each triangle's strain energy is that of MODEL.md's neo-Hookean law per
  reference area, Ws = Es/6 (I1 - 2 + 1/J^2 - 1) = Es/6 (tr(G0^-1 G) + det G0/det G - 3),
  G and G0 the Gram matrices of the current and reference edge vectors (so Ws is exact for
  a flat triangle under a uniform in-plane deformation). The nodal load on the fluid is
  F_i = -dE/dx_i, E = sum over triangles of A0 Ws (the usual linear finite-element
  membrane; its tension is Es/(3J) (B - P/J^2), the same law efsi uses);
* single layer: nodal quadrature, sum_j G(x_i - x_j) F_j over the other nodes, and the
  node's own patch (area A_i, a third of its triangles) integrated analytically as a flat
  disc of the same area: int_disc G dS = pi R (2 I + P), R = sqrt(A_i / pi), applied to
  the load density F_i / A_i. The quadrature is first order in the mesh size; run
  several levels and extrapolate;
* time: Heun (RK2), dt = cfl * h_min * mu / Es (h_min the shortest edge at the start),
  capped by 0.02 / shear rate.

D and the inclination: second moments of the enclosed volume (the polyhedron's
tetrahedra from its centroid), the in-plane pair of principal axes (as efsi's
``taylor_deformation_sharp``), and also Huet's (r_max - r_min)/(r_max + r_min) over the
nodes' distances from the centroid. The output also has the enclosed volume and the
membrane's area (the sum of its triangles').

    /usr/bin/python3 reference/capsule_bi_3d.py --Ca 0.2 --level 3 --t-end 3
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np


def icosphere(level: int):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(level):
        cache: dict = {}
        nf = []

        def mid(a, b):
            k = (min(a, b), max(a, b))
            if k not in cache:
                m = v[a] + v[b]
                v.append(m / np.linalg.norm(m))
                cache[k] = len(v) - 1
            return cache[k]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return np.array(v), np.array(f)


class Membrane:
    def __init__(self, X, tri, Es):
        self.tri, self.Es, self.n = tri, Es, len(X)
        E = self.edges(X)
        self.G0 = np.einsum("tai,tbi->tab", E, E)  # (T, 2, 2): rows are edges
        self.G0inv = np.linalg.inv(self.G0)
        self.detG0 = np.linalg.det(self.G0)
        self.A0 = 0.5 * np.sqrt(self.detG0)

    def edges(self, x):
        t = self.tri
        return np.stack([x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]], 1)  # (T, 2, 3)

    def load(self, x):
        """F_i = -dE/dx_i: the load the membrane puts on the fluid at each node."""
        e = self.edges(x)
        G = np.einsum("tai,tbi->tab", e, e)
        detG = np.linalg.det(G)
        Ginv = np.linalg.inv(G)
        # dWs/dG = Es/6 (G0^-1 - det G0 / det G * G^-1)
        dW = self.Es / 6 * (self.G0inv - (self.detG0 / detG)[:, None, None] * Ginv)
        # dE/de_a = A0 * 2 sum_b dW_ab e_b
        dE = 2 * self.A0[:, None, None] * np.einsum("tab,tbi->tai", dW, e)
        F = np.zeros((self.n, 3))
        t = self.tri
        np.add.at(F, t[:, 1], -dE[:, 0])
        np.add.at(F, t[:, 2], -dE[:, 1])
        np.add.at(F, t[:, 0], dE[:, 0] + dE[:, 1])
        return F

    def nodal_area_normal(self, x):
        e = self.edges(x)
        c = np.cross(e[:, 0], e[:, 1])  # 2 A n (outward for this orientation)
        A = np.zeros(self.n)
        N = np.zeros((self.n, 3))
        for k in range(3):
            np.add.at(A, self.tri[:, k], 0.5 * np.linalg.norm(c, axis=1) / 3)
            np.add.at(N, self.tri[:, k], c)
        N /= np.linalg.norm(N, axis=1)[:, None]
        return A, N


def velocity(x, mem, mu, gamma, subtract=True, chunk=1024):
    F = mem.load(x)
    A, N = mem.nodal_area_normal(x)
    f = F / A[:, None]
    fn = np.einsum("ni,ni->n", f, N) if subtract else np.zeros(len(x))
    AN = A[:, None] * N
    x2 = np.einsum("ni,ni->n", x, x)
    xF = np.einsum("ni,ni->n", x, F)
    xAN = np.einsum("ni,ni->n", x, AN)
    u = np.zeros_like(x)
    for s in range(0, len(x), chunk):
        e = min(s + chunk, len(x))
        xs = x[s:e]
        # r_ij = x_i - x_j; |r|^2 from the Gram matrix (BLAS), the own node excluded
        r2 = x2[s:e, None] + x2[None, :] - 2 * xs @ x.T
        r2[np.arange(e - s), np.arange(s, e)] = np.inf
        inv = 1 / np.sqrt(np.maximum(r2, 1e-300))
        inv3 = inv ** 3
        # source W_j = F_j - fn_i A_j n_j (int_S G(x_i - y) n(y) dS(y) = 0 takes the
        # target's normal load density out of the integrand)
        # r.W = (x_i.F_j - x_j.F_j) - fn_i (x_i.(AN)_j - x_j.(AN)_j)
        rW = (xs @ F.T - xF[None, :]) - fn[s:e, None] * (xs @ AN.T - xAN[None, :])
        w = rW * inv3
        u[s:e] = (inv @ F - fn[s:e, None] * (inv @ AN)
                  + xs * w.sum(1)[:, None] - w @ x)
    R = np.sqrt(A / np.pi)
    fs = f - fn[:, None] * N  # what is left of the own patch's density
    fsn = np.einsum("ni,ni->n", fs, N)
    u += np.pi * R[:, None] * (3 * fs - fsn[:, None] * N)  # pi R (2 I + P) f
    u /= 8 * np.pi * mu
    u[:, 0] += gamma * x[:, 1]
    return u


def shape(x, tri):
    a, b, c = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    vol = np.einsum("ti,ti->t", a, np.cross(b, c)) / 6
    V = vol.sum()
    cg = (vol[:, None] * (a + b + c) / 4).sum(0) / V
    a, b, c = a - cg, b - cg, c - cg
    vol = np.einsum("ti,ti->t", a, np.cross(b, c)) / 6
    S = a + b + c
    I = (np.einsum("t,ti,tj->ij", vol, S, S) + sum(np.einsum("t,ti,tj->ij", vol, p, p)
                                                   for p in (a, b, c))) / 20 / V
    ev, evec = np.linalg.eigh(I)
    o = np.argsort(np.abs(evec[2, :]))[:2]  # the two axes in the shear plane
    o = o[np.argsort(ev[o])]
    lo, hi = np.sqrt(ev[o])
    D = (hi - lo) / (hi + lo)
    v = evec[:, o[1]]
    theta = np.arctan2(v[1], v[0]) % np.pi
    d = np.linalg.norm(x - cg, axis=1)
    D_huet = (d.max() - d.min()) / (d.max() + d.min())
    return D, theta / np.pi, D_huet, V


def area(x, tri):
    a, b, c = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()


def run(Ca, level, t_end, cfl, mu=1.0, gamma=1.0, a=1.0, out=None, every=0.05):
    Es = mu * gamma * a / Ca
    X, tri = icosphere(level)
    X *= a
    mem = Membrane(X, tri, Es)
    e = mem.edges(X)
    h = np.linalg.norm(e, axis=2).min()
    dt = min(cfl * h * mu / Es, 0.02 / gamma)
    x = X.copy()
    t, rows = 0.0, []
    D, th, Dh, V0 = shape(x, tri)
    rows.append((0.0, D, th, Dh, V0, area(x, tri)))
    t0 = time.time()
    nsteps = int(np.ceil(t_end / dt - 1e-9))
    dt = t_end / nsteps
    next_out = every
    for k in range(nsteps):
        u1 = velocity(x, mem, mu, gamma)
        xp = x + dt * u1
        u2 = velocity(xp, mem, mu, gamma)
        x = x + dt / 2 * (u1 + u2)
        t = (k + 1) * dt
        if t >= next_out - 1e-9 or k == nsteps - 1:
            D, th, Dh, V = shape(x, tri)
            if not np.isfinite(D):
                raise SystemExit(f"unstable at t = {t}")
            rows.append((t, D, th, Dh, V, area(x, tri)))
            next_out += every
            print(f"t {t:.3f} D {D:.4f} theta/pi {th:.4f} D_huet {Dh:.4f} volume drift {V / V0 - 1:+.2e}"
                  f" ({time.time() - t0:.0f} s)", file=sys.stderr, flush=True)
    if out:
        out.mkdir(parents=True, exist_ok=True)
        np.savetxt(out / f"bi3d_ca{Ca:g}_L{level}.csv", np.array(rows), delimiter=",",
                   header="t,D,theta_over_pi,D_rmax_rmin,volume,area", comments="")
    return {"Ca": Ca, "level": level, "nodes": len(X), "dt": dt, "h_min": h,
            "D_final": rows[-1][1], "seconds": time.time() - t0}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--Ca", type=float, nargs="+", default=[0.2])
    ap.add_argument("--level", type=int, nargs="+", default=[3])
    ap.add_argument("--t-end", dest="t_end", type=float, default=3.0)
    ap.add_argument("--cfl", type=float, default=0.5)
    ap.add_argument("--out", default="build/reference/capsule_bi_3d")
    args = ap.parse_args()
    res = []
    for Ca in args.Ca:
        for L in args.level:
            r = run(Ca, L, args.t_end, args.cfl, out=Path(args.out))
            print(json.dumps(r), flush=True)
            res.append(r)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    (Path(args.out) / "bi3d_summary.json").write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
