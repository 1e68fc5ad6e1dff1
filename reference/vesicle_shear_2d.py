#!/usr/bin/python3
"""Capsule in simple shear, 2D full-Eulerian finite elements (seed section 3.1, z-invariant).

What "the z-invariant version of the 3D model" means
====================================================
Take the 3D model of MODEL.md and assume nothing depends on z and v_z = 0.  The capsule
is then an infinitely long circular *cylinder* of radius a; its membrane is the cylinder
surface.  In-plane (x, y) the membrane is a closed curve; along z it is never stretched.
With F = diag(F_2D, 1) and P_R = I - n_R n_R (n_R in-plane), the 3D surface tensor is

    Gs = F P_R F^T = [[Gs_2D, 0], [0, 1]],     Gs_2D = F_2D (I - n_R n_R) F_2D^T,

and only the 2x2 block Gs_2D has to be transported (Lzz = 0 keeps Gs_zz = 1).
Bs = P Gs P has eigenvalues lambda^2 (along the in-plane tangent t), 1 (along z) and 0,
with lambda^2 = tr(P_2D Gs_2D P_2D) = P_2D : Gs_2D.  So J = lambda, Is = IIs = lambda^2 - 1
and the 3D neo-Hookean law tau_s = Es/(3J)(Bs - P/J^2) gives the in-plane tension

    T(lambda) = t . tau_s . t = Es/(3 lambda) (lambda^2 - 1/lambda^2) = Es/3 (lambda - lambda^-3)

(the z-z tension Es/(3 lambda)(1 - 1/lambda^2) exerts no force on a straight generator).
In 2D the membrane is therefore an elastic string with tension T(lambda), tau_s = T t t
= T P_2D.

Equations (one fluid, fixed mesh; mu the same inside and outside)
=================================================================

    rho (du/dt + u.grad u) = div(-p I + 2 mu D(u)) + |grad phi| f,    div u = 0
    f = (P.grad).tau_s                         (surface divergence of the tension)
    D phi/Dt = 0,      D Gs/Dt = L Gs + Gs L^T    (L = grad u)

phi is a smoothed indicator (1 inside), n = grad phi/|grad phi|, P = I - n n.
The membrane force enters the weak form by virtual work (as in membrane_stress.py):

    int |grad phi| f . v dx  :=  - int |grad phi| T(lambda) P : grad v dx,

the regularised form of  int_Gamma (div_s tau_s).v ds = - int_Gamma tau_s : grad_s v ds
(valid for a closed curve); it needs no curvature (no second derivatives of phi).

Set-up and scales: radius a = 1 (d = 2), shear rate gamma = 1, mu = 1; then
Re = rho gamma d^2/(4 mu) gives rho, and Ca = mu gamma a/Es gives Es = 1/Ca.
Box [-Lx/2, Lx/2] x [-Ly/2, Ly/2] with Ly = 4d, Lx = 8d: walls y = +-Ly/2 move at
+-U = +-gamma Ly/2 (Dirichlet u = (gamma y, 0)); the ends x = +-Lx/2 carry the traction
of the undisturbed shear flow, sigma n = (0, +-mu gamma) (no periodicity: DOLFINx 0.5
has no periodic constraint without dolfinx_mpc, so the box is long instead).

Discretisation
==============
* mesh: uniform right triangles of size h_far, refined (Plaza) ``--refine`` times in the
  square |x|, |y| < 2a so that h = h_far / 2^refine around the capsule;
* flow: Taylor-Hood P2/P1; inertia explicit (rho u^n.grad u^n, rho tiny), viscous and
  pressure implicit, so the matrix is constant and factorised once (MUMPS LU);
* membrane force explicit (from phi^n, Gs^n): time step dt <= C_el mu h / Es
  (``--cfl-elastic``), the usual explicit-membrane restriction;
* phi and Gs: P2, Crank-Nicolson in time with the new velocity u^{n+1}, SUPG
  stabilisation with tau = ((2/dt)^2 + (4|u|/h)^2)^(-1/2); phi = 0 on the boundary;
* initial phi = 1/(1 + exp((r - a)/eps)), eps = ``--eps`` x h (smoothing width, so
  |grad phi| = phi (1 - phi)/eps integrates to 1 across the interface);
  Gs(0) = I - e_r e_r (so lambda = 1 on the membrane);
* n = grad phi / sqrt(|grad phi|^2 + delta^2), delta = 1e-3/eps, avoids 0/0 far away.

Outputs: D(t) = (L - B)/(L + B) and the inclination theta/pi from the second moments of
phi, M = int phi (x - xc)(x - xc)^T dx / int phi dx (for an ellipse L = 2 sqrt(m1),
B = 2 sqrt(m2)); the capsule area int phi dx; CSV and XDMF (P1 interpolants), both one
file with every field (ParaView) and one file per field, ``capsule_<tag>_<field>.xdmf``
(meshio's TimeSeriesReader reads only one temporal collection per file).
``--probe-grid NX NY``: the FE solution itself (P2 velocity and phi, P1 pressure) evaluated
at the cell centres of a uniform NX x NY grid over the box (DOLFINx point evaluation, no
P1 interpolation), written with meshio as ``capsule_<tag>_probe.xdmf`` (quadrilateral cells,
cell data): the common points of the cross-code comparison with the Cartesian solver.

Usage
=====
    /usr/bin/python3 reference/vesicle_shear_2d.py --Ca 0.05 --refine 2 --t-end 1
    mpirun --oversubscribe -np 2 /usr/bin/python3 reference/vesicle_shear_2d.py --small
"""
from __future__ import annotations

