#!/usr/bin/python3
"""1D parallel-slab (parallel-plate) problem of Sugiyama et al., J Comput Phys 230 (2011) 596.

The solid check of the full-Eulerian method: a visco neo-Hookean solid layer in a channel
0 < y < H, driven by the top wall; everything depends on y only.

Equations (MODEL.md restricted to v = (u(y, t), 0, 0))
======================================================
With v_y = 0 there is no advection (v.grad = u d/dx of y-only fields = 0), div v = 0
holds identically and p is constant.  L has the single entry L_xy = du/dy, so
D B/Dt = L B + B L^T reads

    dB_xy/dt = du/dy B_yy,   dB_yy/dt = 0,   dB_xx/dt = 2 du/dy B_xy,   B_z* fixed.

From B(0) = I: B_yy = 1 and, with the displacement xi(y, t) = int_0^t u(y, s) ds of the
material point at height y (material points never change y), B_xy = d xi/dy and
B_xx = 1 + B_xy^2 -- exactly F F^T for the simple shear F = [[1, xi_y], [0, 1]].
The xy component of the mixture stress sigma = -p I + 2 (1 - phi) mu_f D' + phi (2 mu_s D'
+ G B') is (B' and B differ only on the diagonal)

    sigma_xy = [(1 - phi) mu_f + phi mu_s] du/dy + phi G d xi/dy,

and the x-momentum balance rho du/dt = d sigma_xy/dy together with d xi/dt = u is the
whole problem.  It is *linear*: the neo-Hookean shear stress G B_xy is linear in the
shear xi_y (the nonlinearity only shows in the normal stress G (B_xx - 1) = G xi_y^2,
which the 1D balance does not need).  Hence exact solutions:

* steady moving wall u(H) = V: at steady state sigma_xy = tau is uniform, and wherever
  phi > 0 we need du/dy = 0 (otherwise xi_y, hence the stress, would keep growing).  So
  each solid layer moves rigidly, the pure-fluid layers carry plane Couette flow, and
  tau = V / sum(fluid thickness / mu_f); the solid strain is B_xy = xi_y = tau/(phi G).
  Solid on the fixed wall (default): u = 0 in the solid, u = V (y - y1)/(H - y1) above,
  B_xy = tau/G, xi = tau y/G.  (For a smooth phi, xi_y = tau/(phi G) is unbounded where
  phi -> 0: the fringe of the smoothed layer keeps creeping, and its steady state is only
  reached as t -> infinity.)
* oscillating wall u(H) = V sin(omega t): the time-periodic state is Im(U(y) e^{i w t})
  with, per layer of constant properties (sharp phi), i omega rho U = eta U'' and the
  complex viscosity eta = mu + G/(i omega); U = A e^{k y} + B e^{-k y}, k^2 = i omega
  rho/eta; U and eta U' continuous at the interfaces, U(0) = 0, U(H) = V.  xi = Im(U/(i
  omega) e^{i omega t}) (zero-mean periodic displacement).

Parameters (named after Sugiyama et al. 2011's parallel-plate set-up as far as recalled:
wall speed V, angular frequency omega, densities/viscosities rho, mu_f, mu_s, modulus G,
solid layer thickness; the paper's exact values were not available here, so the defaults
below are *assumptions*): H = 1, solid 0 < y < 0.5 on the fixed bottom wall, fluid above,
rho = 1, mu_f = mu_s = 0.1, G = 1, V = 1, omega = pi (period 2).  ``solid`` = (y0, y1)
allows a sandwiched layer (e.g. (0.25, 0.75)).  Profiles: ``sharp`` (phi = 1 in [y0, y1]),
``sin`` (C^1 ramp phi = (1 + sin(pi s/(2 w)))/2 for |s| < w, s the signed distance into
the solid: compact, so the fluid is pure fluid beyond w) and ``tanh`` (phi = (1 + tanh(s/
w))/2, what a smoothed VOF looks like).

Discretisation (DOLFINx, interval mesh of N cells)
==================================================
u and xi in P2 (the same space); B_xy = xi_y (P1 discontinuous, reported at cell
midpoints, where the P2 derivative is superconvergent).  Crank-Nicolson for the pair
(u, xi), with xi eliminated:

    int rho (u - u^n)/dt v + [mu (u + u^n)/2 + phi G (xi^n + dt/4 (u + u^n))]' v' dy = 0,
    xi^{n+1} = xi^n + dt/2 (u + u^n)        (nodewise, i.e. exactly in P2)

Dirichlet u(0) = 0, u(H) = V_wall(t^{n+1}).  The matrix is constant (one MUMPS LU).
phi is a UFL expression of y evaluated at the quadrature points (degree 8); for ``sharp``
the interfaces must lie on mesh nodes (checked), so no cell straddles one.  Expected
errors: O(h^3 + dt^2) in L2 for the sharp case (smooth in each layer), less for a C^1
ramp.

Usage
=====
    /usr/bin/python3 reference/parallel_slab_1d.py run --mode oscillating --N 80 --dt 0.005 \\
        --t-end 4 --times 0.5 1 1.5 2 --out build/reference/slab
    /usr/bin/python3 reference/parallel_slab_1d.py steady          # check vs Couette/strain
    /usr/bin/python3 reference/parallel_slab_1d.py convergence     # orders (analytic + self)
    mpirun --oversubscribe -np 2 /usr/bin/python3 reference/parallel_slab_1d.py convergence

Python: ``solve(params) -> dict`` (see ``DEFAULTS``), ``periodic_solution``,
``steady_solution``.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc

DEFAULTS = dict(
    H=1.0,               # channel height; bottom wall y = 0 fixed, top wall y = H moves
    solid=(0.0, 0.5),    # solid layer y0 < y < y1 (y0 = 0: attached to the bottom wall)
    rho=1.0, mu_f=0.1, mu_s=0.1, G=1.0,
    V=1.0,               # wall speed (steady) or amplitude (oscillating)
    omega=np.pi,         # angular frequency of the oscillating wall
    mode="oscillating",  # "steady": u(H) = V;  "oscillating": u(H) = V sin(omega t)
    profile="sharp",     # "sharp" | "sin" | "tanh"
    width=0.05,          # smoothing half-width w of the phi profile
    N=80,                # cells
    dt=0.005,
    t_end=2.0,
    times=None,          # output times (default: t_end only)
    init="rest",         # "rest" or "periodic" (start on the analytic periodic state; sharp)
)


# ------------------------------------------------------------------ exact solutions
def _layers(p):
    """Piecewise-constant layers [(y_a, y_b, mu, G)] for the sharp profile."""
    y0, y1 = p["solid"]
    H = p["H"]
    out = []
    if y0 > 0:
        out.append((0.0, y0, p["mu_f"], 0.0))
    out.append((y0, y1, p["mu_s"], p["G"]))
    if y1 < H:
        out.append((y1, H, p["mu_f"], 0.0))
    return out


def periodic_amplitude(p):
    """Complex amplitude U(y) of the periodic state u = Im(U e^{i omega t}) (sharp phi)."""
    w, rho, V = p["omega"], p["rho"], p["V"]
    lay = _layers(p)
    n = len(lay)
    eta = [mu + G / (1j * w) for (_, _, mu, G) in lay]
    k = [np.sqrt(1j * w * rho / e) for e in eta]
    # unknowns (A_l, B_l), U_l = A_l exp(k_l (y - ya_l)) + B_l exp(-k_l (y - yb_l))
    # (shifted exponentials keep the system well conditioned for thin boundary layers)
    M = np.zeros((2 * n, 2 * n), complex)
    r = np.zeros(2 * n, complex)

    def val(l, y):
        ya, yb = lay[l][:2]
        return np.array([np.exp(k[l] * (y - ya)), np.exp(-k[l] * (y - yb))])

    def der(l, y):
        ya, yb = lay[l][:2]
        return eta[l] * k[l] * np.array([np.exp(k[l] * (y - ya)), -np.exp(-k[l] * (y - yb))])

    row = 0
    M[row, 0:2] = val(0, 0.0)
    row += 1
    for l in range(n - 1):
        yi = lay[l][1]
        M[row, 2 * l:2 * l + 2] = val(l, yi)
        M[row, 2 * l + 2:2 * l + 4] = -val(l + 1, yi)
        M[row + 1, 2 * l:2 * l + 2] = der(l, yi)
        M[row + 1, 2 * l + 2:2 * l + 4] = -der(l + 1, yi)
        row += 2
    M[row, 2 * n - 2:] = val(n - 1, lay[-1][1])
    r[row] = V
    c = np.linalg.solve(M, r)

    def U(y):
        y = np.asarray(y, float)
        out = np.zeros(y.shape, complex)
        for l, (ya, yb, _, _) in enumerate(lay):
            m = (y >= ya - 1e-14) & (y <= yb + 1e-14)
            out[m] = c[2 * l] * np.exp(k[l] * (y[m] - ya)) + c[2 * l + 1] * np.exp(-k[l] * (y[m] - yb))
        return out
    return U


def periodic_solution(p, y, t):
    """Exact periodic u(y, t), xi(y, t) (zero-mean displacement) for the sharp profile."""
    U = periodic_amplitude(p)(y)
    e = np.exp(1j * p["omega"] * t)
    return np.imag(U * e), np.imag(U / (1j * p["omega"]) * e)


def steady_solution(p, y):
    """Steady state for the wall moving at V (sharp or compact profile): u, tau, B_xy."""
    y = np.asarray(y, float)
    y0, y1 = p["solid"]
    w = p["width"] if p["profile"] == "sin" else 0.0
    if p["profile"] == "tanh":
        raise ValueError("tanh profile: phi > 0 everywhere, no finite-time steady state")
    lo, hi = (y0 - w if y0 > 0 else 0.0), y1 + w          # support of phi
    fl_below, fl_above = lo, p["H"] - hi
    tau = p["V"] / ((fl_below + fl_above) / p["mu_f"])
    Us = tau * fl_below / p["mu_f"]                         # rigid speed of the solid
    u = np.where(y < lo, tau * y / p["mu_f"], np.where(y > hi, Us + tau * (y - hi) / p["mu_f"], Us))
    return {"u": u, "tau": tau, "U_solid": Us, "B_xy_solid": tau / p["G"]}


# ------------------------------------------------------------------ the FE solver
def _phi_ufl(p, x):
    y0, y1 = p["solid"]
    prof, w = p["profile"], p["width"]
    # signed distance into the solid layer
    s = (y1 - x) if y0 <= 0 else ufl.min_value(x - y0, y1 - x)
    if prof == "sharp":
        return ufl.conditional(ufl.ge(s, 0.0), 1.0, 0.0)
    if prof == "sin":
        ramp = 0.5 * (1 + ufl.sin(np.pi * s / (2 * w)))
        return ufl.conditional(ufl.ge(s, w), 1.0, ufl.conditional(ufl.le(s, -w), 0.0, ramp))
    if prof == "tanh":
        return 0.5 * (1 + ufl.tanh(s / w))
    raise ValueError(prof)


def phi_numpy(p, y):
    y0, y1 = p["solid"]
    prof, w = p["profile"], p["width"]
    s = (y1 - y) if y0 <= 0 else np.minimum(y - y0, y1 - y)
    if prof == "sharp":
        return (s >= 0).astype(float)
    if prof == "sin":
        return np.where(s >= w, 1.0, np.where(s <= -w, 0.0, 0.5 * (1 + np.sin(np.pi * s / (2 * w)))))
    return 0.5 * (1 + np.tanh(s / w))


def wall_speed(p, t):
    return p["V"] if p["mode"] == "steady" else p["V"] * np.sin(p["omega"] * t)


def solve(params: dict, comm=MPI.COMM_WORLD) -> dict:
    """Solve the slab problem; returns (on every rank) y (P2 nodes, sorted), times,
    u[k], xi[k] (displacement), y_mid (cell midpoints), B_xy[k], sigma_xy[k] at y_mid,
    the exact periodic solution where available (u_exact, xi_exact), and wall time."""
    p = dict(DEFAULTS)
    p.update(params or {})
    H, N = p["H"], int(p["N"])
    times = sorted(p["times"]) if p["times"] else [p["t_end"]]
    t_end = max(times[-1], p["t_end"]) if p["times"] is None else times[-1]
    n_steps = int(round(t_end / p["dt"]))
    dt = t_end / n_steps
    out_steps = {int(round(t / dt)): t for t in times}
    for k, t in out_steps.items():
        if abs(k * dt - t) > 1e-9 * max(1, t):
            raise ValueError(f"output time {t} is not a multiple of dt = {dt}")
    if p["profile"] == "sharp":
        for yi in p["solid"]:
            if 0 < yi < H and abs(yi / H * N - round(yi / H * N)) > 1e-9:
                raise ValueError(f"sharp profile: interface y = {yi} must be on a node (N = {N})")
    t0 = time.time()

    mesh = dolfinx.mesh.create_interval(comm, N, [0.0, H])
    V = dolfinx.fem.FunctionSpace(mesh, ("Lagrange", 2))
    x = ufl.SpatialCoordinate(mesh)[0]
    phi = _phi_ufl(p, x)
    mu = (1 - phi) * p["mu_f"] + phi * p["mu_s"]
    Gphi = p["G"] * phi
    u, u_n, xi = (dolfinx.fem.Function(V) for _ in range(3))
    dtc = dolfinx.fem.Constant(mesh, PETSc.ScalarType(dt))
    uu, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 8})
    dy = lambda f: f.dx(0)  # noqa: E731
    F = (p["rho"] * (uu - u_n) / dtc * v
         + (mu * dy(uu + u_n) / 2 + Gphi * dy(xi + dtc / 4 * (uu + u_n))) * dy(v)) * dx
    a, L = dolfinx.fem.form(ufl.lhs(F)), dolfinx.fem.form(ufl.rhs(F))

    fdim = 0
    b0 = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda X: np.isclose(X[0], 0.0))
    b1 = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda X: np.isclose(X[0], H))
    u_top = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))
    bcs = [dolfinx.fem.dirichletbc(PETSc.ScalarType(0.0),
                                   dolfinx.fem.locate_dofs_topological(V, fdim, b0), V),
           dolfinx.fem.dirichletbc(u_top, dolfinx.fem.locate_dofs_topological(V, fdim, b1), V)]
    A = dolfinx.fem.petsc.assemble_matrix(a, bcs=bcs)
    A.assemble()
    b = dolfinx.fem.petsc.create_vector(L)
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")

    # initial state
    t = 0.0
    exact = p["profile"] == "sharp" and p["mode"] == "oscillating"
    if p["init"] == "periodic":
        if not exact:
            raise ValueError("init=periodic needs the sharp profile and the oscillating wall")
        u_n.interpolate(lambda X: periodic_solution(p, X[0], 0.0)[0])
        xi.interpolate(lambda X: periodic_solution(p, X[0], 0.0)[1])
    u.x.array[:] = u_n.x.array

    # gather helpers: owned P2 nodes -> rank 0 -> sorted -> broadcast
    imap = V.dofmap.index_map
    n_own = imap.size_local
    y_loc = V.tabulate_dof_coordinates()[:n_own, 0]
    y_all = np.concatenate(comm.allgather(y_loc))
    order = np.argsort(y_all, kind="stable")
    y_nodes = y_all[order]

    def gather(f):
        return np.concatenate(comm.allgather(f.x.array[:n_own].copy()))[order]

    y_mid = 0.5 * (y_nodes[:-2:2] + y_nodes[2::2])
    hcell = y_nodes[2::2] - y_nodes[:-2:2]
    phi_mid = phi_numpy(p, y_mid)
    mu_mid = (1 - phi_mid) * p["mu_f"] + phi_mid * p["mu_s"]

    rec = {"t": [], "u": [], "xi": [], "B_xy": [], "sigma_xy": []}

    def record(tt):
        un, xn = gather(u), gather(xi)
        Bxy = (xn[2::2] - xn[:-2:2]) / hcell
        dudy = (un[2::2] - un[:-2:2]) / hcell
        rec["t"].append(tt)
        rec["u"].append(un)
        rec["xi"].append(xn)
        rec["B_xy"].append(Bxy)
        rec["sigma_xy"].append(mu_mid * dudy + p["G"] * phi_mid * Bxy)

    if 0 in out_steps:
        record(0.0)
    for k in range(1, n_steps + 1):
        t = k * dt
        u_top.value = wall_speed(p, t)
        with b.localForm() as bl:
            bl.set(0.0)
        dolfinx.fem.petsc.assemble_vector(b, L)
        dolfinx.fem.petsc.apply_lifting(b, [a], bcs=[bcs])
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        dolfinx.fem.petsc.set_bc(b, bcs)
        ksp.solve(b, u.vector)
        u.x.scatter_forward()
        xi.x.array[:] += dt / 2 * (u.x.array + u_n.x.array)
        u_n.x.array[:] = u.x.array
        if k in out_steps:
            record(t)

    res = {k: np.array(v) for k, v in rec.items()}
    res.update(y=y_nodes, y_mid=y_mid, phi=phi_numpy(p, y_nodes), phi_mid=phi_mid, dt=dt,
               steps=n_steps, params=p, wall_seconds=time.time() - t0, ranks=comm.size)
    res["B_xx"] = 1 + res["B_xy"] ** 2
    if exact:
        ue = [periodic_solution(p, y_nodes, tt) for tt in res["t"]]
        res["u_exact"] = np.array([e[0] for e in ue])
        res["xi_exact"] = np.array([e[1] for e in ue])
    return res


def l2_nodes(y, f):
    """L2 norm from the P2 nodal values (vertex, midpoint, vertex per cell): Simpson's rule
    on f^2 per cell (4th-order accurate, ample for error norms of order <= 3)."""
    h = y[2::2] - y[:-2:2]
    f2 = f ** 2
    return np.sqrt(np.sum(h / 6 * (f2[:-2:2] + 4 * f2[1:-1:2] + f2[2::2])))


def l2_p2(y, f, exact):
    """True L2 norm of (P2 interpolant of the nodal values f) - exact(y): 5-point Gauss
    per cell.  (l2_nodes sees only nodal values, where 1D P2 Galerkin superconverges.)"""
    g, w = np.polynomial.legendre.leggauss(5)
    ya, ym, yb = y[:-2:2], y[1:-1:2], y[2::2]
    fa, fm, fb = f[:-2:2], f[1:-1:2], f[2::2]
    tot = 0.0
    for gk, wk in zip(g, w):
        s = (gk + 1) / 2                                   # 0..1 in the cell
        yk = ya + s * (yb - ya)
        fk = fa * (1 - s) * (1 - 2 * s) + fm * 4 * s * (1 - s) + fb * s * (2 * s - 1)
        tot += np.sum(wk / 2 * (yb - ya) * (fk - exact(yk)) ** 2)
    return np.sqrt(tot)


# ------------------------------------------------------------------ checks
def steady_check(p=None, comm=MPI.COMM_WORLD):
    """Run the steady moving wall long enough and compare with the steady state."""
    p = {**DEFAULTS, "N": 40, "dt": 0.02, "t_end": 60.0, **(p or {})}
    p["mode"], p["times"] = "steady", None
    r = solve(p, comm)
    st = steady_solution(p, r["y"])
    u = r["u"][-1]
    sig = r["sigma_xy"][-1]
    solid = r["phi_mid"] >= 1 - 1e-12
    return {"u_err_max": float(np.max(np.abs(u - st["u"]))),
            "tau_exact": st["tau"], "tau_min": float(sig.min()), "tau_max": float(sig.max()),
            "B_xy_solid_exact": st["B_xy_solid"],
            "B_xy_solid_err_max": float(np.max(np.abs(r["B_xy"][-1][solid] - st["B_xy_solid"]))),
            "t_end": p["t_end"], "N": p["N"], "dt": r["dt"], "profile": p["profile"],
            "wall_seconds": r["wall_seconds"]}


def convergence(Ns=(10, 20, 40, 80), c_dt=0.2, comm=MPI.COMM_WORLD, base=None, n_space=1000):
    """Orders in L2 at t = one period.  (1) sharp profile from the exact periodic state vs
    the exact solution, dt = c_dt * h (so the CN error dominates: order 2), and space
    alone (Richardson in time: order 3); (2) ``sin`` profile from rest, self-convergence."""
    base = dict(DEFAULTS, **(base or {}))
    T = 2 * np.pi / base["omega"]
    out = {"sharp_dt_prop_h": [], "sharp_space": [], "sin_self": []}
    for N in Ns:
        h = base["H"] / N
        n = int(np.ceil(T / (c_dt * h)))
        r = solve(dict(base, N=N, dt=T / n, times=[T], init="periodic"), comm)
        eu = l2_p2(r["y"], r["u"][-1], lambda yy: periodic_solution(base, yy, T)[0])
        ex = l2_p2(r["y"], r["xi"][-1], lambda yy: periodic_solution(base, yy, T)[1])
        out["sharp_dt_prop_h"].append({"N": N, "dt": r["dt"], "err_u": eu, "err_xi": ex})
    for N in Ns:
        # space alone: CN's error expands in even powers of dt, so Richardson extrapolation
        # (4 u_{dt/2} - u_dt)/3 of two runs removes the dt^2 term and leaves O(h^3 + dt^4)
        r1 = solve(dict(base, N=N, dt=T / n_space, times=[T], init="periodic"), comm)
        r2 = solve(dict(base, N=N, dt=T / (2 * n_space), times=[T], init="periodic"), comm)
        uR = (4 * r2["u"][-1] - r1["u"][-1]) / 3
        ex = lambda yy: periodic_solution(base, yy, T)[0]  # noqa: E731
        out["sharp_space"].append({"N": N, "dt": r2["dt"],
                                   "err_u": l2_p2(r1["y"], uR, ex),
                                   "err_u_nodes": l2_nodes(r1["y"], uR - r1["u_exact"][-1]),
                                   "err_u_no_extrapolation": l2_nodes(
                                       r2["y"], r2["u"][-1] - r2["u_exact"][-1])})
    sols = []
    for N in list(Ns) + [2 * Ns[-1]]:
        h = base["H"] / N
        n = int(np.ceil(T / (c_dt * h)))
        sols.append(solve(dict(base, N=N, dt=T / n, times=[T], profile="sin", init="rest"), comm))
    for i in range(len(Ns)):
        coarse, fine = sols[i], sols[i + 1]
        # nested meshes: coarse P2 node j is fine P2 node 2j
        out["sin_self"].append({"N": Ns[i], "diff_u": l2_nodes(
            coarse["y"], coarse["u"][-1] - fine["u"][-1][::2])})
    for key, ek in (("sharp_dt_prop_h", "err_u"), ("sharp_space", "err_u"),
                    ("sharp_space", "err_u_nodes"), ("sin_self", "diff_u")):
        e = np.array([row[ek] for row in out[key]])
        out["order_" + key + ("_nodes" if ek.endswith("nodes") else "")] = list(
            np.log2(e[:-1] / e[1:]))
    out["order_xi_sharp_dt_prop_h"] = list(np.log2(
        np.array([r["err_xi"] for r in out["sharp_dt_prop_h"]])[:-1]
        / np.array([r["err_xi"] for r in out["sharp_dt_prop_h"]])[1:]))
    return out


# ------------------------------------------------------------------ CLI
def _common(ap, **over):
    d = dict(DEFAULTS, **over)
    for k in ("H", "rho", "mu_f", "mu_s", "G", "V", "omega", "width", "dt", "t_end"):
        ap.add_argument("--" + k.replace("_", "-"), dest=k, type=float, default=d[k])
    ap.add_argument("--solid", type=float, nargs=2, default=DEFAULTS["solid"])
    ap.add_argument("--mode", choices=["steady", "oscillating"], default=DEFAULTS["mode"])
    ap.add_argument("--profile", choices=["sharp", "sin", "tanh"], default=DEFAULTS["profile"])
    ap.add_argument("--N", type=int, default=d["N"])
    ap.add_argument("--init", choices=["rest", "periodic"], default="rest")
    ap.add_argument("--out", default="build/reference/slab")


def _jsonable(o):
    if isinstance(o, dict):
        return {k: _jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_jsonable(v) for v in o]
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.generic):
        return o.item()
    return o


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="one solve; CSV (t, y, u, xi, phi) + JSON")
    _common(r)
    r.add_argument("--times", type=float, nargs="*", default=None)
    s = sub.add_parser("steady", help="steady moving wall vs the exact steady state")
    _common(s, N=40, dt=0.02, t_end=60.0)
    c = sub.add_parser("convergence", help="orders, oscillating wall")
    _common(c)
    c.add_argument("--Ns", type=int, nargs="+", default=[10, 20, 40, 80])
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    p = {k: getattr(args, k) for k in DEFAULTS if hasattr(args, k)}
    p["solid"] = tuple(args.solid)
    out = Path(args.out)
    say = print if comm.rank == 0 else (lambda *a, **k: None)
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    if args.cmd == "run":
        p["times"] = args.times
        res = solve(p, comm)
        rows = []
        for k, t in enumerate(res["t"]):
            for j, y in enumerate(res["y"]):
                rows.append([t, y, res["u"][k][j], res["xi"][k][j], res["phi"][j]])
        tag = f"slab_{p['mode']}_{p['profile']}_N{p['N']}"
        if comm.rank == 0:
            np.savetxt(out / f"{tag}.csv", np.array(rows), delimiter=",",
                       header="t,y,u,xi,phi", comments="")
            np.savetxt(out / f"{tag}_mid.csv", np.array(
                [[t, y, res["B_xy"][k][j], res["sigma_xy"][k][j], res["phi_mid"][j]]
                 for k, t in enumerate(res["t"]) for j, y in enumerate(res["y_mid"])]),
                delimiter=",", header="t,y_mid,B_xy,sigma_xy,phi", comments="")
            (out / f"{tag}.json").write_text(json.dumps(_jsonable(res), indent=None))
        say(f"{tag}: {res['steps']} steps, dt {res['dt']:.3g}, {res['wall_seconds']:.2f} s -> {out}")
        if "u_exact" in res:
            for k, t in enumerate(res["t"]):
                say(f"t {t:.4g}: |u - u_periodic|_L2 = {l2_nodes(res['y'], res['u'][k] - res['u_exact'][k]):.3e}")
    elif args.cmd == "steady":
        res = steady_check(p, comm)
        say(json.dumps(res, indent=1))
        if comm.rank == 0:
            (out / f"slab_steady_{p['profile']}.json").write_text(json.dumps(res, indent=1))
    else:
        res = convergence(tuple(args.Ns), comm=comm, base=p)
        say(json.dumps(_jsonable(res), indent=1))
        if comm.rank == 0:
            (out / "slab_convergence.json").write_text(json.dumps(_jsonable(res), indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
