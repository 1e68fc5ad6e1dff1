#!/usr/bin/python3
"""Lagrangian membrane stress on a triangulated surface (FEniCSx reference).

Problem
=======
A membrane with reference surface S_R (points X) is moved by a prescribed map
x = chi(X) onto the deformed surface S.  We compute, on S:

* the surface deformation gradient F (tangent of S_R -> tangent of S) and
  Bs = F F^T (MODEL.md: Bs = P Gs P with Gs = F P_R F^T);
* the in-plane Cauchy tension tau_s(Bs) of the neo-Hookean or Skalak law
  (``membrane_laws.py``);
* the membrane load q (force per unit *deformed* area exerted by the membrane on its
  surroundings), defined by virtual work:

      int_S q . w da = - int_S tau_s : grad_s w da      for all w,          (1)

  i.e. q = div_s tau_s in the weak sense.  Solving (1) in a finite element space is
  an L2 (mass-matrix) projection of the distributional surface divergence;
* its normal and tangential parts q_n = q . n,  q_t = (I - n n) q;
* the total elastic energy E = int_{S_R} Ws dA = int_S Ws / J da.

Discretisation
==============
Isoparametric Lagrange elements of degree k (1 or 2): the surface is the P_k
interpolant of the exact surface, the map is interpolated at the geometry nodes.
We store the *reference* position as a P_k field X(x) on the deformed mesh, so that

      H = grad_s X = F^+      (the pseudo-inverse of F: deformed tangent -> reference)
      Bs = (H^T H)^+ = inv(H^T H + n n) - n n

with n the deformed unit normal (UFL ``CellNormal``, oriented outwards per cell).
UFL's ``grad`` on a tdim-2 / gdim-3 mesh is the surface gradient, so (1) is written
exactly as printed.  Integrals use a fixed quadrature degree (the integrands are
rational functions of the nodal positions).

Closed forms used for verification
==================================
Uniform inflation x = s X of a sphere of radius R0: Bs = s^2 P, J = s^2, so the tension
is isotropic, tau_s = T P, with (``membrane_laws.isotropic_tension``)

      neo-Hookean   T = Es/3 (1 - s^-6)
      Skalak        T = 2Es/3 (s^2 - 1 + alpha s^2 (s^4 - 1)),

and q = div_s(T P) = -(2T/R) n with R = s R0: purely normal, inward, no tangential part.

Uniaxial stretch of a flat sheet with T2 = 0 is in MODEL.md "Constitutive checks";
here lambda2 is found by solving T2(lambda1, lambda2) = 0 with the FE tension, and T1 is
compared with the closed form and with the digitised data of Barthes-Biesel et al. 2002.

A discrete virtual-work identity checks the law implementation independently of mesh
size: d/deps E(x + eps dx) = int_S tau_s : grad_s dx da (the tension is the derivative of
the energy), verified by a central finite difference.

Usage
=====
    /usr/bin/python3 reference/membrane_stress.py single --shape rbc --map inflate:1.1
    /usr/bin/python3 reference/membrane_stress.py convergence --levels 1 2 3 4
    /usr/bin/python3 reference/membrane_stress.py uniaxial
    mpirun --oversubscribe -np 2 /usr/bin/python3 reference/membrane_stress.py convergence
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
import dolfinx.io

sys.path.insert(0, str(Path(__file__).resolve().parent))
import membrane_laws as laws  # noqa: E402
import surface_meshes as sm  # noqa: E402

DATA = Path(__file__).resolve().parent.parent / "verification" / "data"
logging.getLogger().setLevel(logging.WARNING)   # silence the JIT compiler chatter


def allsum(comm, local):
    return comm.allreduce(local, op=MPI.SUM)


class Membrane:
    """A surface mesh that can be moved by a map, with the membrane operators on it."""

    def __init__(self, comm, nodes, cells, outward, degree=1, law="neo-hookean", Es=1.0,
                 alpha=1.0):
        self.comm, self.degree, self.law, self.Es, self.alpha = comm, degree, law, Es, alpha
        self.mesh = sm.create_surface_mesh(comm, nodes, cells, degree)
        self.X0 = self.mesh.geometry.x.copy()                 # reference node positions
        # outward orientation per cell (fixed by the reference configuration; maps used
        # here preserve orientation, so it stays valid on the deformed surface)
        self.Q0 = dolfinx.fem.FunctionSpace(self.mesh, ("DG", 0))
        self.orient = dolfinx.fem.Function(self.Q0)
        n_loc = self.Q0.dofmap.index_map.size_local + self.Q0.dofmap.index_map.num_ghosts
        self.orient.x.array[:n_loc] = sm.cell_orientation(self.mesh, outward)
        self.V = dolfinx.fem.VectorFunctionSpace(self.mesh, ("CG", degree))
        self.S = dolfinx.fem.FunctionSpace(self.mesh, ("CG", degree))
        self.Xref = dolfinx.fem.Function(self.V, name="X_reference")
        self.Xref.interpolate(lambda x: x)                   # exact at the P_k nodes
        self.dx = ufl.Measure("dx", domain=self.mesh,
                              metadata={"quadrature_degree": 2 * degree + 2})

    # ------------------------------------------------------------------ geometry
    def deform(self, mapping):
        """Move every geometry node: x = mapping(X) (mapping acts on (N, 3) arrays)."""
        self.mesh.geometry.x[:, :] = mapping(self.X0)

    def kinematics(self):
        n = self.orient * ufl.CellNormal(self.mesh)
        I = ufl.Identity(3)
        nn = ufl.outer(n, n)
        H = ufl.grad(self.Xref)                               # = F^+
        Bs = ufl.inv(H.T * H + nn) - nn
        return n, I - nn, Bs

    def stress(self):
        n, P, Bs = self.kinematics()
        tau, W, J = laws.tension(self.law, Bs, P, self.Es, self.alpha)
        return n, P, Bs, tau, W, J

    # ------------------------------------------------------------------ outputs
    def energy(self):
        _, _, _, _, W, J = self.stress()
        return allsum(self.comm, dolfinx.fem.assemble_scalar(dolfinx.fem.form(W / J * self.dx)))

    def area(self):
        one = dolfinx.fem.Constant(self.mesh, PETSc.ScalarType(1.0))
        return allsum(self.comm, dolfinx.fem.assemble_scalar(dolfinx.fem.form(one * self.dx)))

    def virtual_work(self, field):
        """int_S tau : grad_s dx da for a P_k field dx."""
        _, _, _, tau, _, _ = self.stress()
        return allsum(self.comm, dolfinx.fem.assemble_scalar(
            dolfinx.fem.form(ufl.inner(tau, ufl.grad(field)) * self.dx)))

    def project(self, expr, space, name):
        u, v = ufl.TrialFunction(space), ufl.TestFunction(space)
        L = ufl.inner(expr, v) * self.dx
        return self._solve_mass(space, L, name)

    def _solve_mass(self, space, L, name):
        u, v = ufl.TrialFunction(space), ufl.TestFunction(space)
        problem = dolfinx.fem.petsc.LinearProblem(
            ufl.inner(u, v) * self.dx, L, bcs=[],
            petsc_options={"ksp_type": "cg", "pc_type": "jacobi", "ksp_rtol": 1e-13,
                           "ksp_atol": 1e-30, "ksp_max_it": 5000})
        f = problem.solve()
        f.name = name
        return f

    def load(self):
        """q from (1); returns q, q_n, q_t and the tension as P_k fields."""
        n, P, Bs, tau, W, J = self.stress()
        w = ufl.TestFunction(self.V)
        q = self._solve_mass(self.V, -ufl.inner(tau, ufl.grad(w)) * self.dx, "load")
        qn = self.project(ufl.dot(q, n), self.S, "load_normal")
        qt = self.project(ufl.dot(P, q), self.V, "load_tangential")
        return q, qn, qt

    def principal_tensions(self):
        """P_k projections of the two in-plane principal tensions (tr and det of tau)."""
        n, P, Bs, tau, W, J = self.stress()
        tr = ufl.tr(tau)
        det2 = (tr ** 2 - ufl.tr(tau * tau)) / 2                # product of the two
        disc = ufl.sqrt(ufl.max_value(tr ** 2 / 4 - det2, 0.0))
        T1 = self.project(tr / 2 + disc, self.S, "tension_1")
        T2 = self.project(tr / 2 - disc, self.S, "tension_2")
        Jf = self.project(J, self.S, "area_ratio")
        return T1, T2, Jf

    def write(self, path: Path, functions):
        """XDMF (dolfinx) plus a meshio-written VTU of the same point data."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with dolfinx.io.XDMFFile(self.comm, str(path.with_suffix(".xdmf")), "w") as f:
            f.write_mesh(self.mesh)
            for g in functions:
                f.write_function(g)
        write_vtu(self, path.with_suffix(".vtu"), functions)