import argparse
import json
import logging
import os
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

logging.getLogger().setLevel(logging.WARNING)
LAMBDA2_MIN = 0.1


# ---------------------------------------------------------------------- small helpers
class LinearSolver:
    """A linear problem whose forms are compiled once and re-assembled on demand."""

    def __init__(self, a, L, bcs, options, prefix):
        self.a, self.L, self.bcs = dolfinx.fem.form(a), dolfinx.fem.form(L), bcs
        self.A = dolfinx.fem.petsc.create_matrix(self.a)
        self.b = dolfinx.fem.petsc.create_vector(self.L)
        self.ksp = PETSc.KSP().create(self.A.getComm())
        self.ksp.setOptionsPrefix(prefix)
        opts = PETSc.Options()
        for k, v in options.items():
            opts[prefix + k] = v
        self.ksp.setFromOptions()
        self.ksp.setOperators(self.A)

    def assemble_matrix(self):
        self.A.zeroEntries()
        dolfinx.fem.petsc.assemble_matrix(self.A, self.a, bcs=self.bcs)
        self.A.assemble()

    def solve(self, x: dolfinx.fem.Function):
        with self.b.localForm() as b:
            b.set(0.0)
        dolfinx.fem.petsc.assemble_vector(self.b, self.L)
        dolfinx.fem.petsc.apply_lifting(self.b, [self.a], bcs=[self.bcs])
        self.b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        dolfinx.fem.petsc.set_bc(self.b, self.bcs)
        self.ksp.solve(self.b, x.vector)
        if self.ksp.getConvergedReason() < 0:
            raise RuntimeError(f"{self.ksp.getOptionsPrefix()} solve failed "
                               f"({self.ksp.getConvergedReason()})")
        x.x.scatter_forward()


def build_mesh(comm, Lx, Ly, h_far, refine, core=2.0):
    nx, ny = int(round(Lx / h_far)), int(round(Ly / h_far))
    mesh = dolfinx.mesh.create_rectangle(
        comm, [np.array([-Lx / 2, -Ly / 2]), np.array([Lx / 2, Ly / 2])], [nx, ny],
        dolfinx.mesh.CellType.triangle, diagonal=dolfinx.mesh.DiagonalType.crossed
        if False else dolfinx.mesh.DiagonalType.right)
    for _ in range(refine):
        cells = dolfinx.mesh.locate_entities(
            mesh, 2, lambda x: (np.abs(x[0]) <= core + 1e-10) & (np.abs(x[1]) <= core + 1e-10))
        mesh.topology.create_entities(1)
        edges = dolfinx.mesh.compute_incident_entities(mesh, cells, 2, 1)
        mesh = dolfinx.mesh.refine(mesh, edges, redistribute=True)
    return mesh


