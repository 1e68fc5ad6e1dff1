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

Usage
=====
    /usr/bin/python3 reference/flow_mms.py --N 8 16 32 64
    mpirun --oversubscribe -np 2 /usr/bin/python3 reference/flow_mms.py --equations navier-stokes
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


def orders(rows, key):
    h = np.array([r["h"] for r in rows])
    e = np.array([r[key] for r in rows])
    return list(np.log(e[1:] / e[:-1]) / np.log(h[1:] / h[:-1]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--N", type=int, nargs="+", default=[8, 16, 32, 64])
    ap.add_argument("--equations", default="stokes", choices=["stokes", "navier-stokes"])
    ap.add_argument("--rho", type=float, default=1.0)
    ap.add_argument("--mu", type=float, default=0.1)
    ap.add_argument("--small", action="store_true", help="N = 4 8 16 (tests)")
    ap.add_argument("--out", default="build/reference/flow_mms")
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    Ns = [4, 8, 16] if args.small else args.N
    rows = []
    for N in Ns:
        r = solve(comm, N, args.equations, args.rho, args.mu)
        rows.append(r)
        if comm.rank == 0:
            print(f"N {N:4d} dofs {r['dofs']:7d}  |u-u_h| {r['err_u_L2']:.3e}  "
                  f"|grad(u-u_h)| {r['err_u_H1']:.3e}  |p-p_h| {r['err_p_L2']:.3e}  "
                  f"({r['solve_seconds']:.2f} s)", flush=True)
    res = {"equations": args.equations, "rho": args.rho, "mu": args.mu, "ranks": comm.size,
           "rows": rows, "order_u_L2": orders(rows, "err_u_L2"),
           "order_u_H1": orders(rows, "err_u_H1"), "order_p_L2": orders(rows, "err_p_L2")}
    if comm.rank == 0:
        print("orders u L2", np.round(res["order_u_L2"], 2), " u H1",
              np.round(res["order_u_H1"], 2), " p L2", np.round(res["order_p_L2"], 2))
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / f"mms_{args.equations}.json").write_text(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