def write_vtu(mem: Membrane, path: Path, functions):
    """Gather P_k point data on rank 0 (original node numbering) and write with meshio."""
    import meshio
    mesh = mem.mesh
    tdim = mesh.topology.dim
    n_cells = mesh.topology.index_map(tdim).size_local
    g_dofs = mesh.geometry.dofmap.array.reshape(-1, mesh.geometry.dofmap.links(0).size)[:n_cells]
    igi = np.asarray(mesh.geometry.input_global_indices)[g_dofs]
    local = {"igi": igi.ravel(), "x": mesh.geometry.x[g_dofs].reshape(-1, 3),
             "cells": igi}
    for f in functions:
        bs = f.function_space.dofmap.index_map_bs
        dofs = np.array([f.function_space.dofmap.cell_dofs(c) for c in range(n_cells)])
        vals = f.x.array.reshape(-1, bs)[dofs.ravel()]
        local[f.name] = vals
    gathered = mem.comm.gather(local, root=0)
    if mem.comm.rank != 0:
        return
    igi = np.concatenate([g["igi"] for g in gathered])
    n_nodes = igi.max() + 1
    pts = np.zeros((n_nodes, 3))
    pts[igi] = np.concatenate([g["x"] for g in gathered])
    cells = np.concatenate([g["cells"] for g in gathered])
    if cells.shape[1] == 6:                   # DOLFINx -> VTK triangle6 node order
        cells, ctype = cells[:, [0, 1, 2, 5, 3, 4]], "triangle6"
    else:
        ctype = "triangle"
    pdata = {}
    for f in functions:
        v = np.concatenate([g[f.name] for g in gathered])
        arr = np.zeros((n_nodes, v.shape[1]))
        arr[igi] = v
        pdata[f.name] = arr[:, 0] if arr.shape[1] == 1 else arr
    meshio.write(str(path), meshio.Mesh(pts, [(ctype, cells)], point_data=pdata))


