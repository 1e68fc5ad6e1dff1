#!/usr/bin/python3
"""Taylor-Hood (P2/P1) Stokes and steady Navier-Stokes on a manufactured solution.

Equations
=========
On Omega = (0,1) x (0,1), find velocity u and pressure p with

    rho (u . grad) u - div sigma(u, p) = f,    div u = 0,
    sigma = -p I + 2 mu D(u),  D = (grad u + grad u^T)/2,

(``--equations stokes`` drops the convective term).  The exact solution is

    u = ( sin(pi x) cos(pi y), -cos(pi x) sin(pi y) )      (divergence free)
    p = cos(pi x) sin(pi y) + x y

and f is computed from it symbolically (UFL).  Boundary conditions: u = u_exact on
x = 0, y = 0 and y = 1; the exact traction sigma(u_ex, p_ex) n on x = 1 (natural
condition), which also fixes the pressure level (no null space).

Weak form (Taylor-Hood, inf-sup stable, no stabilisation needed):

    int rho (u.grad u).v + 2 mu D(u):D(v) - p div v - q div u dx
        = int f.v dx + int_{x=1} (sigma_ex n).v ds

Navier-Stokes is solved by Newton's method (UFL derivative), Stokes by one linear solve;
both with a MUMPS LU factorisation.  Expected L2 orders: velocity 3, pressure 2
(H1 velocity 2).  Errors are integrated with raised quadrature and summed over ranks.

The mesh is a structured triangulation with nx = N, ny = 3N/2 (anisotropic on purpose).

Unsteady: 2D Taylor-Green vortex (``--equations taylor-green``)
=============================================================
The exact decaying Navier-Stokes solution on Omega = (0, L)^2, L = 2 pi, k = 2 pi / L:

    u = U ( sin(kx) cos(ky), -cos(kx) sin(ky) ) F(t),   F = exp(-2 nu k^2 t)
    p = rho U^2 / 4 (cos 2kx + cos 2ky) F(t)^2,          f = 0

(U = 1, rho = 1, nu = 0.01, i.e. Re = U L / (2 pi nu) = 100, to t = 1: the problem the
efsi solver runs in verification/studies/flow_mms.py.)  No periodic constraint exists in
DOLFINx 0.5 without dolfinx_mpc, so the FE problem is posed on the same square with the
exact velocity on x = 0, y = 0, y = L and the exact traction sigma(u, p) n on x = L
(the normal velocity vanishes on every side, so that side has no inflow; the natural
condition fixes the pressure level).  Starting from the exact u(0).

Discretisation: Taylor-Hood P2/P1 in space; in time Crank-Nicolson for the viscous term
with the pressure implicit (a Lagrange multiplier at t^(n+1/2)) and second-order
Adams-Bashforth for the convective term (explicit Euler on the first step, whose O(dt^2)
local error keeps the scheme second order):

    rho (u^{n+1} - u^n)/dt + rho [3/2 (u^n.grad)u^n - 1/2 (u^{n-1}.grad)u^{n-1}]
        - div( mu (D(u^{n+1}) + D(u^n)) ) + grad p^{n+1/2} = 0,  div u^{n+1} = 0,

and the traction on x = L is the average of the exact traction at t^n and t^(n+1).  The
matrix does not change, so MUMPS factorises it once.  Time step dt = cfl h / U
(h = L / N, ``--cfl``, default 0.15).  Why 0.15: the explicit AB2 convection has a stability
limit; on N = 32 the velocity error is 2.649e-3 for 30 or more steps (cfl <= 0.17), 2.655e-3
at cfl 0.19, 7.0e-3 at cfl 0.24 and 1.2e-2 at cfl 0.25 (the P2 nodes are h/2 apart), so
0.15 keeps the result converged in time (the time error is otherwise negligible: the
convective term of this solution is a pure gradient, absorbed by the pressure).  Errors at
t = T: ||u_h - u||_L2 and its area-normalised value ||.||_L2 / L (err_u_rms, the measure
of the efsi study: the RMS of the error); the RMS of the nodal errors at the P2 velocity
dofs (err_u_nodes_rms, the analogue of the efsi study's error at its own unknowns); p_h
against the exact p at T - dt/2.

Observed: velocity L2 errors 4.8e-1, 3.9e-2, 2.6e-3, 1.8e-4 on N = 8, 16, 32, 64 (orders
3.6, 3.9, 3.9), several times the P2 interpolation error of the exact field (4.9e-3,
6.1e-4, 7.6e-5 on N = 16, 32, 64).  That is the known lack of pressure robustness of
Taylor-Hood: the velocity error carries a term ~ (1/nu) x (best approximation error of p),
and this flow's pressure is large against its viscous forces (nu = 0.01); see John,
Linke, Merdon, Neilan & Rebholz, SIAM Review 59 (2017) 492.

Usage
=====
    /usr/bin/python3 reference/flow_mms.py --N 8 16 32 64
    mpirun --oversubscribe -np 2 /usr/bin/python3 reference/flow_mms.py --equations navier-stokes
    /usr/bin/python3 reference/flow_mms.py --equations taylor-green --N 8 16 32 64
"""
from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import dolfinx.nls.petsc

