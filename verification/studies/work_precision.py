"""Work-precision: error against wall time for each verified problem and each solver.

For every problem the SAME problem is solved by each available solver at several
resolutions, the error is measured against the same exact or independent reference, and the
wall time of the whole process is measured here (time.perf_counter around the command; the
minimum of two repeats for runs shorter than SHORT_RUN seconds) together with the solver's
own timer (efsi summary.json ``wall_seconds``, the FE scripts' solve timers: no Python or
MPI start-up) and os.getloadavg() before each run.

Problems (error measure; reference):
* flow_mms: 2D Taylor-Green vortex, Re = 100, t = 1 (as verification/studies/flow_mms.py
  runs it); RMS velocity error against the exact solution. efsi on 1 and 2 ranks (the
  flow_mms settings: dt = 16 T / N^2, tight solver tolerances) and on 1 rank with the
  case's automatic dt; FE: reference/flow_mms.py --equations taylor-green (Taylor-Hood
  P2/P1, Crank-Nicolson/AB2, exact velocity on three sides, exact traction on the fourth).
* vof_single_vortex: the single-vortex VOF test (T = 8) of vof_advection.py
  (efsi_vof_study, MTHINC); shape error sum |phi(T) - phi(0)| dV. efsi 1 and 2 ranks; no FE
  VOF exists in reference/.
* parallel_slab / parallel_slab_sharp: Sugiyama's oscillating parallel plate with a smooth
  (tanh, width 1/16) and a sharp solid layer; relative L2 error of u(y, t = 2) against the
  1D FE reference on a fine mesh (N = 512, dt = 5e-4), as parallel_slab.py measures it.
  efsi 1 and 2 ranks (2 ranks: smooth layer only) vs reference/parallel_slab_1d.py at
  coarser meshes.
* capsule_2d: 2D capsule in shear, Ca = 0.05, to shear rate x t = 1; |D(1) - D_BI(1)| with
  D_BI from reference/capsule_bi_2d.py at its finest N in this tier (run here). efsi
  cases/capsule_shear_2d (1 and 2 ranks) vs reference/vesicle_shear_2d.py.
* capsule_3d: 3D capsule D(t): max |D - D_ref| over shear rate x t in [0.2, 2] against
  Ramanujan & Pozrikidis 1998 (capsule_shear.py's measure), from the cached runs of the
  capsule_shear study (build/verification/capsule_shear/runs/3d_*_t2, their solver wall time)
  plus a d/8 run (32^3, Ca 0.2) made here on 1 and 2 ranks. FE: the 3D Eulerian FE run as measured
  by the stored full tier of reference_vesicle (its Ca, d/8, wall time and D at its sample
  times, read from verification/results/reference_vesicle/result.json, never typed here).

Equal-error comparison: for a target error inside the range both solvers reach, the time
each needs is interpolated linearly in log(time) against log(error) between the two runs
that bracket it (``time_at_error``); the target is the geometric middle of the overlap of
the two error ranges (``equal_error``). No extrapolation: when the ranges do not overlap
the speedup metric is omitted and, where one solver's cheapest run is already more
accurate than the other's best, a bound is reported instead (``disjoint_bound``).
"""
from __future__ import annotations

import numpy as np

from _wp_analysis import analyse, capsule_3d_analysis, load_description, markdown_table, plot
from _wp_problems import PRESSURE_CAP, SHORT_RUN, capsule_2d, capsule_3d, flow_mms, slab, vof

from _bounds import Bound  # noqa: E402

DESCRIPTION = ("work-precision: error vs wall time, efsi (1 and 2 ranks) vs FE reference, "
               "speedup at equal error")

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"speedup_vs_fe_at_equal_error_flow_mms", ">=", 1.0,
          "efsi reaches the FE reference's flow error in less time"),
    Bound(r"speedup_vs_fe_at_equal_error_capsule_2d", ">=", 1.0,
          "efsi reaches the FE reference's 2D capsule error in less time", tiers=("quick", "full")),
]