# ---------------------------------------------------------------------- maps
def parse_map(spec: str):
    """inflate:s | linear:F11,F12,F13,F21,...,F33 | file:PATH (rows X Y Z x y z)."""
    kind, _, arg = spec.partition(":")
    if kind == "inflate":
        s = float(arg)
        return lambda X: s * X
    if kind == "linear":
        F = np.array([float(a) for a in arg.split(",")]).reshape(3, 3)
        return lambda X: X @ F.T
    if kind == "file":
        return map_from_file(arg)
    raise ValueError(f"unknown map {spec!r}")


def map_from_file(path, tol=1e-8):
    """A map given as displaced points: each row 'X Y Z x y z'.  Every mesh node must
    coincide (to tol x size) with one listed reference point."""
    from scipy.spatial import cKDTree
    data = np.loadtxt(path, delimiter=None if not str(path).endswith(".csv") else ",")
    tree = cKDTree(data[:, :3])
    size = np.ptp(data[:, :3], axis=0).max()

    def m(X):
        dist, idx = tree.query(X)
        if X.shape[0] and dist.max() > tol * size:
            raise ValueError(f"map file {path}: a mesh node is {dist.max():.3g} from every "
                             "listed reference point (the file must list the mesh nodes)")
        return data[idx, 3:]
    return m


