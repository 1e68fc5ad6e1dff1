#!/usr/bin/python3
"""Capsule in simple shear, 3D full-Eulerian finite elements (seed section 3.1).

The 3D counterpart of ``vesicle_shear_2d.py`` (same structure, same continuum model of
MODEL.md, no z-invariance): a spherical capsule of radius a with a neo-Hookean membrane
and equal viscosity inside and outside in a wall-bounded shear flow.

Equations (one fluid on a fixed tetrahedral mesh)
=================================================

    rho (du/dt + u.grad u) = div(-p I + 2 mu D(u)) + |grad phi| f,    div u = 0
    D phi/Dt = 0,      D Gs/Dt = L Gs + Gs L^T           (L = grad u, L_ij = du_i/dx_j)

phi is a smoothed indicator (1 inside), n = grad phi/|grad phi|, P = I - n n and, as in
MODEL.md,

    Bs = P Gs P,   Is = tr Bs - 2,   J^2 = IIs + 1 = (tr^2 Bs - tr Bs^2)/2,
    tau_s = Es/(3 J) (Bs - P/J^2)                         (neo-Hookean, Es = 3 Gs)

The membrane force f = (P.grad).tau_s enters by virtual work, exactly as in 2D:

    int |grad phi| f . v dx  :=  - int |grad phi| tau_s : grad v dx

(the regularised int_Gamma (div_s tau_s).v ds = - int_Gamma tau_s : grad_s v ds for a
closed surface; tau_s is tangential so tau_s : grad v = tau_s : grad_s v).  No curvature,
no second derivatives of phi.

Set-up (a = 1, d = 2, shear rate gamma = 1, mu = 1; Re = rho gamma d^2/(4 mu) = 0.01 gives
rho = 0.01; Ca = mu gamma a/Es gives Es = 1/Ca).  Box [-Lx/2, Lx/2] x [-Ly/2, Ly/2] x
[-Lz/2, Lz/2] (default 8 x 6 x 6, i.e. 4d x 3d x 3d): walls y = +-Ly/2 move with the
undisturbed shear (Dirichlet u = (gamma y, 0, 0)); the ends x = +-Lx/2 carry the traction
of the undisturbed shear sigma n = (0, +-mu gamma, 0); the faces z = +-Lz/2 are
traction-free, which the undisturbed shear also satisfies (sigma e_z = 0 with p = 0).
No periodicity (DOLFINx 0.5 has no periodic constraint without dolfinx_mpc).

Discretisation (as in 2D, and why)
==================================
* mesh: uniform tetrahedra (6 per cube of side h_far), refined (Plaza) ``--refine`` times
  in the cube |x|, |y|, |z| < ``--core`` so that h = h_far/2^refine around the capsule.
  Default h_far = 0.5, refine 1: h = 0.25 = d/8, about 30k tetrahedra;
* flow: Taylor-Hood P2/P1; viscous and pressure terms implicit, inertia explicit
  (rho u^n.grad u^n with rho = 0.01), so the matrix is constant.  Two solvers:
  ``--flow-solver lu``: MUMPS LU, factorised once, one pair of triangular solves per step
  (the cheapest option while the factor fits in memory: ~1-2 GB at the default mesh);
  ``--flow-solver minres``: MINRES with the block-diagonal preconditioner
  diag(A_uu, M_p/mu) (fieldsplit, additive): BoomerAMG (hypre) on the velocity block and
  Jacobi on the pressure mass matrix, the standard mesh-independent Stokes preconditioner
  (the rho/dt mass term is small so M_p/mu is a good Schur-complement approximation;
  BoomerAMG with the usual 3D settings, strong threshold 0.7, HMIS, ext+i).  Measured on
  the --small mesh (15k dofs): 97 MINRES iterations, 1.45 s CPU per solve, against LU's
  7.5 s factorisation then 0.07 s per solve (the machine's BLAS is the reference netlib
  one, which makes the factorisation slow: ~1250 s wall, ~10 CPU minutes, at the default
  mesh; then ~4 s per step);
* membrane force explicit (phi^n, Gs^n); dt = min(dt_max, C mu h/Es), C = 0.5;
* phi (P2 scalar) and Gs (six P2 scalar components of the symmetric tensor):
  Crank-Nicolson advection with u^{n+1}, SUPG with tau = ((2/dt)^2 + (4|u|/h)^2)^(-1/2),
  GMRES + block-Jacobi/ILU; phi = 0 on the boundary.  Unlike the 2D script (one coupled
  tensor system), the stretching source L Gs + Gs L^T is taken by Heun's predictor-
  corrector, so all six components share one scalar matrix and one ILU per step: the
  coupled 3D tensor system (9 components) was ~10x more expensive to assemble and solve.
  Still second order in time; |L| dt <~ 0.02, far inside the explicit stability limit;
* phi(0) = 1/(1 + exp((r - a)/eps)), eps = ``--eps`` x h;  Gs(0) = I - e_r e_r;
* n = grad phi/sqrt(|grad phi|^2 + delta^2), delta = 1e-3/eps; J^2 floored at 0.1 (far
  from the capsule n is arbitrary and J -> 0 would make 1/J^3 explode; the range of J
  over the band 0.05 < phi < 0.95 is reported to show the floor is inactive there).

D in the shear plane: the 3D second moments M = int w (x - xc)(x - xc)^T dx / int w with
the weight w = max(2 phi - 1, 0) (a function of phi, so it moves with the capsule; it
vanishes where phi < 1/2 and so ignores the smoothed tail, which a non-cubic box truncates
anisotropically: with plain phi, D(0) = 0.08 in the small 6 x 4 x 4 box at h = d/4);
z is a symmetry direction, so the ellipse of the shear-plane section has semi-axes
proportional to the square roots of the eigenvalues of the xy block of M (an ellipsoid
with semi-axes a_i has M = diag(a_i^2)/5 in its frame), D = (L - B)/(L + B), and the
inclination from the leading eigenvector.  Because moments of an affinely transported
function (of any function of phi) transform as F M F^T, the smoothing does not bias D while the capsule
just follows the shear (early times: D(t) = t/sqrt(4 + t^2) ~ t/2).

Usage
=====
    /usr/bin/python3 reference/vesicle_shear_3d.py --Ca 0.05 --t-end 0.5
    /usr/bin/python3 reference/vesicle_shear_3d.py --small --Ca 0.2      # tests, seconds
    mpirun --oversubscribe -np 2 /usr/bin/python3 reference/vesicle_shear_3d.py --small
"""
from __future__ import annotations