TIERS = {
    "ci": {"flow_mms": {"cpp": [8, 16], "cpp_auto_dt": [], "cpp_2ranks": [8, 16],
                        "fe": [16, 32]}},
    # quick: 2-rank runs on the coarser grids only (on the loaded 2-core machine they are
    # slower than 1 rank and would dominate the tier's time); full: every grid.
    "quick": {"flow_mms": {"cpp": [8, 16, 32, 64], "cpp_auto_dt": [16, 32, 64, 128],
                           "cpp_2ranks": [8, 16, 32], "fe": [8, 16, 32, 64]},
              "vof": {"cpp": [32, 64], "cpp_2ranks": [32]},
              "slab": {"cpp": [16, 32, 64], "cpp_2ranks": [16], "fe": [8, 16, 32, 64]},
              "capsule_2d": {"cpp": [8, 16], "cpp_2ranks": [8], "fe_refine": [1, 2],
                             "bi_N": [64, 128]},
              "capsule_3d": {"run_n": [8], "ranks": [1]}},
    "full": {"flow_mms": {"cpp": [8, 16, 32, 64, 128], "cpp_auto_dt": [16, 32, 64, 128, 256],
                          "cpp_2ranks": [8, 16, 32, 64, 128], "fe": [8, 16, 32, 64, 128]},
             "vof": {"cpp": [32, 64, 128], "cpp_2ranks": [32, 64, 128]},
             "slab": {"cpp": [16, 32, 64, 128], "cpp_2ranks": [16, 32, 64],
                      "fe": [8, 16, 32, 64, 128]},
             "capsule_2d": {"cpp": [8, 16, 32], "cpp_2ranks": [8, 16, 32],
                            "fe_refine": [1, 2, 3], "bi_N": [128, 256]},
             "capsule_3d": {"run_n": [8], "ranks": [1, 2]}},
}

def run(ctx):
    cfg = TIERS[ctx.tier]
    problems = {"flow_mms": flow_mms(ctx, cfg["flow_mms"])}
    if "vof" in cfg:
        problems["vof_single_vortex"] = vof(ctx, cfg["vof"])
    if "slab" in cfg:
        problems.update(slab(ctx, cfg["slab"]))
    if "capsule_2d" in cfg:
        problems["capsule_2d"] = capsule_2d(ctx, cfg["capsule_2d"])
    if "capsule_3d" in cfg:
        problems["capsule_3d"] = capsule_3d(ctx, cfg["capsule_3d"])

    metrics, table = {}, []
    for name, prob in problems.items():
        if name == "capsule_3d":
            capsule_3d_analysis(prob, metrics, table)
        else:
            analyse(name, prob, metrics, table)
    loads = [x for p in problems.values() for rows in p["series"].values() for r in rows
             for x in r.get("loadavg_1min", [])]
    png = plot(ctx, problems, table, load_description(loads))
    md = markdown_table(table)
    (ctx.outdir / "table.md").write_text(md + "\n")
    capped = [f"{name} {label} {r.get('n', r.get('N'))}: {r['pressure_cap_rows']} of "
              f"{r['diagnostic_rows']} diagnostic rows"
              for name, p in problems.items() for label, rows in p["series"].items()
              for r in rows if r.get("pressure_cap_rows")]
    metrics["loadavg_1min_median"] = float(np.median(loads)) if loads else None
    notes = (
        f"Timings: {load_description(loads)} (1-minute load average before each run, which "
        "counts the study's own previous runs: range "
        f"{f'{min(loads):.1f}-{max(loads):.1f}' if loads else '-'}; recorded per run in the "
        "tables). 'wall' is the "
        "whole process measured here (minimum of 2 repeats for runs shorter than "
        f"{SHORT_RUN:g} s; it includes Python/dolfinx import, about 1-2 s, for the FE "
        "scripts and mpirun start-up for 2 ranks); 'solver' is the code's own timer. Under "
        "load, 2-rank runs on 2 cores compete with the other jobs, so their speedups are "
        "lower bounds of what an idle machine gives. Equal error: log-log interpolation between "
        "the two runs bracketing the target, the target the geometric middle of the error "
        "range both solvers reach; no extrapolation. flow_mms: efsi's error is the RMS of "
        "its face velocities against the exact field (periodic box), the FE's the L2 norm / "
        "L (its Dirichlet/traction box; the FE nodal RMS is in the tables as "
        "error_nodes_rms). parallel_slab: the FE is a 1D code, efsi solves the same problem "
        "on a 4 x n x 1 grid (2 ranks split the 4 cells in x). capsule_2d: the error against "
        "the unbounded Re = 0 boundary integral contains the wall confinement (Ly = 4d) and "
        "Re = 0.01 of both Eulerian codes, so it has a floor that is not discretisation "
        "error. capsule_3d: efsi times are the solver timers of the capsule_shear study's "
        "cached runs (1 rank) and of the d/8 runs made here; the FE 3D figure is the one "
        "measured by the stored full tier of reference_vesicle. VOF: there is no FE VOF in "
        "reference/.")
    if capped:
        notes += (" PRESSURE SOLVE AT ITS ITERATION CAP (" + str(PRESSURE_CAP) + ") in efsi "
                  "runs (their time is dominated by unconverged pressure solves, so they are "
                  "slower than the method needs to be): " + "; ".join(capped) + ".")
    return {"metrics": metrics, "tables": {"equal_error": table, "pressure_cap": capped, "runs": {
        k: v["series"] for k, v in problems.items()}, "markdown": md,
        "references": {k: v.get("reference") for k, v in problems.items() if v.get("reference")},
        "capsule_3d_skipped": problems.get("capsule_3d", {}).get("skipped_cached_runs")},
        "figures": [str(png)], "notes": notes + "\n\n" + md}