def build(args, comm):
    if args.shape == "sheet":
        nodes, cells, outward = sm.flat_sheet(2 ** args.level, 2 ** args.level, degree=args.degree)
    else:
        params = {"R0": args.R0} if args.R0 is not None else {}
        nodes, cells, outward = sm.closed_surface(args.shape, args.level, args.degree, params)
    return Membrane(comm, nodes, cells, outward, args.degree, args.law, args.Es, args.alpha)


# ---------------------------------------------------------------------- studies
def sphere_inflation_errors(comm, level, degree, law, Es, alpha, s, R0=1.0):
    """Relative L2 errors of q, q_n, and |q_t| against the closed form on level ``level``."""
    nodes, cells, outward = sm.closed_surface("sphere", level, degree, {"R0": R0})
    mem = Membrane(comm, nodes, cells, outward, degree, law, Es, alpha)
    mem.deform(lambda X: s * X)
    q, qn, qt = mem.load()
    T = laws.isotropic_tension(law, s, Es, alpha)
    R = s * R0
    x = ufl.SpatialCoordinate(mem.mesh)
    n_ex = x / ufl.sqrt(ufl.dot(x, x))
    q_ex = -(2 * T / R) * n_ex
    integ = lambda e: allsum(comm, dolfinx.fem.assemble_scalar(dolfinx.fem.form(e * mem.dx)))  # noqa: E731
    norm_ex = np.sqrt(integ(ufl.dot(q_ex, q_ex)))
    e_q = np.sqrt(integ(ufl.dot(q - q_ex, q - q_ex))) / norm_ex
    e_n = np.sqrt(integ((qn + 2 * T / R) ** 2)) / norm_ex
    e_t = np.sqrt(integ(ufl.dot(qt, qt))) / norm_ex
    E = mem.energy()
    E_ex = 4 * np.pi * R0 ** 2 * laws.energy_density(law, s, s, Es, alpha)
    n_cells = allsum(comm, mem.mesh.topology.index_map(2).size_local)
    h = np.sqrt(4 * np.pi * R0 ** 2 * 4 / np.sqrt(3) / n_cells)   # equilateral-equivalent edge
    return {"level": level, "cells": n_cells, "h": h, "err_q": e_q, "err_qn": e_n,
            "err_qt": e_t, "energy": E, "energy_exact": E_ex,
            "err_energy": abs(E - E_ex) / abs(E_ex)}, mem, (q, qn, qt)


def observed_orders(h, e):
    h, e = np.asarray(h), np.asarray(e)
    return list(np.log(e[1:] / e[:-1]) / np.log(h[1:] / h[:-1]))


def virtual_work_check(mem, mapping, eps=1e-6):
    """Central difference of E along a smooth perturbation vs int tau:grad_s dx."""
    pert = lambda X: np.c_[np.sin(X[:, 1]), X[:, 0] * X[:, 2], np.cos(X[:, 0] + X[:, 2])]  # noqa: E731
    mem.deform(mapping)
    dfield = dolfinx.fem.Function(mem.V)
    dfield.interpolate(lambda x: pert(x.T).T)
    vw = mem.virtual_work(dfield)
    mem.deform(lambda X: mapping(X) + eps * pert(mapping(X)))
    Ep = mem.energy()
    mem.deform(lambda X: mapping(X) - eps * pert(mapping(X)))
    Em = mem.energy()
    mem.deform(mapping)
    fd = (Ep - Em) / (2 * eps)
    return {"virtual_work": vw, "energy_fd": fd, "rel_diff": abs(vw - fd) / max(abs(vw), 1e-300)}


