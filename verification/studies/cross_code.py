"""Cross-code field comparison: the C++ finite-volume solver against the FEniCSx reference,
both read through meshio and compared at common points.

(a) 2D capsule in simple shear (z-invariant neo-Hookean ring, Re = 0.01, walls at
    y = +-Ly/2 moving at +-Ly/2): ``efsi run cases/capsule_shear_2d`` (box, cells, Es = 1/Ca
    and smoothing width set with --set) against ``reference/vesicle_shear_2d.py`` at the same
    h = d/n at the capsule. Common points: the C++ cell centres. The FE script evaluates its
    own solution there (``--probe-grid``: P2 velocity and phi, P1 pressure, DOLFINx point
    evaluation) and writes it with meshio; both files are read with
    ``meshio.xdmf.TimeSeriesReader``. The FE script's DOLFINx XDMF (P1 interpolants, one
    file per field because meshio reads one temporal collection per file) is read too and
    interpolated to the same centres with matplotlib.tri: reported as the "P1 path", to
    show what reading interpolated FE data would add.
    Matching set-up: the same phi profile (C++ phi = (1 - tanh(L/eps_c))/2 with
    eps_c = 2 cells is the FE's 1/(1 + exp(L/eps_f)) with eps_f = h; checked at t = 0),
    the same Re, Ca, box height and walls. Not the same: the C++ box is periodic in x, the
    FE box has the undisturbed shear traction on its ends x = +-Lx/2 (DOLFINx 0.5 has no
    periodic constraint); so the norms are taken over the window |x| <= Lx/4 (the whole-box
    numbers are in the tables), and the end effect is not a discretisation error.
    Norms at t (relative, over the window):
      velocity  ||u_fd - u_fe||_2 / ||u_fe - u_shear||_2 (the disturbance flow, because the
                imposed shear carries 98 % of ||u|| and would hide everything),
      pressure  ||p'_fd - p'_fe||_2 / ||p'_fe||_2 with p' = p - mean over the window,
      phi       sum |phi_fd - phi_fe| / sum phi_fe (L1).

(b) Membrane load on a prescribed shape: the reference sphere R0 = 0.5 moved by the linear
    map x = c + A X of ``efsi_membrane_force_study --map linear`` (neo-Hookean, Es = 1):
    the C++ Eulerian force |grad phi| f (smoothed phi, eps = 1 cell, Gs = A P_R A^T exact,
    written with ``--write``) against the FE load q of ``reference/membrane_stress.py
    single --degree 2`` (isoparametric P2 surface, same A, written as VTU by meshio).
    Common points: the FE surface nodes (C++ points are x + c). Two traction measures of the
    C++ band force at each node x with the exact normal n of the deformed ellipsoid:
      line      t(x) = int_{-8h}^{8h} F(x + s n) ds (trilinear interpolation of the
                cell-centred force, 8 samples per cell, trapezoid rule), at every FE node;
      smoothed  sum_cells F K dV with the Gaussian surface kernel
                K = exp(-|P(y - x)|^2 / l^2) / (pi l^2), l = 2h, over the band cells,
                against sum_nodes q K dA of the FE load (the same functional on both
                sides), at the 642 vertices of the level-3 icosahedron.
    Norm: area-weighted relative L2 over the FE nodes, ||t - q|| / ||q||.

Metrics: fd_fe_velocity_diff_L2_d<n>, fd_fe_pressure_diff_L2_d<n>, fd_fe_phi_diff_L1_d<n>
(at the last time; _t<T> at the others), their orders fd_fe_*_diff_order (least-squares
slope against h); fd_fe_membrane_force_diff_n<cells> (line traction), its normal and
tangential parts, fd_fe_membrane_force_smoothed_diff_n<cells>, and their orders.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess

import numpy as np

import _meshcompare as mc
from _flowio import slope

from _bounds import Bound  # noqa: E402

DESCRIPTION = ("cross-code: C++ vs FE fields through meshio (2D capsule in shear: u, p, phi; "
               "membrane traction on a linearly deformed sphere)")

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"fd_fe_velocity_diff_order", ">=", 0.8,
          "efsi and the FE reference converge to each other (velocity, first order or better)"),
    Bound(r"fd_fe_membrane_force_smoothed_diff_order", ">=", 1.0,
          "the band-smoothed membrane traction converges to the FE one"),
    Bound(r"fd_fe_phi_diff_L1_t0_max", "<=", 1e-3, "both codes start from the same capsule"),
    Bound(r"fd_fe_D_rel_diff_d[0-9]+", ">=", -0.1, "D(t) within 10 % of the FE reference"),
    Bound(r"fd_fe_D_rel_diff_d[0-9]+", "<=", 0.1, "D(t) within 10 % of the FE reference"),
    Bound(r"fd_fe_D_rel_diff_d32", ">=", -0.05, "D(1) within 5 % of the FE at d/32",
          tiers=("full",)),
    Bound(r"fd_fe_D_rel_diff_d32", "<=", 0.05, "D(1) within 5 % of the FE at d/32",
          tiers=("full",)),
]

# capsule: n = cells per diameter d = 2 a; box (Lx, Ly); times compared.
# membrane: cells across the reference diameter 2 R0.
TIERS = {
    "ci": {"capsule": {"ns": [8, 12], "box": (8.0, 8.0), "times": [0.1, 0.2], "Ca": 0.2},
           "membrane": {"cells": [16, 20, 24], "fe_level": 3}},
    "quick": {"capsule": {"ns": [8, 12, 16], "box": (16.0, 8.0), "times": [0.5, 1.0],
                          "Ca": 0.2},
              "membrane": {"cells": [16, 24, 32]}},
    "full": {"capsule": {"ns": [8, 16, 32], "box": (16.0, 8.0), "times": [0.5, 1.0],
                         "Ca": 0.2},
             "membrane": {"cells": [16, 32, 64]}},
}
# The linear map of efsi_membrane_force_study (3D) and its centre; R0 = 0.5, Es = 1.
A_MAP = np.array([[1.15, 0.12, 0.0], [-0.05, 0.9, 0.08], [0.03, 0.0, 1.05]])
C_MAP = np.array([0.013, 0.027, 0.041])
R0 = 0.5
SMOOTH_POINTS = 642   # vertices of the level-3 icosahedron
C_SMOOTH = 2.0        # C++ smoothing width (cells) matching the FE's eps = h


def fe_mesh(n: int):
    """(h_far, refine) of the FE mesh with h = d/n = 2/n at the capsule."""
    refine = max(1, int(math.floor(math.log2(n / 4))))
    return 2.0 ** (refine + 1) / n, refine


def fe_level(cells: int) -> int:
    """Icosahedron level whose edge (0.602 R0 / 2^(level-1)) is nearest h = 2 R0 / cells."""
    h = 2 * R0 / cells
    return max(3, int(round(1 + math.log2(0.602 * R0 / h))))


# ---------------------------------------------------------------------- (a) capsule
def run_capsule(ctx, cfg, metrics, tables, figures):
    Lx, Ly = cfg["box"]
    times, Ca = cfg["times"], cfg["Ca"]
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    rows, fields = [], {}
    for n in cfg["ns"]:
        h = 2.0 / n
        nx, ny = int(round(Lx / h)), int(round(Ly / h))
        cdir = ctx.outdir / f"capsule_fd_d{n}"
        sets = {"grid.cells": f"[{nx},{ny},1]", "grid.length": f"[{Lx},{Ly},{h}]",
                "grid.origin": f"[{-Lx / 2},{-Ly / 2},{-h / 2}]",
                "boundary.y_low.velocity": f"[{-Ly / 2},0.0,0.0]",
                "boundary.y_high.velocity": f"[{Ly / 2},0.0,0.0]",
                "initial.amplitude": Ly / 2, "time.end_time": times[-1],
                "output.fields_interval": times[0], "body[0].elastic_modulus": 1.0 / Ca,
                "body[0].smoothing_width": C_SMOOTH}
        if nx & (nx - 1):       # PFMG needs a power of two along the periodic x
            sets["solver.pressure.method"] = "pcg_smg"
        # fresh directories: the C++ field output extends an existing series (restarts)
        shutil.rmtree(cdir, ignore_errors=True)
        fd_sum = ctx.run_efsi(ctx.repo / "cases" / "capsule_shear_2d", cdir, sets)
        h_far, refine = fe_mesh(n)
        fdir = ctx.outdir / f"capsule_fe_d{n}"
        shutil.rmtree(fdir, ignore_errors=True)
        ctx.run([ctx.python, ctx.repo / "reference" / "vesicle_shear_2d.py", "--Ca", Ca,
                 "--h-far", h_far, "--refine", refine, "--Lx", Lx, "--Ly", Ly,
                 "--t-end", times[-1], "--write-times", 0, *times, "--probe-grid", nx, ny,
                 "--out", fdir])
        tag = f"ca{Ca:g}_r{refine}"
        fe_sum = json.loads((fdir / f"capsule_{tag}.json").read_text())
        assert abs(fe_sum["h"] - h) < 1e-12, (fe_sum["h"], h)

        # both codes through meshio
        pts, cells, fd_steps = mc.read_series(cdir / "fields" / "fields.xdmf")
        xc = mc.cell_centres(pts, cells)[:, :2]
        fpts, fcells, fe_steps = mc.read_series(fdir / f"capsule_{tag}_probe.xdmf")
        xf = mc.cell_centres(fpts, fcells)
        if np.abs(xf - xc).max() > 1e-9 * Lx:
            raise RuntimeError("the FE probe points are not the C++ cell centres")
        # the P1 path: DOLFINx's own XDMF (P1 interpolants) + matplotlib.tri
        p1 = {}
        for name in ("velocity", "pressure", "phi"):
            p1[name] = mc.read_series(fdir / f"capsule_{tag}_{name}.xdmf")
        interp = mc.P1Interpolant(p1["phi"][0], p1["phi"][1][0].data)

        window = np.abs(xc[:, 0]) <= Lx / 4 + 1e-12
        u_shear = np.c_[xc[:, 1], np.zeros(len(xc))]
        for T in [0.0] + times:
            (tf, _, cd), dtf = mc.at_time(fd_steps, T)
            (te, _, ed), dte = mc.at_time(fe_steps, T)
            if dtf > 1e-9 or dte > 1e-6:
                raise RuntimeError(f"no snapshot at t = {T}: C++ {tf}, FE {te}")
            u = mc.cell_field(cd, "velocity")[:, :2]
            p = mc.cell_field(cd, "pressure")
            phi = mc.cell_field(cd, "phi_capsule")
            ue, pe, phie = (mc.cell_field(ed, k) for k in ("velocity", "pressure", "phi"))
            row = {"n": n, "h": h, "t": T, "fd_cells": nx * ny, "fe_cells": fe_sum["cells"]}
            for region, m in (("window", window), ("box", np.ones(len(xc), bool))):
                if T > 0:
                    row[f"u_{region}"] = mc.rel_l2(u[m] - ue[m], ue[m] - u_shear[m])
                    row[f"u_total_{region}"] = mc.rel_l2(u[m] - ue[m], ue[m])
                    pm, pem = p[m] - p[m].mean(), pe[m] - pe[m].mean()
                    row[f"p_{region}"] = mc.rel_l2(pm - pem, pem)
                row[f"phi_{region}"] = mc.rel_l1(phi[m] - phie[m], phie[m])
            # P1 path (FE values interpolated from the P1 XDMF), window only
            snap = {k: mc.at_time(v[2], T)[0][1] for k, v in p1.items()}
            phi_p1 = interp(snap["phi"]["phi"], xc[:, 0], xc[:, 1])
            row["phi_window_p1path"] = mc.rel_l1(phi[window] - phi_p1[window], phie[window])
            if T > 0:
                u_p1 = interp(snap["velocity"]["velocity"][:, :2], xc[:, 0], xc[:, 1])
                row["u_window_p1path"] = mc.rel_l2(u[window] - u_p1[window],
                                                   ue[window] - u_shear[window])
            rows.append(row)
            if T == times[-1]:
                fields[n] = {"xc": xc, "nx": nx, "ny": ny, "u": u, "ue": ue, "p": p, "pe": pe,
                             "phi": phi, "phie": phie, "window": window}
        fe_csv = np.genfromtxt(fdir / f"capsule_{tag}.csv", delimiter=",", names=True)
        fd_csv = np.genfromtxt(cdir / "bodies.csv", delimiter=",", names=True, dtype=None,
                               encoding=None)
        metrics[f"fd_D_d{n}"] = float(fd_csv["taylor_deformation"][-1])
        metrics[f"fe_D_d{n}"] = float(fe_csv["D"][-1])
        metrics[f"fd_fe_D_rel_diff_d{n}"] = metrics[f"fd_D_d{n}"] / metrics[f"fe_D_d{n}"] - 1
        fields[n]["theta"] = float(fe_csv["theta_over_pi"][-1]) * np.pi
        metrics[f"fd_wall_seconds_capsule_d{n}"] = fd_sum["wall_seconds"]
        metrics[f"fe_wall_seconds_capsule_d{n}"] = fe_sum["wall_seconds"]

    ns = cfg["ns"]
    hs = [2.0 / n for n in ns]
    # periodic images: the C++ run again in a box twice as long, compared in the window
    n = ns[-1]
    h = 2.0 / n
    nx2, ny = int(round(2 * Lx / h)), int(round(Ly / h))
    ldir = ctx.outdir / f"capsule_fd_d{n}_long"
    shutil.rmtree(ldir, ignore_errors=True)
    sets.update({"grid.cells": f"[{nx2},{ny},1]", "grid.length": f"[{2 * Lx},{Ly},{h}]",
                 "grid.origin": f"[{-Lx},{-Ly / 2},{-h / 2}]"})
    if not nx2 & (nx2 - 1):
        sets.pop("solver.pressure.method", None)
    ctx.run_efsi(ctx.repo / "cases" / "capsule_shear_2d", ldir, dict(sets))
    lpts, lcells, lsteps = mc.read_series(ldir / "fields" / "fields.xdmf")
    xl = mc.cell_centres(lpts, lcells)[:, :2]
    f = fields[n]
    w = f["window"]
    ul = mc.CellGrid(np.c_[xl, np.zeros(len(xl))], 2)
    (tl, _, cl), _ = mc.at_time(lsteps, times[-1])
    uw = ul.interpolator(mc.cell_field(cl, "velocity")[:, :2])(f["xc"][w])   # same centres
    pl = ul.interpolator(mc.cell_field(cl, "pressure"))(f["xc"][w])
    u_sh = np.c_[f["xc"][w, 1], np.zeros(w.sum())]
    metrics[f"fd_periodic_image_velocity_L2_d{n}"] = mc.rel_l2(f["u"][w] - uw, f["ue"][w] - u_sh)
    pw = f["p"][w] - f["p"][w].mean()
    metrics[f"fd_periodic_image_pressure_L2_d{n}"] = mc.rel_l2(
        pw - (pl - pl.mean()), f["pe"][w] - f["pe"][w].mean())
    for T in times:
        suffix = "" if T == times[-1] else f"_t{T:g}"
        sel = [r for r in rows if r["t"] == T]
        for key, metric in (("u_window", "velocity_diff_L2"), ("p_window", "pressure_diff_L2"),
                            ("phi_window", "phi_diff_L1")):
            vals = [r[key] for r in sel]
            for n, v in zip(ns, vals):
                metrics[f"fd_fe_{metric}_d{n}{suffix}"] = v
            metrics[f"fd_fe_{metric.rsplit('_', 1)[0]}_order{suffix}"] = slope(hs, vals)
    last = [r for r in rows if r["t"] == times[-1]]
    for n, r in zip(ns, last):
        metrics[f"fd_fe_phi_diff_L1_p1path_d{n}"] = r["phi_window_p1path"]
        metrics[f"fd_fe_velocity_diff_L2_p1path_d{n}"] = r["u_window_p1path"]
        metrics[f"fd_fe_velocity_diff_L2_wholebox_d{n}"] = r["u_box"]
    t0 = [r for r in rows if r["t"] == 0.0]
    metrics["fd_fe_phi_diff_L1_t0_max"] = max(r["phi_window"] for r in t0)
    tables["capsule"] = rows
    figures.append(str(plot_capsule(ctx, cfg, fields, rows)))


def plot_capsule(ctx, cfg, fields, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    Lx, Ly = cfg["box"]
    times = cfg["times"]
    n = max(fields)
    f = fields[n]
    nx, ny, xc = f["nx"], f["ny"], f["xc"]
    order = np.lexsort((xc[:, 0], xc[:, 1]))          # y-major, x fastest
    grid = lambda v: v[order].reshape(ny, nx)          # noqa: E731
    fig, axes = plt.subplots(2, 3, figsize=(16, 8.5))
    ext = [-Lx / 2, Lx / 2, -Ly / 2, Ly / 2]
    du = np.linalg.norm(f["u"] - f["ue"], axis=1)
    w = f["window"]
    dp = (f["p"] - f["p"][w].mean()) - (f["pe"] - f["pe"][w].mean())
    dphi = f["phi"] - f["phie"]
    for ax, val, title, cmap in ((axes[0, 0], du, "|u_FD - u_FE|", "viridis"),
                                 (axes[0, 1], dp, "p_FD - p_FE (window means removed)", "RdBu_r"),
                                 (axes[0, 2], dphi, "phi_FD - phi_FE", "RdBu_r")):
        lim = np.abs(val[w]).max()                    # colour scale from the window
        im = ax.imshow(grid(val), origin="lower", extent=ext, cmap=cmap,
                       vmin=-lim if cmap != "viridis" else 0, vmax=lim)
        ax.contour(np.unique(xc[:, 0]), np.unique(xc[:, 1]), grid(f["phie"]), [0.5],
                   colors="k", linewidths=0.6)
        for xw in (-Lx / 4, Lx / 4):
            ax.axvline(xw, color="0.4", ls=":", lw=0.8)
        ax.set_title(f"{title}, d/{n}, t = {times[-1]:g}", fontsize=9)
        fig.colorbar(im, ax=ax, shrink=0.8)
    # profiles through the centre: u_x - y along x = 0 and p along y = 0 (nearest cells)
    ax = axes[1, 0]
    for k, nn in enumerate(sorted(fields)):
        g = fields[nn]
        x0 = np.unique(g["xc"][:, 0])
        col = np.abs(g["xc"][:, 0] - x0[np.argmin(np.abs(x0))]) < 1e-9
        y = g["xc"][col, 1]
        o = np.argsort(y)
        ax.plot(y[o], (g["u"][col, 0] - y)[o], "-", color=f"C{k}", label=f"FD d/{nn}")
        ax.plot(y[o], (g["ue"][col, 0] - y)[o], "--", color=f"C{k}", label=f"FE d/{nn}")
    ax.set(xlabel="y (x = 0)", ylabel="u_x - shear rate y", title="disturbance velocity")
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    s_ax = np.linspace(-3.0, 3.0, 601)            # along the major axis through the origin
    for k, nn in enumerate(sorted(fields)):
        g = fields[nn]
        line = np.c_[np.cos(g["theta"]) * s_ax, np.sin(g["theta"]) * s_ax]
        grid2 = mc.CellGrid(np.c_[g["xc"], np.zeros(len(g["xc"]))], 2)
        w = g["window"]
        for val, ls, code in ((g["p"], "-", "FD"), (g["pe"], "--", "FE")):
            ax.plot(s_ax, grid2.interpolator(val - val[w].mean())(line), ls, color=f"C{k}",
                    label=f"{code} d/{nn}")
    ax.set(xlabel="distance from the centre along the major axis (FE inclination)",
           ylabel="p - window mean", title="pressure through the capsule tips")
    ax.legend(fontsize=7)
    ax = axes[1, 2]
    for T, ls in zip(times, ("--", "-")):
        sel = [r for r in rows if r["t"] == T]
        h = [r["h"] for r in sel]
        for key, lab, c in (("u_window", "velocity L2", "C0"), ("p_window", "pressure L2", "C1"),
                            ("phi_window", "phi L1", "C2")):
            v = [r[key] for r in sel]
            ax.loglog(h, v, ls, marker="o", color=c,
                      label=f"{lab}, t={T:g} (slope {slope(h, v):.2f})")
    ax.set(xlabel="h (= d/n)", ylabel="relative difference FD - FE", title="difference vs h")
    ax.set_xticks(hs := sorted({r["h"] for r in rows}))
    ax.set_xticklabels([f"d/{2 / v:.0f}" for v in hs])
    ax.minorticks_off()
    ax.legend(fontsize=7)
    fig.suptitle(f"2D capsule in shear, Ca = {cfg['Ca']:g}: C++ (periodic box) vs FE "
                 f"(traction ends); norms over |x| <= {Lx / 4:g} (dotted)", fontsize=10)
    fig.tight_layout()
    png = ctx.outdir / "cross_code_capsule.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return png


# ---------------------------------------------------------------------- (b) membrane
def force_study_binary(ctx):
    exe = os.environ.get("EFSI_MEMBRANE_FORCE_BIN",
                         str(ctx.efsi.parent / "efsi_membrane_force_study"))
    helptext = subprocess.run([exe, "--help"], capture_output=True, text=True).stdout
    if "--write" not in helptext:
        raise RuntimeError(f"{exe} has no --write option (built before it was added): rebuild, "
                           "or point EFSI_MEMBRANE_FORCE_BIN at a build that has it")
    return exe


def run_membrane(ctx, cfg, metrics, tables, figures):
    import meshio
    from scipy.spatial import cKDTree

    exe = force_study_binary(ctx)
    Ainv = np.linalg.inv(A_MAP)
    fe_cache, rows, keep = {}, [], {}
    for cells in cfg["cells"]:
        level = cfg.get("fe_level") or fe_level(cells)
        if level not in fe_cache:
            fdir = ctx.outdir / f"membrane_fe_l{level}"
            ctx.run([ctx.python, ctx.repo / "reference" / "membrane_stress.py", "single",
                     "--shape", "sphere", "--R0", R0, "--degree", 2, "--level", level,
                     "--map", "linear:" + ",".join(f"{a:g}" for a in A_MAP.ravel()),
                     "--out", fdir])
            m = meshio.read(fdir / "sphere_neo-hookean.vtu")
            x, q = m.points, m.point_data["load"]
            X = x @ Ainv.T                                  # reference points
            nrm = X @ Ainv                                  # A^-T X: normal of the image
            nrm /= np.linalg.norm(nrm, axis=1)[:, None]
            fe_cache[level] = (x, q, nrm, mc.lumped_node_areas(x, m.cells), X)
        x, q, nrm, w, X = fe_cache[level]

        cdir = ctx.outdir / f"membrane_fd_n{cells}"
        shutil.rmtree(cdir, ignore_errors=True)
        res = ctx.run([exe, "--dim", 3, "--cells", cells, "--map", "linear", "--write", cdir])
        summary = json.loads(res.stdout)
        pts, cblocks, steps = mc.read_series(cdir / "fields" / "fields.xdmf")
        centres = mc.cell_centres(pts, cblocks)
        grid = mc.CellGrid(centres, 3)
        F = mc.cell_field(steps[0][2], "velocity")
        h = grid.h[0]
        W = 8 * h
        pts_fd = x + C_MAP
        t_line = mc.line_traction(grid.interpolator(F), pts_fd, nrm, W, samples=16 * 8 + 1)
        if np.isnan(t_line).any():
            raise RuntimeError("line traction left the grid")
        # smoothed tractions at the 642 vertices of the level-3 icosahedron (the first
        # nodes of every finer level), weighted by the area of their nearest-node cells
        sub = slice(0, SMOOTH_POINTS)
        w_sub = np.bincount(cKDTree(x[sub]).query(x)[1], weights=w, minlength=SMOOTH_POINTS)
        ell = 2 * h
        t_sm = mc.smoothed_traction_volume(centres, F, h ** 3, pts_fd[sub], nrm[sub], ell, W)
        q_sm = mc.smoothed_traction_surface(x, q, w, x[sub], nrm[sub], ell)
        d = t_line - q
        dn = np.sum(d * nrm, 1)
        row = {"cells": cells, "h": h, "fe_level": level, "fe_nodes": len(x),
               "grid": summary["grid"], "line": mc.rel_l2(d, q, w),
               "line_normal": mc.rel_l2(dn, q, w),
               "line_tangential": mc.rel_l2(d - dn[:, None] * nrm, q, w),
               "line_mean_normal": float(np.sum(w * dn) / np.sum(w * np.linalg.norm(q, axis=1))),
               "smoothed": mc.rel_l2(t_sm - q_sm, q_sm, w_sub),
               "bump_error_vs_exact": summary["force_error"]}
        rows.append(row)
        keep[cells] = (X, d, dn, nrm, q, t_line)
        tag = f"n{cells}"
        metrics[f"fd_fe_membrane_force_diff_{tag}"] = row["line"]
        metrics[f"fd_fe_membrane_force_diff_normal_{tag}"] = row["line_normal"]
        metrics[f"fd_fe_membrane_force_diff_tangential_{tag}"] = row["line_tangential"]
        metrics[f"fd_fe_membrane_force_smoothed_diff_{tag}"] = row["smoothed"]
        metrics[f"fd_membrane_force_bump_error_{tag}"] = row["bump_error_vs_exact"]
    hs = [r["h"] for r in rows]
    for key, name in (("line", "fd_fe_membrane_force_diff_order"),
                      ("line_normal", "fd_fe_membrane_force_diff_normal_order"),
                      ("line_tangential", "fd_fe_membrane_force_diff_tangential_order"),
                      ("smoothed", "fd_fe_membrane_force_smoothed_diff_order")):
        metrics[name] = slope(hs, [r[key] for r in rows])
    tables["membrane"] = rows
    figures.append(str(plot_membrane(ctx, rows, keep)))


def plot_membrane(ctx, rows, keep):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 4, figsize=(21, 4.6))
    cells = max(keep)
    X, d, dn, nrm, q, t_line = keep[cells]
    r = np.linalg.norm(X, axis=1)
    theta = np.arccos(np.clip(X[:, 2] / r, -1, 1))
    phi = np.arctan2(X[:, 1], X[:, 0])
    lim = np.abs(dn).max()
    sc = axes[0].scatter(phi, theta, c=dn, s=3, cmap="RdBu_r", vmin=-lim, vmax=lim)
    fig.colorbar(sc, ax=axes[0])
    axes[0].set(xlabel="reference azimuth", ylabel="reference polar angle",
                title=f"normal part of t_line - q_FE, {cells} cells across")
    sc = axes[1].scatter(phi, theta, c=np.linalg.norm(d - dn[:, None] * nrm, axis=1), s=3)
    fig.colorbar(sc, ax=axes[1])
    axes[1].set(xlabel="reference azimuth", title="|tangential part of t_line - q_FE|")
    ax = axes[2]                                   # profile along the reference equator
    for c_ in sorted(keep):
        Xc, _, _, nc, qc, tc = keep[c_]
        eq = np.abs(Xc[:, 2]) < 0.03 * np.linalg.norm(Xc, axis=1)
        az = np.arctan2(Xc[eq, 1], Xc[eq, 0])
        o = np.argsort(az)
        ax.plot(az[o], np.sum(tc * nc, 1)[eq][o], ".-", ms=2, lw=0.5,
                label=f"C++ line traction, {c_} cells")
        if c_ == cells:
            ax.plot(az[o], np.sum(qc * nc, 1)[eq][o], "k-", lw=1.2, label=f"FE q.n, {c_} cells")
    ax.set(xlabel="reference azimuth (nodes with |Z| < 0.03 |X|)",
           ylabel="normal load q.n (n outward)", title="normal load near the equator")
    ax.legend(fontsize=7)
    ax = axes[3]
    h = [r_["h"] for r_ in rows]
    for key, lab, mk in (("line", "line traction", "o-"), ("line_normal", "  normal part", "s--"),
                         ("line_tangential", "  tangential part", "^--"),
                         ("smoothed", "smoothed (kernel 2h), both codes", "D-"),
                         ("bump_error_vs_exact", "C++ bump error vs exact load", "x:")):
        v = [r_[key] for r_ in rows]
        ax.loglog(h, v, mk, label=f"{lab} (slope {slope(h, v):.2f})")
    ax.set(xlabel="h", ylabel="relative L2 difference", title="membrane load: FD vs FE")
    ax.legend(fontsize=7)
    fig.tight_layout()
    png = ctx.outdir / "cross_code_membrane.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return png


def run(ctx):
    cfg = TIERS[ctx.tier]
    metrics, tables, figures = {}, {}, []
    run_capsule(ctx, cfg["capsule"], metrics, tables, figures)
    run_membrane(ctx, cfg["membrane"], metrics, tables, figures)
    cap = cfg["capsule"]
    notes = (
        f"(a) 2D capsule, Ca = {cap['Ca']:g}, d/n = {cap['ns']}: both codes at the same h, "
        "the FE solution evaluated at the C++ cell centres by the FE script (meshio XDMF), "
        f"norms over |x| <= {cap['box'][0] / 4:g} (C++ periodic in x, FE with traction ends). "
        "Velocity difference relative to the FE disturbance flow u - shear. The '_p1path' "
        "metrics read DOLFINx's P1 XDMF and interpolate with matplotlib.tri instead: the "
        "difference to the probe numbers is the P1 interpolation of P2 data. "
        "(b) line traction = C++ band force integrated along the exact normal over +-8h; "
        "'smoothed' = both loads filtered by the same Gaussian surface kernel of width 2h. "
        "See the module docstring for the exact definitions.")
    return {"metrics": metrics, "tables": tables, "figures": figures, "notes": notes}