import argparse
import json
import logging
import os
import resource
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")   # 2-core machine: no BLAS threads in MUMPS
import numpy as np  # noqa: E402
import ufl  # noqa: E402
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc
import dolfinx.io

sys.path.insert(0, str(Path(__file__).resolve().parent))
from vesicle_shear_2d import LinearSolver  # noqa: E402  (shared helper within reference/)

logging.getLogger().setLevel(logging.WARNING)
J2_MIN = 0.1


def build_mesh(comm, Lx, Ly, Lz, h_far, refine, core):
    n = [max(1, int(round(L / h_far))) for L in (Lx, Ly, Lz)]
    mesh = dolfinx.mesh.create_box(
        comm, [np.array([-Lx / 2, -Ly / 2, -Lz / 2]), np.array([Lx / 2, Ly / 2, Lz / 2])], n,
        dolfinx.mesh.CellType.tetrahedron)
    for _ in range(refine):
        cells = dolfinx.mesh.locate_entities(
            mesh, 3, lambda x: np.all(np.abs(x) <= core + 1e-10, axis=0))
        mesh.topology.create_entities(1)
        edges = dolfinx.mesh.compute_incident_entities(mesh, cells, 3, 1)
        mesh = dolfinx.mesh.refine(mesh, edges, redistribute=True)
    return mesh