def uniaxial(comm, law, Gs=1.0, C=1.0, degree=1, level=2, n_points=12, lmax=None):
    """FE uniaxial stretch of a flat sheet: solve T2 = 0 for lambda2, compare T1."""
    from scipy.optimize import brentq
    Es = laws.Es_from_Gs(law, Gs)
    nodes, cells, outward = sm.flat_sheet(2 ** level, 2 ** level + 1, degree=degree)
    mem = Membrane(comm, nodes, cells, outward, degree, law, Es, C)
    e1 = dolfinx.fem.Constant(mem.mesh, np.array([1.0, 0.0, 0.0]))
    e2 = dolfinx.fem.Constant(mem.mesh, np.array([0.0, 1.0, 0.0]))

    def tensions(l1, l2):
        mem.deform(lambda X: X * np.array([l1, l2, 1.0]))
        _, _, _, tau, _, _ = mem.stress()
        A = mem.area()
        T = [allsum(comm, dolfinx.fem.assemble_scalar(dolfinx.fem.form(
            ufl.dot(e, ufl.dot(tau, e)) * mem.dx))) / A for e in (e1, e2)]
        return T

    data = np.loadtxt(DATA / "uniaxial_stretch" / f"barthes_biesel2002_{law.replace('-', '_')}.csv",
                      delimiter=",")
    data = data[np.argsort(data[:, 0])]
    lam_data = np.sqrt(1 + 2 * data[:, 0])
    lmax = lmax or lam_data.max()
    lam = np.unique(np.r_[np.linspace(1.0, lmax, n_points)[1:], lam_data[lam_data > 1.0005]])
    rows = []
    for l1 in lam:
        l2 = brentq(lambda l2: tensions(l1, l2)[1], 0.2, 1.0, xtol=1e-14)
        T1 = tensions(l1, l2)[0]
        l2_ex, T1_ex = laws.uniaxial_closed_form(law, l1, Gs, C)
        rows.append((l1, (l1 ** 2 - 1) / 2, l2, l2_ex, T1 / Gs, T1_ex / Gs))
    rows = np.array(rows)
    err_T1 = np.max(np.abs(rows[:, 4] - rows[:, 5]) / np.maximum(np.abs(rows[:, 5]), 1e-12))
    err_l2 = np.max(np.abs(rows[:, 2] - rows[:, 3]))
    # data comparison at the digitised strains (exclude e ~ 0 where relative error is ill-posed)
    fe_at_data = np.interp(data[:, 0], rows[:, 1], rows[:, 4])
    big = data[:, 1] > 0.05 * data[:, 1].max()
    dev = np.abs(fe_at_data - data[:, 1])
    return {"law": law, "C": C, "table": rows,
            "max_rel_err_T1_vs_closed_form": float(err_T1),
            "max_abs_err_lambda2_vs_closed_form": float(err_l2),
            "data_max_abs_dev_over_Gs": float(dev.max()),
            "data_rms_rel_dev": float(np.sqrt(np.mean((dev[big] / data[big, 1]) ** 2))),
            "data_max_T1_over_Gs": float(data[:, 1].max())}