logging.getLogger().setLevel(logging.WARNING)
LU = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}


def exact(x):
    """UFL exact solution on SpatialCoordinate x."""
    pi = ufl.pi
    u = ufl.as_vector((ufl.sin(pi * x[0]) * ufl.cos(pi * x[1]),
                       -ufl.cos(pi * x[0]) * ufl.sin(pi * x[1])))
    p = ufl.cos(pi * x[0]) * ufl.sin(pi * x[1]) + x[0] * x[1]
    return u, p


def sym_grad(u):
    return ufl.sym(ufl.grad(u))


def solve(comm, N, equations="stokes", rho=1.0, mu=0.1):
    mesh = dolfinx.mesh.create_rectangle(comm, [np.array([0.0, 0.0]), np.array([1.0, 1.0])],
                                         [N, (3 * N) // 2], dolfinx.mesh.CellType.triangle)
    cell = mesh.ufl_cell()
    W = dolfinx.fem.FunctionSpace(mesh, ufl.MixedElement(
        [ufl.VectorElement("Lagrange", cell, 2), ufl.FiniteElement("Lagrange", cell, 1)]))
    x = ufl.SpatialCoordinate(mesh)
    u_ex, p_ex = exact(x)
    sigma_ex = -p_ex * ufl.Identity(2) + 2 * mu * sym_grad(u_ex)
    f = -ufl.div(sigma_ex)
    if equations == "navier-stokes":
        f = f + rho * ufl.grad(u_ex) * u_ex

    # Dirichlet velocity on x=0, y=0, y=1
    fdim = mesh.topology.dim - 1
    facets = dolfinx.mesh.locate_entities_boundary(
        mesh, fdim, lambda X: np.isclose(X[0], 0.0) | np.isclose(X[1], 0.0) | np.isclose(X[1], 1.0))
    W0 = W.sub(0)
    V, _ = W0.collapse()
    u_bc = dolfinx.fem.Function(V)
    u_bc.interpolate(lambda X: np.vstack([np.sin(np.pi * X[0]) * np.cos(np.pi * X[1]),
                                          -np.cos(np.pi * X[0]) * np.sin(np.pi * X[1])]))
    dofs = dolfinx.fem.locate_dofs_topological((W0, V), fdim, facets)
    bc = dolfinx.fem.dirichletbc(u_bc, dofs, W0)

    n = ufl.FacetNormal(mesh)
    dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 6})
    ds = ufl.Measure("ds", domain=mesh, metadata={"quadrature_degree": 6})
    v, q = ufl.TestFunctions(W)
    rhs = ufl.inner(f, v) * dx + ufl.inner(sigma_ex * n, v) * ds   # traction on x=1 only:
    # on the Dirichlet sides the test function vanishes, so ds over the whole boundary is fine

    t0 = time.time()
    if equations == "stokes":
        u, p = ufl.TrialFunctions(W)
        a = (2 * mu * ufl.inner(sym_grad(u), sym_grad(v)) - p * ufl.div(v) - q * ufl.div(u)) * dx
        w = dolfinx.fem.petsc.LinearProblem(a, rhs, bcs=[bc], petsc_options=LU).solve()
    else:
        w = dolfinx.fem.Function(W)
        u, p = ufl.split(w)
        F = (rho * ufl.inner(ufl.grad(u) * u, v) + 2 * mu * ufl.inner(sym_grad(u), sym_grad(v))
             - p * ufl.div(v) - q * ufl.div(u)) * dx - rhs
        problem = dolfinx.fem.petsc.NonlinearProblem(F, w, bcs=[bc])
        newton = dolfinx.nls.petsc.NewtonSolver(comm, problem)
        newton.rtol, newton.atol, newton.max_it = 1e-12, 1e-13, 25
        ksp = newton.krylov_solver
        ksp.setType("preonly")
        ksp.getPC().setType("lu")
        ksp.getPC().setFactorSolverType("mumps")
        its, converged = newton.solve(w)
        assert converged, "Newton did not converge"
    seconds = time.time() - t0

    uh, ph = w.sub(0).collapse(), w.sub(1).collapse()
    integ = lambda e: comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(e * dx)),  # noqa: E731
                                     op=MPI.SUM)
    e_u = np.sqrt(integ(ufl.inner(uh - u_ex, uh - u_ex)))
    e_uh1 = np.sqrt(integ(ufl.inner(ufl.grad(uh - u_ex), ufl.grad(uh - u_ex))))
    e_p = np.sqrt(integ((ph - p_ex) ** 2))
    div = np.sqrt(integ(ufl.div(uh) ** 2))
    ndofs = W.dofmap.index_map.size_global * W.dofmap.index_map_bs
    return {"N": N, "h": 1.0 / N, "dofs": int(ndofs), "err_u_L2": e_u, "err_u_H1": e_uh1,
            "err_p_L2": e_p, "div_u_L2": div, "solve_seconds": seconds}