class CapsuleShear3D:
    def __init__(self, comm, Ca, Re=0.01, Lx=8.0, Ly=6.0, Lz=6.0, h_far=0.5, refine=1,
                 core=1.75, eps=1.0, cfl_elastic=0.5, dt_max=0.02, flow_solver="lu", a=1.0):
        self.comm, self.Ca, self.a = comm, Ca, a
        gamma, mu, d = 1.0, 1.0, 2 * a
        self.gamma, self.mu = gamma, mu
        self.rho = Re * 4 * mu / (gamma * d ** 2)
        self.Es = mu * gamma * a / Ca
        self.h = h_far / 2 ** refine
        self.eps = eps * self.h
        self.dt = min(dt_max, cfl_elastic * mu * self.h / self.Es)
        self.mesh = mesh = build_mesh(comm, Lx, Ly, Lz, h_far, refine, core)
        cell = mesh.ufl_cell()
        x = ufl.SpatialCoordinate(mesh)

        self.W = dolfinx.fem.FunctionSpace(mesh, ufl.MixedElement(
            [ufl.VectorElement("Lagrange", cell, 2), ufl.FiniteElement("Lagrange", cell, 1)]))
        self.V, _ = self.W.sub(0).collapse()
        self.Q = dolfinx.fem.FunctionSpace(mesh, ("Lagrange", 2))
        self.w = dolfinx.fem.Function(self.W)
        self.u = dolfinx.fem.Function(self.V, name="velocity")
        self.u_old = dolfinx.fem.Function(self.V)
        self.phi = dolfinx.fem.Function(self.Q, name="phi")
        self.phi_old = dolfinx.fem.Function(self.Q)
        # Gs is symmetric: six P2 scalar components g_ij (i <= j), and a predictor copy
        self.IJ = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]
        self.g = [dolfinx.fem.Function(self.Q, name=f"Gs{i}{j}") for i, j in self.IJ]
        self.g_old = [dolfinx.fem.Function(self.Q) for _ in self.IJ]
        self.g_pred = [dolfinx.fem.Function(self.Q) for _ in self.IJ]
        self.G, self.G_old, self.G_pred = (self.sym3(c) for c in (self.g, self.g_old, self.g_pred))

        shear = lambda X: np.vstack([gamma * X[1], 0 * X[0], 0 * X[0]])  # noqa: E731
        self.u.interpolate(shear)
        self.u_old.interpolate(shear)
        e = self.eps
        self.phi.interpolate(lambda X: 1 / (1 + np.exp((np.linalg.norm(X, axis=0) - a) / e)))

        for (i, j), gij in zip(self.IJ, self.g):
            gij.interpolate(lambda X, i=i, j=j: (1.0 if i == j else 0.0)
                            - X[i] * X[j] / (np.sum(X ** 2, axis=0) + 1e-12))
        self.dt_c = dolfinx.fem.Constant(mesh, PETSc.ScalarType(self.dt))

        dirac, P, J, self.tau_s = self.membrane(self.phi_old, self.G_old)

        # ---- flow
        (uu, pp), (v, q) = ufl.TrialFunctions(self.W), ufl.TestFunctions(self.W)
        dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 4})
        self.dx = dx
        D = lambda z: ufl.sym(ufl.grad(z))  # noqa: E731
        a_f = (self.rho / self.dt_c * ufl.inner(uu, v) + 2 * mu * ufl.inner(D(uu), D(v))
               - pp * ufl.div(v) - q * ufl.div(uu)) * dx
        membrane = -dirac * ufl.inner(self.tau_s, ufl.grad(v))
        L_f = (self.rho / self.dt_c * ufl.inner(self.u_old, v)
               - self.rho * ufl.inner(ufl.grad(self.u_old) * self.u_old, v) + membrane) * dx
        nf = ufl.FacetNormal(mesh)
        sigma_inf = ufl.as_matrix([[0.0, mu * gamma, 0.0], [mu * gamma, 0.0, 0.0],
                                   [0.0, 0.0, 0.0]])
        L_f += ufl.inner(sigma_inf * nf, v) * ufl.ds
        fdim = 2
        walls = dolfinx.mesh.locate_entities_boundary(
            mesh, fdim, lambda X: np.isclose(np.abs(X[1]), Ly / 2))
        u_wall = dolfinx.fem.Function(self.V)
        u_wall.interpolate(shear)
        W0 = self.W.sub(0)
        bc_u = dolfinx.fem.dirichletbc(
            u_wall, dolfinx.fem.locate_dofs_topological((W0, self.V), fdim, walls), W0)
        if flow_solver == "lu":
            self.flow = LinearSolver(a_f, L_f, [bc_u], {
                "ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps",
                "mat_mumps_icntl_14": 200}, "flow_")
            self.flow.assemble_matrix()
        else:
            self.flow = LinearSolver(a_f, L_f, [bc_u], {
                "ksp_type": "minres", "ksp_rtol": 1e-9, "ksp_max_it": 2000,
                "pc_type": "fieldsplit", "pc_fieldsplit_type": "additive",
                "fieldsplit_u_ksp_type": "preonly", "fieldsplit_u_pc_type": "hypre",
                "fieldsplit_u_pc_hypre_type": "boomeramg",
                # 3D P2: the default strong threshold 0.25 gives dense coarse grids (~10x
                # slower here); the usual 3D settings
                "fieldsplit_u_pc_hypre_boomeramg_strong_threshold": 0.7,
                "fieldsplit_u_pc_hypre_boomeramg_coarsen_type": "HMIS",
                "fieldsplit_u_pc_hypre_boomeramg_interp_type": "ext+i",
                "fieldsplit_u_pc_hypre_boomeramg_agg_nl": 1,
                "fieldsplit_p_ksp_type": "preonly", "fieldsplit_p_pc_type": "jacobi"},
                "flow_")
            # preconditioner matrix: the velocity block and the pressure mass matrix / mu
            p_form = dolfinx.fem.form(
                (self.rho / self.dt_c * ufl.inner(uu, v) + 2 * mu * ufl.inner(D(uu), D(v))
                 + pp * q / mu) * dx)
            self.p_form, self.bc_u = p_form, bc_u
            self.Pmat = dolfinx.fem.petsc.assemble_matrix(p_form, bcs=[bc_u])
            self.Pmat.assemble()
            self.flow.ksp.setOperators(self.flow.A, self.Pmat)
            pc = self.flow.ksp.getPC()
            imap = self.W.dofmap.index_map
            n_own, off = imap.size_local, imap.local_range[0]
            iss = []
            for i in range(2):
                _, m = self.W.sub(i).collapse()
                m = np.asarray(m, dtype=np.int32)
                iss.append(PETSc.IS().createGeneral(np.sort(m[m < n_own]) + off, comm=comm))
            pc.setFieldSplitIS(("u", iss[0]), ("p", iss[1]))
            self.flow.ksp.setFromOptions()
            self.flow.assemble_matrix()
        self.flow_solver = flow_solver

        # ---- transport: Crank-Nicolson + SUPG with u^{n+1}
        uvel = self.u
        hK = ufl.CellDiameter(mesh)
        unorm = ufl.sqrt(ufl.dot(uvel, uvel) + 1e-12)
        tau = 1 / ufl.sqrt((2 / self.dt_c) ** 2 + (4 * unorm / hK) ** 2)
        th = 0.5
        f_, g_ = ufl.TrialFunction(self.Q), ufl.TestFunction(self.Q)
        fm = th * f_ + (1 - th) * self.phi_old
        res = (f_ - self.phi_old) / self.dt_c + ufl.dot(uvel, ufl.grad(fm))
        F_phi = (res * g_ + tau * ufl.dot(uvel, ufl.grad(g_)) * res) * dx
        bdry = dolfinx.mesh.locate_entities_boundary(mesh, fdim,
                                                     lambda X: np.full(X.shape[1], True))
        bc_phi = dolfinx.fem.dirichletbc(PETSc.ScalarType(0.0),
                                         dolfinx.fem.locate_dofs_topological(self.Q, fdim, bdry),
                                         self.Q)
        iterative = {"ksp_type": "gmres", "pc_type": "bjacobi", "sub_pc_type": "ilu",
                     "ksp_rtol": 1e-10, "ksp_atol": 1e-14, "ksp_max_it": 500}
        self.adv_phi = LinearSolver(ufl.lhs(F_phi), ufl.rhs(F_phi), [bc_phi], iterative, "phi_")
        # Gs: the advection operator is the scalar one (without phi's boundary condition),
        # the same for the six components; the stretching source S(G) = L G + G L^T is
        # taken by Heun's predictor-corrector: predictor with S(Gs^n), corrector with
        # (S(Gs^n) + S(Gs*))/2 -- second order, and only scalar solves with one matrix
        # and one ILU per step (the coupled 9x9-block tensor system cost ~10x more).
        a_g = ((f_ / self.dt_c + th * ufl.dot(uvel, ufl.grad(f_)))
               * (g_ + tau * ufl.dot(uvel, ufl.grad(g_)))) * dx
        Lg = ufl.grad(uvel)
        S = lambda G: Lg * G + G * Lg.T  # noqa: E731
        src = 0.5 * (S(self.G_old) + S(self.G_pred))
        self.adv_G = []
        for k, (i, j) in enumerate(self.IJ):
            go = self.g_old[k]
            rhs = (go / self.dt_c - (1 - th) * ufl.dot(uvel, ufl.grad(go)) + src[i, j]) \
                * (g_ + tau * ufl.dot(uvel, ufl.grad(g_))) * dx
            self.adv_G.append(dolfinx.fem.form(rhs))
        self.adv_Gmat = LinearSolver(a_g, self.adv_G[0], [], iterative, "gs_")

        # ---- diagnostics
        # shape weight w = max(2 phi - 1, 0): a function of phi, so its moments transform
        # like those of phi under an affine motion, but it vanishes outside phi = 1/2 and
        # so does not feel the truncation of the smoothed tail by the (non-cubic) box
        wgt = ufl.max_value(2 * self.phi - 1, 0.0)
        self.f_vol = dolfinx.fem.form(self.phi * dx)
        self.f_w = dolfinx.fem.form(wgt * dx)
        self.f_mom1 = [dolfinx.fem.form(wgt * x[i] * dx) for i in range(3)]
        self.xc = dolfinx.fem.Constant(mesh, np.zeros(3))
        r = x - self.xc
        self.f_mom2 = {(i, j): dolfinx.fem.form(wgt * r[i] * r[j] * dx)
                       for i in range(3) for j in range(i, 3)}
        dirac1, _, J1, _ = self.membrane(self.phi, self.G)
        self.f_area = dolfinx.fem.form(dirac1 * dx)
        self.f_J = dolfinx.fem.form(dirac1 * J1 * dx)
        self.J_nodes = dolfinx.fem.Function(self.Q)
        self.J_expr = dolfinx.fem.Expression(J1, self.Q.element.interpolation_points())
        self.t = 0.0

    @staticmethod
    def sym3(c):
        return ufl.as_matrix([[c[0], c[1], c[2]], [c[1], c[3], c[4]], [c[2], c[4], c[5]]])

    def membrane(self, phi, G):
        """|grad phi|, P, J and the neo-Hookean tension tau_s from phi and Gs."""
        gphi = ufl.grad(phi)
        delta = 1e-3 / self.eps
        n = gphi / ufl.sqrt(ufl.dot(gphi, gphi) + delta ** 2)
        P = ufl.Identity(3) - ufl.outer(n, n)
        dirac = ufl.sqrt(ufl.dot(gphi, gphi))
        Bs = P * G * P
        trB = ufl.tr(Bs)
        J2 = ufl.max_value((trB ** 2 - ufl.inner(Bs, Bs.T)) / 2, J2_MIN)
        J = ufl.sqrt(J2)
        tau_s = self.Es / (3 * J) * (Bs - P / J2)
        return dirac, P, J, tau_s

    def integrate(self, f):
        return self.comm.allreduce(dolfinx.fem.assemble_scalar(f), op=MPI.SUM)

    def shape(self):
        V, Vw = self.integrate(self.f_vol), self.integrate(self.f_w)
        xc = np.array([self.integrate(f) for f in self.f_mom1]) / Vw
        self.xc.value[:] = xc
        M = np.zeros((3, 3))
        for (i, j), f in self.f_mom2.items():
            M[i, j] = M[j, i] = self.integrate(f) / Vw
        ev, evec = np.linalg.eigh(M[:2, :2])
        Lh, Bh = np.sqrt(ev[1]), np.sqrt(ev[0])
        vv = evec[:, 1] * np.sign(evec[0, 1] if evec[0, 1] != 0 else 1)
        return {"volume": V, "volume_w": Vw, "xc": xc[0], "yc": xc[1], "zc": xc[2], "D": (Lh - Bh) / (Lh + Bh),
                "theta_over_pi": np.arctan2(vv[1], vv[0]) / np.pi,
                "Mzz": M[2, 2]}

    def membrane_state(self):
        A = self.integrate(self.f_area)
        self.J_nodes.interpolate(self.J_expr)
        band = (self.phi.x.array > 0.05) & (self.phi.x.array < 0.95)
        Jb = self.J_nodes.x.array[band]
        jmin = self.comm.allreduce(Jb.min() if Jb.size else np.inf, op=MPI.MIN)
        jmax = self.comm.allreduce(Jb.max() if Jb.size else -np.inf, op=MPI.MAX)
        return {"surface": A, "mean_J": self.integrate(self.f_J) / A,
                "J_min_band": jmin, "J_max_band": jmax}

    def step(self):
        self.phi_old.x.array[:] = self.phi.x.array
        for go, gp, g in zip(self.g_old, self.g_pred, self.g):
            go.x.array[:] = g.x.array
            gp.x.array[:] = g.x.array
        self.u_old.x.array[:] = self.u.x.array
        self.flow.solve(self.w)
        self.u.interpolate(self.w.sub(0))
        self.adv_phi.assemble_matrix()
        self.adv_phi.solve(self.phi)
        self.adv_Gmat.assemble_matrix()
        # (PETSc rebuilds the ILU once, at the first solve after the matrix changed)
        for stage in range(2):                             # predictor, corrector
            for k, g in enumerate(self.g):
                self.adv_Gmat.L = self.adv_G[k]
                self.adv_Gmat.solve(g)
            if stage == 0:
                for gp, g in zip(self.g_pred, self.g):
                    gp.x.array[:] = g.x.array
        self.t += self.dt

    def output_fields(self):
        V1 = dolfinx.fem.VectorFunctionSpace(self.mesh, ("Lagrange", 1))
        Q1 = dolfinx.fem.FunctionSpace(self.mesh, ("Lagrange", 1))
        out = []
        for f, S in ((self.u, V1), (self.phi, Q1)):
            g = dolfinx.fem.Function(S, name=f.name)
            g.interpolate(f)
            out.append(g)
        p = dolfinx.fem.Function(Q1, name="pressure")
        p.interpolate(self.w.sub(1))
        out.append(p)
        return out