# ---------------------------------------------------------------------- main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", choices=["single", "convergence", "uniaxial", "write-map"])
    ap.add_argument("--shape", default="sphere", choices=["sphere", "ellipsoid", "rbc", "sheet"])
    ap.add_argument("--map", default="inflate:1.2", help="inflate:s | linear:F(9) | file:PATH")
    ap.add_argument("--law", default="neo-hookean", choices=laws.LAWS)
    ap.add_argument("--Es", type=float, default=1.0)
    ap.add_argument("--alpha", type=float, default=1.0, help="Skalak alpha (= C)")
    ap.add_argument("--R0", type=float, default=None)
    ap.add_argument("--level", type=int, default=3, help="icosahedron refinements")
    ap.add_argument("--levels", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--degree", type=int, default=1, choices=[1, 2])
    ap.add_argument("--stretch", type=float, default=1.2, help="inflation factor s")
    ap.add_argument("--out", default="build/reference/membrane")
    ap.add_argument("--small", action="store_true", help="tiny meshes (tests)")
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    out = Path(args.out)
    t0 = time.time()
    say = (lambda *a: print(*a, flush=True)) if comm.rank == 0 else (lambda *a: None)

    if args.mode == "write-map":
        # example displaced-point file: a smooth nonlinear map of the chosen shape
        mem = build(args, comm)
        X = mem.X0
        x = np.c_[X[:, 0] * (1 + 0.1 * X[:, 2]), X[:, 1] + 0.05 * X[:, 0] ** 2, 1.1 * X[:, 2]]
        rows = comm.gather(np.c_[X, x], root=0)
        if comm.rank == 0:
            out.parent.mkdir(parents=True, exist_ok=True)
            np.savetxt(out, np.unique(np.concatenate(rows), axis=0), header="X Y Z x y z")
            say(f"wrote {out}")
        return 0

    if args.mode == "single":
        mem = build(args, comm)
        mapping = parse_map(args.map)
        vw = virtual_work_check(mem, mapping)
        q, qn, qt = mem.load()
        T1, T2, Jf = mem.principal_tensions()
        res = {"shape": args.shape, "map": args.map, "law": args.law, "level": args.level,
               "degree": args.degree, "area": mem.area(), "energy": mem.energy(),
               "total_force": [allsum(comm, dolfinx.fem.assemble_scalar(dolfinx.fem.form(
                   q[i] * mem.dx))) for i in range(3)],
               "virtual_work_check": vw, "ranks": comm.size}
        mem.write(out / f"{args.shape}_{args.law}", [q, qn, qt, T1, T2, Jf])
        res["seconds"] = time.time() - t0
        say(json.dumps(res, indent=1))
        if comm.rank == 0:
            (out / f"{args.shape}_{args.law}.json").write_text(json.dumps(res, indent=1))
        return 0

    if args.mode == "convergence":
        levels = [1, 2] if args.small else args.levels
        rows, last = [], None
        for lev in levels:
            r, mem, fields = sphere_inflation_errors(comm, lev, args.degree, args.law, args.Es,
                                                     args.alpha, args.stretch)
            rows.append(r)
            last = (mem, fields)
            say(f"level {lev}: cells {r['cells']:6d} h {r['h']:.4f} err_q {r['err_q']:.3e} "
                f"err_qn {r['err_qn']:.3e} err_qt {r['err_qt']:.3e} err_E {r['err_energy']:.3e}")
        orders = observed_orders([r["h"] for r in rows], [r["err_q"] for r in rows])
        res = {"law": args.law, "degree": args.degree, "stretch": args.stretch, "rows": rows,
               "orders_q": orders,
               "orders_energy": observed_orders([r["h"] for r in rows],
                                                [r["err_energy"] for r in rows]),
               "ranks": comm.size}
        mem, (q, qn, qt) = last
        mem.write(out / f"sphere_inflation_{args.law}_P{args.degree}", [q, qn, qt])
        res["seconds"] = time.time() - t0
        say("orders (load, L2):", " ".join(f"{o:.2f}" for o in orders))
        if comm.rank == 0:
            out.mkdir(parents=True, exist_ok=True)
            (out / f"convergence_{args.law}_P{args.degree}.json").write_text(json.dumps(res, indent=1))
        return 0

    if args.mode == "uniaxial":
        res = {}
        for law in laws.LAWS:
            r = uniaxial(comm, law, Gs=1.0, C=args.alpha, degree=args.degree,
                         level=1 if args.small else 2, n_points=6 if args.small else 12)
            tab = r.pop("table")
            res[law] = r
            say(f"{law}: max rel err T1 {r['max_rel_err_T1_vs_closed_form']:.2e}, "
                f"lambda2 {r['max_abs_err_lambda2_vs_closed_form']:.2e}, data RMS rel dev "
                f"{r['data_rms_rel_dev']:.3f}")
            if comm.rank == 0:
                out.mkdir(parents=True, exist_ok=True)
                np.savetxt(out / f"uniaxial_{law}.csv", tab, delimiter=",",
                           header="lambda1,e,lambda2_fe,lambda2_exact,T1_fe/Gs,T1_exact/Gs")
        res["seconds"] = time.time() - t0
        res["ranks"] = comm.size
        if comm.rank == 0:
            (out / "uniaxial.json").write_text(json.dumps(res, indent=1))
        return 0


if __name__ == "__main__":
    sys.exit(main())