# ---------------------------------------------------------------------- the model
class CapsuleShear2D:
    def __init__(self, comm, Ca, Re=0.01, Lx=16.0, Ly=8.0, h_far=0.5, refine=2, eps=1.0,
                 cfl_elastic=0.5, dt_max=0.02, a=1.0):
        self.comm, self.Ca, self.a = comm, Ca, a
        gamma, mu, d = 1.0, 1.0, 2 * a
        self.gamma, self.mu = gamma, mu
        self.rho = Re * 4 * mu / (gamma * d ** 2)
        self.Es = mu * gamma * a / Ca
        self.h = h_far / 2 ** refine                         # mesh size at the capsule
        self.eps = eps * self.h
        self.dt = min(dt_max, cfl_elastic * mu * self.h / self.Es)
        self.mesh = mesh = build_mesh(comm, Lx, Ly, h_far, refine)
        self.Lx, self.Ly = Lx, Ly
        cell = mesh.ufl_cell()
        x = ufl.SpatialCoordinate(mesh)

        # ---- spaces and fields
        self.W = dolfinx.fem.FunctionSpace(mesh, ufl.MixedElement(
            [ufl.VectorElement("Lagrange", cell, 2), ufl.FiniteElement("Lagrange", cell, 1)]))
        self.V, _ = self.W.sub(0).collapse()
        self.Q = dolfinx.fem.FunctionSpace(mesh, ("Lagrange", 2))
        self.T = dolfinx.fem.TensorFunctionSpace(mesh, ("Lagrange", 2))
        self.w = dolfinx.fem.Function(self.W)
        self.u = dolfinx.fem.Function(self.V, name="velocity")     # u^{n+1} (after solve)
        self.u_old = dolfinx.fem.Function(self.V)
        self.phi = dolfinx.fem.Function(self.Q, name="phi")
        self.phi_old = dolfinx.fem.Function(self.Q)
        self.G = dolfinx.fem.Function(self.T, name="Gs")
        self.G_old = dolfinx.fem.Function(self.T)

        shear = lambda X: np.vstack([gamma * X[1], 0 * X[0]])  # noqa: E731
        self.u.interpolate(shear)
        self.u_old.interpolate(shear)
        e = self.eps
        self.phi.interpolate(lambda X: 1 / (1 + np.exp((np.hypot(X[0], X[1]) - a) / e)))

        def G0(X):
            r2 = X[0] ** 2 + X[1] ** 2 + 1e-12
            return np.vstack([1 - X[0] ** 2 / r2, -X[0] * X[1] / r2,
                              -X[0] * X[1] / r2, 1 - X[1] ** 2 / r2])
        self.G.interpolate(G0)
        self.dt_c = dolfinx.fem.Constant(mesh, PETSc.ScalarType(self.dt))

        # ---- membrane kinematics and tension from (phi^n, Gs^n)
        dirac, P, lam, self.tension = self.membrane(self.phi_old, self.G_old)

        # ---- flow: rho (u - u^n)/dt - div(2 mu D(u)) + grad p = -rho u^n.grad u^n + membrane
        (uu, pp), (v, q) = ufl.TrialFunctions(self.W), ufl.TestFunctions(self.W)
        dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 6})
        self.dx = dx
        D = lambda z: ufl.sym(ufl.grad(z))  # noqa: E731
        a_f = (self.rho / self.dt_c * ufl.inner(uu, v) + 2 * mu * ufl.inner(D(uu), D(v))
               - pp * ufl.div(v) - q * ufl.div(uu)) * dx
        membrane = -dirac * self.tension * ufl.inner(P, ufl.grad(v))
        L_f = (self.rho / self.dt_c * ufl.inner(self.u_old, v)
               - self.rho * ufl.inner(ufl.grad(self.u_old) * self.u_old, v) + membrane) * dx
        # far-field traction on x = +-Lx/2: sigma n = (0, +-mu gamma)
        nf = ufl.FacetNormal(mesh)
        sigma_inf = ufl.as_matrix([[0.0, mu * gamma], [mu * gamma, 0.0]])
        L_f += ufl.inner(sigma_inf * nf, v) * ufl.ds
        fdim = 1
        walls = dolfinx.mesh.locate_entities_boundary(
            mesh, fdim, lambda X: np.isclose(np.abs(X[1]), Ly / 2))
        u_wall = dolfinx.fem.Function(self.V)
        u_wall.interpolate(shear)
        W0 = self.W.sub(0)
        bc_u = dolfinx.fem.dirichletbc(
            u_wall, dolfinx.fem.locate_dofs_topological((W0, self.V), fdim, walls), W0)
        self.flow = LinearSolver(a_f, L_f, [bc_u], {
            "ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"},
            "flow_")
        self.flow.assemble_matrix()                          # constant: factorised once

        # ---- transport: Crank-Nicolson + SUPG with velocity u^{n+1}
        uvel = self.u
        hK = ufl.CellDiameter(mesh)
        unorm = ufl.sqrt(ufl.dot(uvel, uvel) + 1e-12)
        tau = 1 / ufl.sqrt((2 / self.dt_c) ** 2 + (4 * unorm / hK) ** 2)
        th = 0.5
        f_, g_ = ufl.TrialFunction(self.Q), ufl.TestFunction(self.Q)
        fm = th * f_ + (1 - th) * self.phi_old
        res = (f_ - self.phi_old) / self.dt_c + ufl.dot(uvel, ufl.grad(fm))
        F_phi = (res * g_ + tau * ufl.dot(uvel, ufl.grad(g_)) * res) * dx
        bdry = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda X: np.full(X.shape[1], True))
        bc_phi = dolfinx.fem.dirichletbc(PETSc.ScalarType(0.0),
                                         dolfinx.fem.locate_dofs_topological(self.Q, fdim, bdry),
                                         self.Q)
        iterative = {"ksp_type": "gmres", "pc_type": "bjacobi", "sub_pc_type": "ilu",
                     "ksp_rtol": 1e-10, "ksp_atol": 1e-14, "ksp_max_it": 500}
        self.adv_phi = LinearSolver(ufl.lhs(F_phi), ufl.rhs(F_phi), [bc_phi], iterative, "phi_")

        Gt, H = ufl.TrialFunction(self.T), ufl.TestFunction(self.T)
        Lg = ufl.grad(uvel)                                   # L_ij = du_i/dx_j
        Gm = th * Gt + (1 - th) * self.G_old
        resG = (Gt - self.G_old) / self.dt_c + ufl.dot(ufl.grad(Gm), uvel) - (Lg * Gm + Gm * Lg.T)
        F_G = ufl.inner(resG, H + tau * ufl.dot(ufl.grad(H), uvel)) * dx
        self.adv_G = LinearSolver(ufl.lhs(F_G), ufl.rhs(F_G), [], iterative, "gs_")

        # ---- diagnostics forms
        self.x = x
        self.f_area = dolfinx.fem.form(self.phi * dx)
        self.f_mom1 = [dolfinx.fem.form(self.phi * x[i] * dx) for i in range(2)]
        self.xc = dolfinx.fem.Constant(mesh, np.zeros(2))
        r = x - self.xc
        self.f_mom2 = [dolfinx.fem.form(self.phi * r[i] * r[j] * dx) for i, j in ((0, 0), (0, 1), (1, 1))]
        # perimeter and mean stretch, weighted with |grad phi| (current phi, Gs)
        dirac1, _, lam1, _ = self.membrane(self.phi, self.G)
        self.f_len = dolfinx.fem.form(dirac1 * dx)
        self.f_lam = dolfinx.fem.form(dirac1 * lam1 * dx)
        self.lam_nodes = dolfinx.fem.Function(self.Q)
        self.lam_expr = dolfinx.fem.Expression(lam1, self.Q.element.interpolation_points())
        self.t = 0.0

    def membrane(self, phi, G):
        """|grad phi|, P, lambda and T(lambda) = Es/3 (lambda - lambda^-3) from phi and Gs."""
        gphi = ufl.grad(phi)
        delta = 1e-3 / self.eps
        n = gphi / ufl.sqrt(ufl.dot(gphi, gphi) + delta ** 2)
        P = ufl.Identity(2) - ufl.outer(n, n)
        dirac = ufl.sqrt(ufl.dot(gphi, gphi))
        # lambda^2 = P : Gs, floored at LAMBDA2_MIN: far from the membrane phi ~ 0 and its
        # gradient is round-off, n is then arbitrary and P : Gs may vanish, which would make
        # lambda^-3 (and the force, even times a tiny |grad phi|) blow up.  On the membrane
        # lambda^2 stays far above the floor (checked: min over the band is reported).
        lam = ufl.sqrt(ufl.max_value(ufl.inner(P, G), LAMBDA2_MIN))
        return dirac, P, lam, self.Es / 3 * (lam - lam ** -3)

    def integrate(self, f):
        return self.comm.allreduce(dolfinx.fem.assemble_scalar(f), op=MPI.SUM)

    def shape(self):
        """Area, centroid, D and theta/pi from the second moments of phi."""
        A = self.integrate(self.f_area)
        xc = np.array([self.integrate(f) for f in self.f_mom1]) / A
        self.xc.value[:] = xc
        mxx, mxy, myy = (self.integrate(f) / A for f in self.f_mom2)
        ev, evec = np.linalg.eigh(np.array([[mxx, mxy], [mxy, myy]]))
        Lh, Bh = np.sqrt(ev[1]), np.sqrt(ev[0])
        v = evec[:, 1] * np.sign(evec[0, 1] if evec[0, 1] != 0 else 1)
        theta = np.arctan2(v[1], v[0])
        return {"area": A, "xc": xc[0], "yc": xc[1], "D": (Lh - Bh) / (Lh + Bh),
                "theta_over_pi": theta / np.pi}

    # ------------------------------------------------------------------ time step
    def step(self):
        # stage 0: old state
        self.phi_old.x.array[:] = self.phi.x.array
        self.G_old.x.array[:] = self.G.x.array
        self.u_old.x.array[:] = self.u.x.array
        # stage 1: momentum with the explicit membrane force of (phi^n, Gs^n)
        self.flow.solve(self.w)
        self.u.interpolate(self.w.sub(0))
        # stage 2: transport phi and Gs with u^{n+1}
        self.adv_phi.assemble_matrix()
        self.adv_phi.solve(self.phi)
        self.adv_G.assemble_matrix()
        self.adv_G.solve(self.G)
        self.t += self.dt

    def membrane_state(self):
        """Perimeter int |grad phi|, mean stretch, and the stretch range over the band
        0.05 < phi < 0.95 (P2 nodes)."""
        L = self.integrate(self.f_len)
        self.lam_nodes.interpolate(self.lam_expr)
        band = (self.phi.x.array > 0.05) & (self.phi.x.array < 0.95)
        lam = self.lam_nodes.x.array[band]
        lmin = self.comm.allreduce(lam.min() if lam.size else np.inf, op=MPI.MIN)
        lmax = self.comm.allreduce(lam.max() if lam.size else -np.inf, op=MPI.MAX)
        return {"perimeter": L, "mean_stretch": self.integrate(self.f_lam) / L,
                "lambda_min_band": lmin, "lambda_max_band": lmax}

    def probe(self, points):
        """u (2), p, phi of the FE solution at points (N x 2); complete on rank 0 only
        (every rank evaluates the points inside its cells, rank 0 takes the first hit)."""
        import dolfinx.geometry as geo
        if not hasattr(self, "_probe_cells") or self._probe_points is not points:
            p3 = np.c_[points, np.zeros(len(points))]
            tree = geo.BoundingBoxTree(self.mesh, 2)
            hits = geo.compute_colliding_cells(self.mesh, geo.compute_collisions(tree, p3), p3)
            cells = np.array([hits.links(i)[0] if len(hits.links(i)) else -1
                              for i in range(len(p3))], dtype=np.int32)
            self._probe_points, self._probe_cells, self._probe_p3 = points, cells, p3
            self._p_space = self.W.sub(1).collapse()[0]
        cells, p3 = self._probe_cells, self._probe_p3
        mine = cells >= 0
        p = dolfinx.fem.Function(self._p_space)
        p.interpolate(self.w.sub(1))                     # P1 -> P1: the same values
        vals = np.full((len(p3), 4), np.nan)
        if mine.any():
            vals[mine, :2] = self.u.eval(p3[mine], cells[mine])
            vals[mine, 2] = p.eval(p3[mine], cells[mine])[:, 0]
            vals[mine, 3] = self.phi.eval(p3[mine], cells[mine])[:, 0]
        parts = self.comm.gather(vals, root=0)
        if self.comm.rank != 0:
            return None
        out = parts[0]
        for v in parts[1:]:
            fill = np.isnan(out[:, 0]) & ~np.isnan(v[:, 0])
            out[fill] = v[fill]
        return out

    def output_fields(self):
        """P1 interpolants for XDMF (DOLFINx 0.5 writes Lagrange fields of mesh degree)."""
        V1 = dolfinx.fem.VectorFunctionSpace(self.mesh, ("Lagrange", 1))
        Q1 = dolfinx.fem.FunctionSpace(self.mesh, ("Lagrange", 1))
        T1 = dolfinx.fem.TensorFunctionSpace(self.mesh, ("Lagrange", 1))
        out = []
        for f, S in ((self.u, V1), (self.phi, Q1), (self.G, T1)):
            g = dolfinx.fem.Function(S, name=f.name)
            g.interpolate(f)
            out.append(g)
        p = dolfinx.fem.Function(Q1, name="pressure")
        p.interpolate(self.w.sub(1))
        out.append(p)
        return out