def run(args, comm):
    t_wall = time.time()
    model = CapsuleShear3D(comm, args.Ca, args.Re, args.Lx, args.Ly, args.Lz, args.h_far,
                           args.refine, args.core, args.eps, args.cfl_elastic, args.dt_max,
                           args.flow_solver)
    t_setup = time.time() - t_wall
    say = (lambda *a: print(*a, flush=True)) if comm.rank == 0 else (lambda *a: None)
    n_cells = comm.allreduce(model.mesh.topology.index_map(3).size_local, op=MPI.SUM)
    n_u = model.W.dofmap.index_map.size_global
    say(f"Ca {args.Ca} Re {args.Re}: h {model.h:.4f} (d/{2 / model.h:.0f}) eps {model.eps:.4f} "
        f"dt {model.dt:.3e} tets {n_cells} flow dofs {n_u} setup {t_setup:.1f} s")
    out = Path(args.out)
    tag = f"ca{args.Ca:g}_h{2 / model.h:.0f}"
    n_steps = max(1, int(round(args.t_end / model.dt)))
    model.dt = args.t_end / n_steps
    model.dt_c.value = model.dt
    model.flow.assemble_matrix()
    if model.flow_solver != "lu":
        model.Pmat.zeroEntries()
        dolfinx.fem.petsc.assemble_matrix(model.Pmat, model.p_form, bcs=[model.bc_u])
        model.Pmat.assemble()
    out_times = sorted(set(args.write_times))
    xdmf = None
    if out_times:
        out.mkdir(parents=True, exist_ok=True)
        xdmf = dolfinx.io.XDMFFile(comm, str(out / f"capsule3d_{tag}.xdmf"), "w")
        xdmf.write_mesh(model.mesh)
    rows = []

    def record():
        s = model.shape()
        s.update(model.membrane_state())
        s["t"] = model.t
        s["wall"] = time.time() - t_wall
        rows.append(s)
        return s

    record()
    every = max(1, n_steps // 20)
    for k in range(1, n_steps + 1):
        model.step()
        s = record()
        if xdmf is not None and any(abs(model.t - tw) < 0.5 * model.dt for tw in out_times):
            for f in model.output_fields():
                xdmf.write_function(f, model.t)
        if not np.isfinite(s["D"]) or s["mean_J"] > 10:
            raise RuntimeError(f"diverged at t = {model.t}: {s}")
        if k % every == 0 or k == n_steps:
            say(f"t {model.t:6.3f}  D {s['D']:.4f}  theta/pi {s['theta_over_pi']:.4f}  "
                f"vol {s['volume']:.5f}  J in [{s['J_min_band']:.3f}, {s['J_max_band']:.3f}]  "
                f"wall {s['wall']:.0f} s", )
    if xdmf is not None:
        xdmf.close()
    wall = time.time() - t_wall
    rss = comm.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, op=MPI.SUM)
    summary = {"Ca": args.Ca, "Re": args.Re, "refine": args.refine, "h": model.h,
               "h_over_d": model.h / 2, "eps": model.eps, "dt": model.dt, "steps": n_steps,
               "tets": n_cells, "flow_dofs": n_u, "ranks": comm.size,
               "flow_solver": model.flow_solver, "wall_seconds": wall,
               "setup_seconds": t_setup, "max_rss_MB_sum": rss,
               "D_final": rows[-1]["D"], "theta_over_pi_final": rows[-1]["theta_over_pi"],
               "volume_drift": rows[-1]["volume"] / rows[0]["volume"] - 1,
               "volume_w_drift": rows[-1]["volume_w"] / rows[0]["volume_w"] - 1,
               "D_initial": rows[0]["D"], "t_end": model.t,
               "J_min_band": min(r["J_min_band"] for r in rows),
               "J_max_band": max(r["J_max_band"] for r in rows),
               "box": [args.Lx, args.Ly, args.Lz]}
    if comm.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
        keys = ["t", "D", "theta_over_pi", "volume", "volume_w", "xc", "yc", "zc", "Mzz", "surface",
                "mean_J", "J_min_band", "J_max_band", "wall"]
        np.savetxt(out / f"capsule3d_{tag}.csv", np.array([[r[k] for k in keys] for r in rows]),
                   delimiter=",", header=",".join(keys), comments="")
        (out / f"capsule3d_{tag}.json").write_text(json.dumps(summary, indent=1))
    say(json.dumps(summary))
    return summary


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--Ca", type=float, default=0.05)
    ap.add_argument("--Re", type=float, default=0.01)
    ap.add_argument("--Lx", type=float, default=8.0)
    ap.add_argument("--Ly", type=float, default=6.0, help="wall distance (a = 1)")
    ap.add_argument("--Lz", type=float, default=6.0)
    ap.add_argument("--h-far", dest="h_far", type=float, default=0.5)
    ap.add_argument("--refine", type=int, default=1)
    ap.add_argument("--core", type=float, default=1.75, help="half-width of refined cube")
    ap.add_argument("--eps", type=float, default=1.0, help="smoothing width / h")
    ap.add_argument("--cfl-elastic", dest="cfl_elastic", type=float, default=0.5)
    ap.add_argument("--dt-max", dest="dt_max", type=float, default=0.02)
    ap.add_argument("--t-end", dest="t_end", type=float, default=0.5)
    ap.add_argument("--flow-solver", dest="flow_solver", choices=["lu", "minres"], default="lu")
    ap.add_argument("--write-times", dest="write_times", type=float, nargs="*", default=[])
    ap.add_argument("--small", action="store_true",
                    help="tiny case for tests: box 4 x 4 x 4 (2d), h = d/4, t_end 0.1")
    ap.add_argument("--out", default="build/reference/vesicle3d")
    args = ap.parse_args(argv)
    if args.small:
        args.Lx, args.Ly, args.Lz, args.h_far, args.refine, args.t_end = 4.0, 4.0, 4.0, 0.5, 0, 0.1
    run(args, MPI.COMM_WORLD)
    return 0


if __name__ == "__main__":
    sys.exit(main())