def solve_taylor_green(comm, N, rho=1.0, nu=0.01, U=1.0, t_end=1.0, cfl=0.15, steps=None):
    """Taylor-Green vortex to t_end on an N x N mesh of (0, 2 pi)^2 (module docstring)."""
    t_start = time.time()
    L = 2 * np.pi
    k = 2 * np.pi / L
    mu = rho * nu
    mesh = dolfinx.mesh.create_rectangle(comm, [np.array([0.0, 0.0]), np.array([L, L])],
                                         [N, N], dolfinx.mesh.CellType.triangle)
    cell = mesh.ufl_cell()
    W = dolfinx.fem.FunctionSpace(mesh, ufl.MixedElement(
        [ufl.VectorElement("Lagrange", cell, 2), ufl.FiniteElement("Lagrange", cell, 1)]))
    h = L / N
    n_steps = steps if steps else int(np.ceil(t_end * U / (cfl * h) - 1e-9))
    dt = t_end / n_steps

    def decay(tt, power=1):
        return np.exp(-2 * power * nu * k * k * tt)

    def u_exact_np(tt):
        return lambda X: np.vstack([U * np.sin(k * X[0]) * np.cos(k * X[1]) * decay(tt),
                                    -U * np.cos(k * X[0]) * np.sin(k * X[1]) * decay(tt)])

    x = ufl.SpatialCoordinate(mesh)
    tc = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))   # time at which exact fields live

    def exact_ufl(t_ufl):
        F = ufl.exp(-2 * nu * k * k * t_ufl)
        u = U * F * ufl.as_vector((ufl.sin(k * x[0]) * ufl.cos(k * x[1]),
                                   -ufl.cos(k * x[0]) * ufl.sin(k * x[1])))
        p = rho * U * U / 4 * (ufl.cos(2 * k * x[0]) + ufl.cos(2 * k * x[1])) * F * F
        return u, p

    def sigma(u, p):
        return -p * ufl.Identity(2) + 2 * mu * sym_grad(u)

    # boundary: Dirichlet u on x = 0, y = 0, y = L; traction on x = L
    fdim = mesh.topology.dim - 1
    facets = dolfinx.mesh.locate_entities_boundary(
        mesh, fdim, lambda X: np.isclose(X[0], 0.0) | np.isclose(X[1], 0.0) | np.isclose(X[1], L))
    W0 = W.sub(0)
    V, _ = W0.collapse()
    u_bc = dolfinx.fem.Function(V)
    dofs = dolfinx.fem.locate_dofs_topological((W0, V), fdim, facets)
    bc = dolfinx.fem.dirichletbc(u_bc, dofs, W0)

    w, w_n, w_nm1 = (dolfinx.fem.Function(W) for _ in range(3))
    u_n, u_nm1 = ufl.split(w_n)[0], ufl.split(w_nm1)[0]
    u0 = dolfinx.fem.Function(V)
    u0.interpolate(u_exact_np(0.0))
    sub_dofs = W0.collapse()[1]
    w_n.x.array[sub_dofs] = u0.x.array
    w_nm1.x.array[:] = w_n.x.array

    dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 6})
    ds = ufl.Measure("ds", domain=mesh, metadata={"quadrature_degree": 6})
    n = ufl.FacetNormal(mesh)
    uu, pp = ufl.TrialFunctions(W)
    v, q = ufl.TestFunctions(W)
    idt = dolfinx.fem.Constant(mesh, PETSc.ScalarType(1.0 / dt))
    ab = dolfinx.fem.Constant(mesh, PETSc.ScalarType(1.0))   # AB weights: (1, 0) first step
    ab_old = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))
    # Crank-Nicolson: half of the viscous form 2 mu D(u):D(v) at t^(n+1), half at t^n
    a = (rho * idt * ufl.inner(uu, v) + mu * ufl.inner(sym_grad(uu), sym_grad(v))
         - pp * ufl.div(v) - q * ufl.div(uu)) * dx
    conv = ab * ufl.grad(u_n) * u_n - ab_old * ufl.grad(u_nm1) * u_nm1
    u_a, p_a = exact_ufl(tc)
    u_b, p_b = exact_ufl(tc + 1.0 / idt)
    traction = 0.5 * (sigma(u_a, p_a) + sigma(u_b, p_b)) * n
    Lf = (rho * idt * ufl.inner(u_n, v) - mu * ufl.inner(sym_grad(u_n), sym_grad(v))
          - rho * ufl.inner(conv, v)) * dx + ufl.inner(traction, v) * ds
    a_form, L_form = dolfinx.fem.form(a), dolfinx.fem.form(Lf)
    A = dolfinx.fem.petsc.assemble_matrix(a_form, bcs=[bc])
    A.assemble()
    b = dolfinx.fem.petsc.create_vector(L_form)
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    t_setup = time.time() - t_start

    for step in range(n_steps):
        t0 = step * dt
        tc.value = t0
        if step == 1:
            ab.value, ab_old.value = 1.5, 0.5
        u_bc.interpolate(u_exact_np(t0 + dt))
        with b.localForm() as bl:
            bl.set(0.0)
        dolfinx.fem.petsc.assemble_vector(b, L_form)
        dolfinx.fem.petsc.apply_lifting(b, [a_form], bcs=[[bc]])
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        dolfinx.fem.petsc.set_bc(b, [bc])
        ksp.solve(b, w.vector)
        w.x.scatter_forward()
        w_nm1.x.array[:] = w_n.x.array
        w_n.x.array[:] = w.x.array
    seconds = time.time() - t_start

    T = n_steps * dt
    uT, _ = exact_ufl(dolfinx.fem.Constant(mesh, PETSc.ScalarType(T)))
    _, p_half = exact_ufl(dolfinx.fem.Constant(mesh, PETSc.ScalarType(T - 0.5 * dt)))
    uh, ph = w.sub(0).collapse(), w.sub(1).collapse()
    integ = lambda e: comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(e * dx)),  # noqa: E731
                                     op=MPI.SUM)
    e_u = np.sqrt(integ(ufl.inner(uh - uT, uh - uT)))
    e_uh1 = np.sqrt(integ(ufl.inner(ufl.grad(uh - uT), ufl.grad(uh - uT))))
    e_p = np.sqrt(integ((ph - p_half) ** 2))
    div = np.sqrt(integ(ufl.div(uh) ** 2))
    # RMS of the errors at the P2 velocity nodes (on this structured mesh: the uniform grid
    # of spacing h/2, boundary nodes included)
    Vc = uh.function_space
    n_own = Vc.dofmap.index_map.size_local
    X = Vc.tabulate_dof_coordinates()[:n_own].T
    e_nodes = uh.x.array[:2 * n_own].reshape(-1, 2).T - u_exact_np(T)(X)
    sq = comm.allreduce(float(np.sum(e_nodes ** 2)), op=MPI.SUM)
    cnt = comm.allreduce(n_own, op=MPI.SUM)
    ndofs = W.dofmap.index_map.size_global * W.dofmap.index_map_bs
    return {"N": N, "h": h, "dt": dt, "steps": n_steps, "cfl": U * dt / h, "t_end": T,
            "dofs": int(ndofs), "err_u_L2": e_u, "err_u_rms": e_u / L,
            "err_u_nodes_rms": float(np.sqrt(sq / cnt)), "err_u_H1": e_uh1,
            "err_p_L2": e_p, "div_u_L2": div, "setup_seconds": t_setup,
            "solve_seconds": seconds}