# ---------------------------------------------------------------------- driver
def run(args, comm):
    t_wall = time.time()
    model = CapsuleShear2D(comm, args.Ca, args.Re, args.Lx, args.Ly, args.h_far, args.refine,
                           args.eps, args.cfl_elastic, args.dt_max)
    say = (lambda *a: print(*a, flush=True)) if comm.rank == 0 else (lambda *a: None)
    n_cells = comm.allreduce(model.mesh.topology.index_map(2).size_local, op=MPI.SUM)
    say(f"Ca {args.Ca} Re {args.Re}: h {model.h:.4f} (d/{2 / model.h:.0f}) eps {model.eps:.4f} "
        f"dt {model.dt:.3e} cells {n_cells} rho {model.rho} Es {model.Es}")
    out = Path(args.out)
    tag = f"ca{args.Ca:g}_r{args.refine}"
    n_steps = int(round(args.t_end / model.dt))
    n_steps = max(n_steps, 1)
    model.dt = args.t_end / n_steps
    model.dt_c.value = model.dt
    model.flow.assemble_matrix()
    out_times = sorted(set(args.write_times))
    rows = []
    xdmf = None
    per_field = {}
    probe = None
    if out_times and args.probe_grid:
        import meshio
        nx, ny = args.probe_grid
        xs = np.linspace(-args.Lx / 2, args.Lx / 2, nx + 1)
        ys = np.linspace(-args.Ly / 2, args.Ly / 2, ny + 1)
        X, Y = np.meshgrid(xs, ys)                           # nodes, x fastest
        nodes = np.c_[X.ravel(), Y.ravel()]
        ii, jj = np.meshgrid(np.arange(nx), np.arange(ny))   # cells, x fastest
        n0 = (jj * (nx + 1) + ii).ravel()
        quads = np.c_[n0, n0 + 1, n0 + nx + 2, n0 + nx + 1]
        centres = nodes[quads].mean(axis=1)
        if comm.rank == 0:
            out.mkdir(parents=True, exist_ok=True)
            probe = meshio.xdmf.TimeSeriesWriter(
                str((out / f"capsule_{tag}_probe.xdmf").resolve()))
            cwd = os.getcwd()
            os.chdir(out)            # meshio 5.0 puts the .h5 in the working directory
            try:
                probe.__enter__()
            finally:
                os.chdir(cwd)
            probe.write_points_cells(nodes, [("quad", quads)])
    if out_times:
        out.mkdir(parents=True, exist_ok=True)
        xdmf = dolfinx.io.XDMFFile(comm, str(out / f"capsule_{tag}.xdmf"), "w")
        xdmf.write_mesh(model.mesh)
        # DOLFINx puts each function in its own temporal collection, and meshio's
        # TimeSeriesReader reads only one collection per file; so each field is also
        # written alone (same P1 data), one meshio-readable file per field.
        for name in ("velocity", "phi", "Gs", "pressure"):
            per_field[name] = dolfinx.io.XDMFFile(
                comm, str(out / f"capsule_{tag}_{name}.xdmf"), "w")
            per_field[name].write_mesh(model.mesh)

    def record():
        s = model.shape()
        s.update(model.membrane_state())
        s["t"] = model.t
        rows.append(s)
        return s

    def maybe_write(step):
        if xdmf is None:
            return
        for tw in out_times:
            if abs(model.t - tw) < 0.5 * model.dt:
                for f in model.output_fields():
                    xdmf.write_function(f, model.t)
                    per_field[f.name].write_function(f, model.t)
                if args.probe_grid:
                    vals = model.probe(centres)
                    if probe is not None:
                        probe.write_data(model.t, cell_data={
                            "velocity": [vals[:, :2]], "pressure": [vals[:, 2]],
                            "phi": [vals[:, 3]]})

    record()
    maybe_write(0)
    every = max(1, n_steps // 20)
    diverged = None
    for k in range(1, n_steps + 1):
        model.step()
        s = record()
        maybe_write(k)
        if not np.isfinite(s["D"]) or s["mean_stretch"] > 10:
            # a result, not a crash: the summary says where; the caller sees exit code 3
            diverged = model.t
            say(f"DIVERGED at t = {model.t:.4g} (step {k}): mean stretch "
                f"{s['mean_stretch']:.3g} > 10 or D not finite; band lambda in "
                f"[{s['lambda_min_band']:.3g}, {s['lambda_max_band']:.3g}]")
            rows.pop()  # the diverged state is not a solution
            break
        if k % every == 0 or k == n_steps:
            say(f"t {model.t:6.3f}  D {s['D']:.4f}  theta/pi {s['theta_over_pi']:.4f}  "
                f"area {s['area']:.5f}  lambda in [{s['lambda_min_band']:.3f}, "
                f"{s['lambda_max_band']:.3f}]")
    if xdmf is not None:
        xdmf.close()
        for f in per_field.values():
            f.close()
    if probe is not None:
        probe.__exit__(None, None, None)
    wall = time.time() - t_wall
    summary = {"Ca": args.Ca, "Re": args.Re, "refine": args.refine, "h": model.h,
               "h_over_d": model.h / 2, "eps": model.eps, "dt": model.dt, "steps": len(rows) - 1,
               "cells": n_cells, "ranks": comm.size, "wall_seconds": wall,
               "D_final": rows[-1]["D"], "theta_over_pi_final": rows[-1]["theta_over_pi"],
               "area_drift": rows[-1]["area"] / rows[0]["area"] - 1, "t_end": rows[-1]["t"],
               "lambda_min_band": min(r["lambda_min_band"] for r in rows),
               "lambda_max_band": max(r["lambda_max_band"] for r in rows),
               "Lx": args.Lx, "Ly": args.Ly,
               "status": "completed" if diverged is None else "diverged",
               "diverged_at": diverged}
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
        keys = ["t", "D", "theta_over_pi", "area", "xc", "yc", "perimeter", "mean_stretch",
                "lambda_min_band", "lambda_max_band"]
        np.savetxt(out / f"capsule_{tag}.csv", np.array([[r[k] for k in keys] for r in rows]),
                   delimiter=",", header=",".join(keys), comments="")
        (out / f"capsule_{tag}.json").write_text(json.dumps(summary, indent=1))
    say(json.dumps(summary))
    return summary


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--Ca", type=float, default=0.05)
    ap.add_argument("--Re", type=float, default=0.01)
    ap.add_argument("--Lx", type=float, default=16.0, help="box length (a = 1)")
    ap.add_argument("--Ly", type=float, default=8.0, help="wall distance (a = 1)")
    ap.add_argument("--h-far", dest="h_far", type=float, default=0.5)
    ap.add_argument("--refine", type=int, default=2, help="refinements near the capsule")
    ap.add_argument("--eps", type=float, default=1.0, help="smoothing width / h")
    ap.add_argument("--cfl-elastic", dest="cfl_elastic", type=float, default=0.5)
    ap.add_argument("--dt-max", dest="dt_max", type=float, default=0.02)
    ap.add_argument("--t-end", dest="t_end", type=float, default=1.0)
    ap.add_argument("--write-times", dest="write_times", type=float, nargs="*", default=[])
    ap.add_argument("--probe-grid", dest="probe_grid", type=int, nargs=2, default=None,
                    metavar=("NX", "NY"), help="also write the solution at the cell centres "
                    "of an NX x NY grid over the box (meshio XDMF) at --write-times")
    ap.add_argument("--small", action="store_true",
                    help="tiny fast case (tests): box 8 x 6, h = d/8, t_end 0.3")
    ap.add_argument("--out", default="build/reference/vesicle")
    args = ap.parse_args(argv)
    if args.small:
        args.Lx, args.Ly, args.h_far, args.refine, args.t_end = 8.0, 6.0, 0.5, 1, 0.3
    summary = run(args, MPI.COMM_WORLD)
    return 3 if summary["status"] == "diverged" else 0


if __name__ == "__main__":
    sys.exit(main())