def orders(rows, key):
    h = np.array([r["h"] for r in rows])
    e = np.array([r[key] for r in rows])
    return list(np.log(e[1:] / e[:-1]) / np.log(h[1:] / h[:-1]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--N", type=int, nargs="+", default=[8, 16, 32, 64])
    ap.add_argument("--equations", default="stokes",
                    choices=["stokes", "navier-stokes", "taylor-green"])
    ap.add_argument("--rho", type=float, default=1.0)
    ap.add_argument("--mu", type=float, default=0.1, help="viscosity (stokes, navier-stokes)")
    ap.add_argument("--nu", type=float, default=0.01, help="nu = mu/rho (taylor-green)")
    ap.add_argument("--t-end", dest="t_end", type=float, default=1.0, help="(taylor-green)")
    ap.add_argument("--cfl", type=float, default=0.15, help="U dt / h (taylor-green)")
    ap.add_argument("--steps", type=int, default=None,
                    help="number of time steps, overrides --cfl (taylor-green)")
    ap.add_argument("--small", action="store_true", help="N = 4 8 16 (tests)")
    ap.add_argument("--out", default="build/reference/flow_mms")
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    Ns = [4, 8, 16] if args.small else args.N
    rows = []
    for N in Ns:
        if args.equations == "taylor-green":
            r = solve_taylor_green(comm, N, args.rho, args.nu, 1.0, args.t_end, args.cfl,
                                   args.steps)
        else:
            r = solve(comm, N, args.equations, args.rho, args.mu)
        rows.append(r)
        if comm.rank == 0:
            print(f"N {N:4d} dofs {r['dofs']:7d}  |u-u_h| {r['err_u_L2']:.3e}  "
                  f"|grad(u-u_h)| {r['err_u_H1']:.3e}  |p-p_h| {r['err_p_L2']:.3e}  "
                  f"({r['solve_seconds']:.2f} s)", flush=True)
    res = {"equations": args.equations, "rho": args.rho, "ranks": comm.size,
           "rows": rows, "order_u_L2": orders(rows, "err_u_L2"),
           "order_u_H1": orders(rows, "err_u_H1"), "order_p_L2": orders(rows, "err_p_L2")}
    if args.equations == "taylor-green":
        res.update(nu=args.nu, t_end=args.t_end, cfl=args.cfl)
    else:
        res["mu"] = args.mu
    if comm.rank == 0:
        print("orders u L2", np.round(res["order_u_L2"], 2), " u H1",
              np.round(res["order_u_H1"], 2), " p L2", np.round(res["order_p_L2"], 2))
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / f"mms_{args.equations}.json").write_text(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
