"""Blood in a capillary (issue 20, section 4; seed paper section 3.2, Figs. 2-3).

Three runs of the coarse capillary (44 x 22 x 22 um at 128 x 64 x 64, h = 0.34375 um, until
session 46 at 64 x 32 x 32; a 20 um tube along x, 400 kPa/m; units um, ms, mPa s, uN/m), the
same grid, wall, plasma and driving:
- `capillary_coarse`: red cells seeded to Ht 20 % and 4 platelets (seed 2026);
- `capillary_no_rbc`: the 4 platelets alone (Ht 0; the paper's Fig. 3a);
- plasma alone (no cells: `capillary_no_rbc` without its [seeding]), for the flow rate the
  apparent viscosity is measured against.
The platelets of the two seeded runs start at different places (the red cells' shake moves
them); their statistics are compared, not their paths.

Metrics (result.json):
- `achieved_ht`: red-cell volume / lumen volume placed by the seeding (summary.json);
- `relative_apparent_viscosity`: Q_plasma / Q_cells, the plasma-alone flow rate over the flow
  rate with cells at the same pressure gradient (Q = the x-face velocities summed over a
  cross-section times dy dz, averaged over the x faces and the snapshots of the second half
  of the run). Next to it the in-vitro fit of Pries, Neuhaus & Gaehtgens (Am J Physiol 263
  (1992) H1770) at D = 20 um for the discharge haematocrit H_D that gives the tube
  haematocrit achieved (Fahraeus effect, the same paper's fit H_T / H_D = H_D + (1 - H_D)
  (1 + 1.7 e^(-0.35 D) - 0.6 e^(-0.01 D))): `relative_apparent_viscosity_pries1992` and the
  difference `relative_apparent_viscosity_minus_pries1992` (reported; no bound: the coarse
  grid resolves a red cell's dimple by about one cell, docs/method.md);
- `cell_free_layer_um`: R minus the mean, over the snapshots of the second half, the x
  columns of cells and 16 angular sectors, of the largest radius (cell centre) where the red
  cells' phi summed over cells exceeds 1/2 (columns and sectors with no red cell left out);
  next to it the published widths of CELL_FREE_LAYER_PUBLISHED (in-vivo arterioles at a
  systemic Ht of 20 %; no in-vitro or simulated width at D = 20 um and Ht 0.2 was found in
  the sources searched) as `cell_free_layer_minus_<key>_um` (reported; no bound: in-vivo
  vessels are 20-40 um wide, carry an endothelial surface layer, and their Ht is the
  systemic one, above the tube Ht of a 20 um tube by the Fahraeus effect);
- `platelet_radial_rms_fluctuation_with_rbc_um` and `..._without_rbc_um`: per platelet the
  rms of its centroid's radial position about its mean over the second half of the run,
  then the rms over the platelets (the paper's Fig. 3: the red cells agitate the platelets);
- `max_body_overlap`: max over the snapshots and over every pair of bodies (the wall
  included) of sum max(0, phi_i + phi_j - 1) dV / min(V_i, V_j), each smoothed body (the red
  cells) entering as its sharp equivalent (its phi = 1/2 surface, `sharp_fraction`);
  `body_overlap_at_start` the same in the seeded scene (the first snapshot, t = 0);
  `max_body_overlap_profiles` the same with the smoothed bodies' stored tanh profiles
  (reported, no bound: a smoothed body's tail reaches into a sharp neighbour at any gap;
  docs/method.md, "Body overlap measure");
- `volume_drift_max`: max over the moving bodies of |V(t_end) / V(0) - 1| (bodies.csv);
- `rbc_reference_area_drift_max`: max over the red cells and the diagnostics rows of
  |A_ref / A - 1|, A_ref the area their stored strain implies, A the measured area;
- `t_end_ms_<run>`, `reached_end_<run>`: the time each run reached and whether it was the
  asked end (a run that stops UNSTABLE is measured up to there and breaks the bound);
- `seconds_per_ms_physical`: wall seconds of the run with cells per ms of physical time,
  with `ranks` and the load in the table; `seconds_per_ms_physical_2ranks`: the same scene on
  two ranks over its first TWO_RANK_MS (quick and full tiers; set-up included in both);
- `rate_*` (runs on one rank only): the bytes and seconds per cell and per body patch cell
  that `efsi check` estimates a run's memory and cost with (estimate_rates below;
  solver/simulation/run_estimate.cpp holds them, docs/performance.md shows them).

A fourth run, `rbc_in_tube` (one red cell in a 10 um tube, 24 um periodic: a file of cells
24 um apart; issue 20 section 3), measures the single cell:
- `rbc_in_tube_velocity_ratio`: the cell's velocity (its centroid's, least squares over the
  last quarter of the run) over the mean velocity of the suspension (flow rate / lumen area,
  the snapshots of the last quarter); next to it `rbc_in_tube_velocity_ratio_pries1992`,
  H_D / H_T from the Fahraeus fit above at D = 10 um for the tube haematocrit of the run
  (cell volume / lumen volume: in steady flow the cells' flux H_D Q equals H_T A v_cell, so
  v_cell / v_mean = H_D / H_T), and their difference (reported; no bound: the fit is for
  suspensions in glass tubes, this is a periodic file of single cells);
- `rbc_in_tube_length_um`, `rbc_in_tube_diameter_um`: the cell's extent along the axis and
  twice its largest distance from the axis where its phi >= 1/2 (last snapshot);
- `rbc_in_tube_reference_area_drift_max` (bound 5 %, as for the capillary's cells),
  `rbc_in_tube_max_trace_Gs`, `rbc_in_tube_area_change_max` (|A / A(0) - 1|),
  `rbc_in_tube_volume_drift`, `t_end_ms_tube`, `reached_end_tube`.

Tiers: ci 3 steps of each run on 64 x 32 x 32 at Ht 3 % with a gap of one cell (the
machinery, overlap and volume only; a flow 3 steps old has no flow rate worth comparing);
quick to 0.5 ms and full to 3 ms at the case's Ht 20 % on its grid, on EFSI_VERIFY_RANKS
ranks; the tube to 2 ms (quick) and 10 ms (full).
"""
import csv
import glob
import json
import math
from pathlib import Path

import h5py
import numpy as np

from _blood_references import (CELL_FREE_LAYER_PUBLISHED,  # noqa: F401 (records, tests)
                               cell_free_layer_comparison, pries_1992)
from _bounds import Bound
from _flowio import body_series, cached_run
from _overlap import overlap, sharp_fraction, smoothing_widths, worst_pair  # noqa: F401 (records)

DESCRIPTION = "blood in a capillary: Ht, apparent viscosity, cell-free layer, platelets, overlap"

# Physical time [ms] of the two-rank timing run (quick and full tiers).
TWO_RANK_MS = 0.5
TIERS = {"ci": {"steps": 3, "t_end": None, "fields": 0, "tube_end": None},
         "quick": {"steps": None, "t_end": 0.5, "fields": 0.125, "tube_end": 2.0},
         "full": {"steps": None, "t_end": 3.0, "fields": 0.25, "tube_end": 10.0}}
_QF = ("quick", "full")
BOUNDS = [
    Bound(r"max_body_overlap", "<=", 1e-3,
          "no two bodies' volume fractions overlap by more than 1e-3 of the smaller one"),
    Bound(r"volume_drift_max", "<=", 1e-9, "every body keeps its volume"),
    Bound(r"rbc_reference_area_drift_max", "<=", 0.05,
          "the red cells' stored strain stays consistent with their surface (its area within "
          "5 % of the measured one)", tiers=_QF),
    Bound(r"rbc_in_tube_reference_area_drift_max", "<=", 0.05,
          "the single red cell's stored strain stays consistent with its surface", tiers=_QF),
    Bound(r"rbc_in_tube_volume_drift", "<=", 1e-9, "the single red cell keeps its volume"),
    Bound(r"achieved_ht", ">=", 0.19, "the seeding reaches the paper's Ht of about 20 %",
          tiers=_QF),
    Bound(r"reached_end_.*", "==", 1, "every run reaches its end time (no UNSTABLE stop)",
          tiers=_QF),
    Bound(r"relative_apparent_viscosity$", ">=", 1.0,
          "red cells raise the apparent viscosity", tiers=_QF),
]

R_LUMEN, AXIS_Y, AXIS_Z = 10.0, 11.0, 11.0  # um (cases/capillary_coarse)
BOX_X = 44.0  # um, the box's length along the vessel (cases/capillary_coarse)
# The ci tier's grid, an eighth of the case's cells (h = 0.6875 um), and a gap of one cell
# there; the quick and full tiers also run the plasma alone on it (estimate_rates).
CI_GRID, CI_GAP = "[64, 32, 32]", "0.6875"

DIAMETER = 2 * R_LUMEN
TUBE_R, TUBE_AXIS, TUBE_LENGTH = 5.0, 6.0, 24.0  # um (cases/rbc_in_tube)


def plasma_case(ctx) -> Path:
    """capillary_no_rbc without its [seeding]: the wall alone."""
    text = (ctx.repo / "cases" / "capillary_no_rbc" / "case.toml").read_text()
    text = text[:text.index("[seeding]")] + text[text.index("[output]"):]
    text = text.replace('name = "capillary_no_rbc"', 'name = "capillary_plasma"')
    path = ctx.outdir / "capillary_plasma.toml"
    path.write_text(text)
    return path


def bodies(out: Path) -> dict:
    with open(out / "bodies.csv") as f:
        rows = list(csv.DictReader(f))
    per = {}
    for r in rows:
        per.setdefault(r["body"], []).append(r)
    return per


def snapshots(out: Path) -> list[Path]:
    return sorted(glob.glob(str(out / "fields" / "fields_*.h5")))


def snapshot_time(path) -> float:
    with h5py.File(path, "r") as f:
        return float(f.attrs.get("time", np.nan))


def flow_rate(path, h: float) -> float:
    with h5py.File(path, "r") as f:
        u = f["faces_u"][...]  # [z][y][x]
    return float(u.sum(axis=(0, 1)).mean() * h * h)


def radial_grid(shape, h):
    nz, ny, nx = shape
    zz, yy = np.meshgrid((np.arange(nz) + 0.5) * h, (np.arange(ny) + 0.5) * h, indexing="ij")
    return np.hypot(yy - AXIS_Y, zz - AXIS_Z), np.arctan2(zz - AXIS_Z, yy - AXIS_Y)


def rbc_edge_radii(path, h, sectors=16) -> list[float]:
    """Per x column and angular sector, the largest radius where the red cells fill half."""
    with h5py.File(path, "r") as f:
        names = [k for k in f.keys() if k.startswith("phi_rbc")]
        if not names:
            return []
        shape = f["faces_u"].shape  # [z][y][x]; phi is stored flat in the same order
        rbc = sum(f[k][...].reshape(shape) for k in names)
    r, th = radial_grid(rbc.shape, h)
    sec = ((th + np.pi) / (2 * np.pi) * sectors).astype(int) % sectors
    out = []
    for i in range(rbc.shape[2]):
        full = rbc[:, :, i] > 0.5
        for s in range(sectors):
            m = full & (sec == s)
            if m.any():
                out.append(float(r[m].max()))
    return out


def radial_profiles(path, h, bins):
    """u_x and the red cells' phi averaged over x and angle, per radial bin."""
    with h5py.File(path, "r") as f:
        u = f["faces_u"][...]
        rbc = sum((f[k][...].reshape(u.shape) for k in f.keys() if k.startswith("phi_rbc")),
                  np.zeros(u.shape))
    r, _ = radial_grid(u.shape, h)
    idx = np.digitize(r, bins) - 1
    um, pm = np.full(len(bins) - 1, np.nan), np.full(len(bins) - 1, np.nan)
    ux, px = u.mean(axis=2), rbc.mean(axis=2)
    for b in range(len(bins) - 1):
        m = idx == b
        if m.any():
            um[b], pm[b] = ux[m].mean(), px[m].mean()
    return um, pm


def platelet_radii(per: dict):
    out = {}
    for name, rows in per.items():
        if name.startswith("platelet"):
            t = np.array([float(r["time"]) for r in rows])
            y = np.array([float(r["centroid_y"]) for r in rows])
            z = np.array([float(r["centroid_z"]) for r in rows])
            o = np.argsort(t, kind="stable")
            out[name] = (t[o], np.hypot(y[o] - AXIS_Y, z[o] - AXIS_Z))
    return out


def rms_fluctuation(radii: dict, t_from: float) -> float:
    per = []
    for t, r in radii.values():
        m = t >= t_from
        if m.sum() >= 2:
            per.append(float(np.sqrt(np.mean((r[m] - r[m].mean()) ** 2))))
    return float(np.sqrt(np.mean(np.square(per)))) if per else float("nan")


def volume_drift(per: dict) -> float:
    worst = 0.0
    for name, rows in per.items():
        if name == "wall":
            continue
        v0, v1 = float(rows[0]["volume"]), float(rows[-1]["volume"])
        worst = max(worst, abs(v1 / v0 - 1))
    return worst


def reference_area_drift(per: dict) -> float:
    """Max over the red cells and the rows of |A_ref / A - 1|: A_ref is the area the stored
    strain implies (bodies.csv reference_area), A the measured one. 0 while the strain
    stays consistent with the surface it sits on (docs/method.md, "The reference map")."""
    worst = 0.0
    for name, rows in per.items():
        if not name.startswith("rbc"):
            continue
        for r in rows:
            a, a_ref = float(r["area"]), float(r["reference_area"])
            if a > 0 and a_ref > 0:
                worst = max(worst, abs(a_ref / a - 1))
    return worst


def tube_shape(path, h) -> tuple[float, float]:
    """The single red cell's length along the axis and its diameter (twice the largest
    distance from the axis) where its phi >= 1/2; the cell may straddle the periodic end."""
    with h5py.File(path, "r") as f:
        shape = f["faces_u"].shape  # [z][y][x]
        phi = f["phi_rbc"][...].reshape(shape)
    inside = phi >= 0.5
    cols = inside.any(axis=(0, 1))
    if not cols.any():
        return float("nan"), float("nan")
    # Roll an empty column to the front so the cell's columns are contiguous.
    empty = np.flatnonzero(~cols)
    cols = np.roll(cols, -int(empty[0])) if len(empty) else cols
    idx = np.flatnonzero(cols)
    length = (idx[-1] - idx[0] + 1) * h
    nz, ny, _ = shape
    zz, yy = np.meshgrid((np.arange(nz) + 0.5) * h, (np.arange(ny) + 0.5) * h, indexing="ij")
    r = np.hypot(yy - TUBE_AXIS, zz - TUBE_AXIS)
    return float(length), float(2 * r[inside.any(axis=2)].max())


def tube_metrics(out: Path, summary: dict, h: float) -> tuple[dict, dict]:
    """Metrics of the single red cell in the 10 um tube (docstring above), and the series
    the plot shows."""
    keys = ("centroid_x", "volume", "area", "reference_area", "tensor_trace_max")
    t, *values = body_series(out, "rbc", keys)
    col = dict(zip(keys, values))
    x = np.unwrap(col["centroid_x"], period=TUBE_LENGTH)
    t_end = float(summary["time"])
    m = {"t_end_ms_tube": t_end, "reached_end_tube": int(summary["status"] == "completed"),
         "rbc_in_tube_volume_drift": abs(col["volume"][-1] / col["volume"][0] - 1),
         "rbc_in_tube_area_change_max": float(np.max(np.abs(col["area"] / col["area"][0] - 1))),
         "rbc_in_tube_max_trace_Gs": float(col["tensor_trace_max"].max())}
    ok = (col["area"] > 0) & (col["reference_area"] > 0)
    m["rbc_in_tube_reference_area_drift_max"] = float(
        np.max(np.abs(col["reference_area"][ok] / col["area"][ok] - 1)))
    series = {"t": t, "x": x, "drift": col["reference_area"] / col["area"] - 1,
              "area": col["area"] / col["area"][0] - 1}
    snaps = snapshots(out)
    late = [p for p in snaps if snapshot_time(p) >= 0.75 * t_end - 1e-9]
    last = t >= 0.75 * t_end
    if late and last.sum() >= 2 and t_end > 0:
        v_cell = float(np.polyfit(t[last], x[last], 1)[0])
        v_mean = float(np.mean([flow_rate(p, h) for p in late])) / (math.pi * TUBE_R ** 2)
        tube_ht = col["volume"][0] / (math.pi * TUBE_R ** 2 * TUBE_LENGTH)
        _, hd = pries_1992(tube_ht, 2 * TUBE_R)
        m["rbc_in_tube_tube_haematocrit"] = float(tube_ht)
        m["rbc_in_tube_cell_velocity_um_per_ms"] = v_cell
        m["rbc_in_tube_mean_velocity_um_per_ms"] = v_mean
        m["rbc_in_tube_velocity_ratio"] = v_cell / v_mean
        m["rbc_in_tube_velocity_ratio_pries1992"] = hd / tube_ht
        m["rbc_in_tube_velocity_ratio_minus_pries1992"] = v_cell / v_mean - hd / tube_ht
        length, diameter = tube_shape(snaps[-1], h)
        m["rbc_in_tube_length_um"], m["rbc_in_tube_diameter_um"] = length, diameter
        series["first"], series["last"] = snaps[0], snaps[-1]
    return m, series


def plot_tube(ctx, series, h) -> list[str]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(14, 3.8))
    t, x = series["t"], series["x"]
    v = np.gradient(x, t) if len(t) > 2 else np.zeros_like(t)
    ax[0].plot(t, v)
    ax[0].set_xlabel("t [ms]")
    ax[0].set_ylabel("cell velocity [um/ms]")
    ax[0].set_title("red cell in a 10 um tube: velocity")
    ax[1].plot(t, 100 * series["drift"], label="A_ref / A - 1 (bound: 5 %)")
    ax[1].plot(t, 100 * series["area"], label="A / A(0) - 1")
    ax[1].axhline(5, color="k", lw=0.8, ls="--")
    ax[1].axhline(-5, color="k", lw=0.8, ls="--")
    ax[1].set_xlabel("t [ms]")
    ax[1].set_ylabel("[%]")
    ax[1].set_title("area, and the stored strain against it")
    ax[1].legend(fontsize=7)
    for key, style in (("first", "C0"), ("last", "C3")):
        if key in series:
            with h5py.File(series[key], "r") as f:
                shape = f["faces_u"].shape
                phi = f["phi_rbc"][...].reshape(shape)
                tt = float(f.attrs.get("time", np.nan))
            k = int(TUBE_AXIS / h)  # the cell row just above the axis: the y-x section
            sec = phi[k]
            ext = [0, shape[2] * h, 0, shape[1] * h]
            ax[2].contour(sec, levels=[0.5], colors=style, extent=ext)
            ax[2].plot([], [], color=style, label=f"t = {tt:.1f} ms")
    if "first" in series:
        ax[2].legend(fontsize=7)
    ax[2].axhline(TUBE_AXIS - TUBE_R, color="k", lw=0.8)
    ax[2].axhline(TUBE_AXIS + TUBE_R, color="k", lw=0.8)
    ax[2].set_aspect("equal")
    ax[2].set_xlabel("x [um]")
    ax[2].set_ylabel("y [um]")
    ax[2].set_title("phi = 1/2 in the plane z ~ axis")
    fig.tight_layout()
    png = ctx.outdir / "rbc_in_tube.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return [str(png)]


FLOW_STAGES = ("advection", "predictor", "viscous_solve", "pressure_solve", "correction", "halo")


def _body_seconds(s: dict) -> float:
    return sum(v for k, v in s["stages"].items()
               if k.startswith("bodies") or k in ("body_stress", "diagnostics"))


def _patch(s: dict, prefix: str) -> float:
    return float(sum(b["patch_cells"] for b in s.get("bodies", []) if b["name"].startswith(prefix)))


def estimate_rates(summary: dict) -> dict:
    """The rates `efsi check` turns a case into memory and time with
    (solver/simulation/run_estimate.cpp), measured on these runs (one rank):
    - the flow with hypre's viscous solve: the plasma run's flow stages per cell and step;
      its bytes per cell and the process's base memory: the slope and intercept of peak RSS
      against cells through the plasma run and the same on the ci tier's grid
      (`plasma_coarse`, an eighth of the cells): hypre's matrices and PFMG levels grow
      with the cells, so one run cannot part them from the base (the slope holds the pinned
      wall's own fields, which the estimate also counts as held patch cells: ~1 % more);
    - the flow with FFT solves, bytes per cell: the throughput study's 128^3 run;
    - a solid's patch cell: the platelets-alone run's body stages per platelet patch cell and
      step, and its peak RSS above the plasma run's per platelet patch cell;
    - a membrane's patch cell: the same between the run with red cells and the platelets
      alone (the platelets' share removed with the solid rate).
    The copies of the velocity and the force across the periodic x seam (bodies/body_seam.cpp)
    are the size of the grid, not of the patches: `efsi check` counts them on their own
    (run_estimate.cpp, seam_copy_bytes), so each run's own (summary.json
    `seam_copy_bytes_max_rank`) is taken out of its peak RSS before the patches' bytes are
    derived. Runs made before that key existed (session 57) have none to take out."""
    if any(s.get("ranks", 1) != 1 for s in summary.values()):
        return {}
    pl, sol, cel = summary["plasma"], summary["platelets"], summary["cells"]
    cells = float(pl["cells"])
    out = {"rate_flow_seconds_per_cell_step_hypre":
           sum(pl["stages"].get(k, 0.0) for k in FLOW_STAGES) / pl["steps"] / cells}
    plc = summary.get("plasma_coarse")
    if plc is not None and float(plc["cells"]) != cells:
        slope = ((pl["peak_rss_bytes_max_rank"] - plc["peak_rss_bytes_max_rank"])
                 / (cells - float(plc["cells"])))
        out["rate_flow_bytes_per_cell_hypre"] = slope
        out["rate_process_base_bytes"] = pl["peak_rss_bytes_max_rank"] - slope * cells
    tp = Path(__file__).resolve().parents[1] / "results" / "throughput" / "result.json"
    if tp.exists():
        out["rate_flow_bytes_per_cell"] = json.loads(tp.read_text())["metrics"]["bytes_per_cell"]
    def rss(s: dict) -> float:
        return s["peak_rss_bytes_max_rank"] - max(0.0, s.get("seam_copy_bytes_max_rank", 0.0))

    p_sol = _patch(sol, "platelet")
    out["rate_solid_seconds_per_patch_cell_step"] = _body_seconds(sol) / sol["steps"] / p_sol
    out["rate_solid_bytes_per_patch_cell"] = (rss(sol) - rss(pl)) / p_sol
    for key, s in (("platelets", sol), ("cells", cel)):
        if "seam_copy_bytes_max_rank" in s:
            out[f"seam_copy_bytes_{key}"] = float(s["seam_copy_bytes_max_rank"])
    p_mem, p_sol_c = _patch(cel, "rbc"), _patch(cel, "platelet")
    if p_mem > 0:
        solid_share = out["rate_solid_seconds_per_patch_cell_step"] * p_sol_c
        out["rate_membrane_seconds_per_patch_cell_step"] = (
            (_body_seconds(cel) / cel["steps"] - solid_share) / p_mem)
        out["rate_membrane_bytes_per_patch_cell"] = (
            (rss(cel) - rss(sol) - out["rate_solid_bytes_per_patch_cell"] * (p_sol_c - p_sol))
            / p_mem)
    return out


def run(ctx):
    tier = TIERS[ctx.tier]
    sets = {"output.progress_every": "100000", "output.checkpoint_every": "100"}
    cell_sets = {}
    if tier["steps"] is not None:
        sets["time.max_steps"] = str(tier["steps"])
        sets["output.fields_interval"] = "0"
        # The ci tier checks the machinery on the sparse scene (Ht 3 %, a gap of one cell) on
        # a grid of 64 x 32 x 32 (h = 0.6875 um), an eighth of the case's cells: there a gap
        # of one cell packs only 15.7 % (docs/method.md).
        cell_sets = {"seeding.target_haematocrit": "0.03", "seeding.gap": CI_GAP}
        sets["grid.cells"] = CI_GRID
    else:
        sets["time.end_time"] = repr(tier["t_end"])
        sets["output.fields_interval"] = repr(tier["fields"])
    runs = {"cells": ctx.repo / "cases" / "capillary_coarse",
            "platelets": ctx.repo / "cases" / "capillary_no_rbc",
            "plasma": plasma_case(ctx)}
    out, summary = {}, {}
    # One folder per tier: the ci tier's few steps must not overwrite the full tier's runs,
    # which are kept and measured again rather than rerun.
    run_dir = ctx.outdir / "runs" / ctx.tier
    for key, case in runs.items():
        out[key] = run_dir / key
        extra = cell_sets if key == "cells" else {}
        # A finished run is measured again, not rerun (the full tier's takes most of an hour).
        if tier["t_end"] is None:  # ci: a few steps (status max_steps), always rerun
            ctx.run_efsi(case, out[key], sets={**sets, **extra}, ranks=ctx.long_ranks)
        else:
            # A run that stops UNSTABLE is a result: measured up to where it stopped.
            cached_run(ctx, case, out[key], {**sets, **extra}, tier["t_end"],
                       ranks=ctx.long_ranks, allow_unstable=True)
        summary[key] = json.loads((out[key] / "summary.json").read_text())
    # The plasma alone on the ci tier's grid too (quick and full tiers, whose runs are on
    # the case's): with the run above, the flow's bytes per cell under hypre
    # (estimate_rates). An eighth of the cells, to the same end.
    if tier["t_end"] is not None:
        out["plasma_coarse"] = run_dir / "plasma_coarse"
        cached_run(ctx, runs["plasma"], out["plasma_coarse"],
                   {**sets, "grid.cells": CI_GRID}, tier["t_end"],
                   ranks=ctx.long_ranks, allow_unstable=True)
        summary["plasma_coarse"] = json.loads((out["plasma_coarse"] / "summary.json").read_text())
    # The cost on two ranks (issue 20 asks for it): the scene with cells over its first
    # TWO_RANK_MS, its own cached run (the study's other runs keep EFSI_VERIFY_RANKS ranks).
    if tier["t_end"] is not None:
        out["cells_2ranks"] = run_dir / "cells_2ranks"
        cached_run(ctx, runs["cells"], out["cells_2ranks"],
                   {**sets, "time.end_time": repr(TWO_RANK_MS), "output.fields_interval": "0"},
                   TWO_RANK_MS, ranks=2, allow_unstable=True)
        summary["cells_2ranks"] = json.loads((out["cells_2ranks"] / "summary.json").read_text())
    tube_out = run_dir / "tube"
    tube_case = ctx.repo / "cases" / "rbc_in_tube"
    if tier["tube_end"] is None:
        ctx.run_efsi(tube_case, tube_out, sets=sets, ranks=ctx.long_ranks)
    else:
        cached_run(ctx, tube_case, tube_out,
                   {**sets, "time.end_time": repr(tier["tube_end"]),
                    "output.fields_interval": "0.5"},
                   tier["tube_end"], ranks=ctx.long_ranks, allow_unstable=True)
    tube_summary = json.loads((tube_out / "summary.json").read_text())
    h = BOX_X / int(summary["cells"]["grid"][0])
    t_end = float(summary["cells"]["time"])
    half = 0.5 * t_end
    metrics = {"achieved_ht": float(summary["cells"]["seeding"]["achieved_haematocrit"])}
    if tier["t_end"] is not None:
        for k in runs:
            metrics[f"t_end_ms_{k}"] = float(summary[k]["time"])
            metrics[f"reached_end_{k}"] = int(summary[k]["status"] == "completed")
    per = {k: bodies(out[k]) for k in ("cells", "platelets")}
    metrics["volume_drift_max"] = max(volume_drift(per["cells"]), volume_drift(per["platelets"]))
    metrics["rbc_reference_area_drift_max"] = reference_area_drift(per["cells"])
    snaps = {k: snapshots(out[k]) for k in runs}
    widths = {k: smoothing_widths(out[k]) for k in ("cells", "platelets")}
    metrics["max_body_overlap"] = max(overlap(p, widths[k]) for k in ("cells", "platelets")
                                      for p in snaps[k])
    metrics["body_overlap_at_start"] = max(overlap(snaps[k][0], widths[k])
                                           for k in ("cells", "platelets") if snaps[k])
    metrics["max_body_overlap_profiles"] = max(overlap(p) for k in ("cells", "platelets")
                                               for p in snaps[k])
    metrics["seconds_per_ms_physical"] = float(summary["cells"]["wall_seconds"]) / t_end
    if "cells_2ranks" in summary:
        s2 = summary["cells_2ranks"]
        metrics["seconds_per_ms_physical_2ranks"] = float(s2["wall_seconds"]) / float(s2["time"])
    late = {k: [p for p in snaps[k] if snapshot_time(p) >= half - 1e-9] or snaps[k][-1:]
            for k in runs}
    q = {k: float(np.mean([flow_rate(p, h) for p in late[k]])) for k in runs}
    metrics["relative_apparent_viscosity"] = q["plasma"] / q["cells"]
    metrics["relative_apparent_viscosity_no_rbc"] = q["plasma"] / q["platelets"]
    pries, hd = pries_1992(metrics["achieved_ht"], DIAMETER)
    metrics["relative_apparent_viscosity_pries1992"] = pries
    metrics["relative_apparent_viscosity_minus_pries1992"] = (
        metrics["relative_apparent_viscosity"] - pries)
    edges = [r for p in late["cells"] for r in rbc_edge_radii(p, h)]
    metrics["cell_free_layer_um"] = R_LUMEN - float(np.mean(edges)) if edges else float("nan")
    metrics.update(cell_free_layer_comparison(metrics["cell_free_layer_um"]))
    radii = {k: platelet_radii(per[k]) for k in per}
    metrics["platelet_radial_rms_fluctuation_with_rbc_um"] = rms_fluctuation(radii["cells"], half)
    metrics["platelet_radial_rms_fluctuation_without_rbc_um"] = rms_fluctuation(
        radii["platelets"], half)
    rows = [{"run": k, "t_end [ms]": float(summary[k]["time"]), "status": summary[k]["status"],
             "steps": summary[k]["steps"], "ranks": summary[k]["ranks"],
             "wall [s]": round(float(summary[k]["wall_seconds"]), 1),
             "load before": summary[k].get("load_before"),
             "flow rate [um^3/ms]": round(q[k], 2) if k in q else "-",
             "bodies": len(summary[k].get("bodies", []))} for k in summary]
    metrics.update(estimate_rates({k: summary[k] for k in summary if k != "cells_2ranks"}))
    h_tube = TUBE_LENGTH / int(tube_summary["grid"][0])
    tube, tube_series = tube_metrics(tube_out, tube_summary, h_tube)
    if tier["tube_end"] is None:  # ci: the machinery only
        tube = {k: v for k, v in tube.items() if k.startswith("rbc_in_tube_volume")}
    metrics.update(tube)
    rows.append({"run": "tube", "t_end [ms]": float(tube_summary["time"]),
                 "status": tube_summary["status"], "steps": tube_summary["steps"],
                 "ranks": tube_summary["ranks"],
                 "wall [s]": round(float(tube_summary["wall_seconds"]), 1),
                 "load before": tube_summary.get("load_before"), "bodies": 2})
    # Statistics a run too short to have (the ci tier's 3 steps) are left out, not NaN.
    metrics = {k: v for k, v in metrics.items() if np.isfinite(v)}
    figures = plot(ctx, radii, late, h, q) + plot_tube(ctx, tube_series, h_tube)
    notes = (f"Pries et al. 1992 at D = 20 um: tube Ht {metrics['achieved_ht']:.4f} is a "
             f"discharge Ht of {hd:.4f}, relative apparent viscosity {pries:.3f}. "
             "Cell-free layer beside the published in-vivo widths at a systemic Ht of 20 % "
             "(um): " + ", ".join(f"{k} {v:g}" for k, v in CELL_FREE_LAYER_PUBLISHED.items()) +
             " (the sources in CELL_FREE_LAYER_PUBLISHED, verification/studies/"
             "_blood_references.py).")
    return {"metrics": metrics, "tables": {"runs": rows}, "figures": figures, "notes": notes}


def plot(ctx, radii, late, h, q) -> list[str]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for a, key, title in ((ax[0], "platelets", "without red cells"),
                          (ax[1], "cells", "with red cells (Ht 20 %)")):
        for name, (t, r) in sorted(radii[key].items()):
            a.plot(t, r, label=name)
        a.set_title(f"platelets' radial position, {title}")
        a.set_xlabel("t [ms]")
        a.axhline(R_LUMEN, color="k", lw=0.8)
    ax[0].set_ylabel("r [um]")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    png1 = ctx.outdir / "platelet_radial_position.png"
    fig.savefig(png1, dpi=110)
    plt.close(fig)

    bins = np.linspace(0, R_LUMEN + 1, 16)
    mid = 0.5 * (bins[1:] + bins[:-1])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for key, label in (("plasma", "plasma"), ("platelets", "platelets only"),
                       ("cells", "red cells, Ht 20 %")):
        prof = np.nanmean([radial_profiles(p, h, bins)[0] for p in late[key]], axis=0)
        ax[0].plot(mid, prof, "o-", label=f"{label} (Q = {q[key]:.0f} um^3/ms)")
    ax[0].set_xlabel("r [um]")
    ax[0].set_ylabel("u_x [um/ms]")
    ax[0].set_title("velocity profile (second half, x and angle mean)")
    ax[0].legend(fontsize=7)
    phi = np.nanmean([radial_profiles(p, h, bins)[1] for p in late["cells"]], axis=0)
    ax[1].plot(mid, phi, "o-", color="C3", label="red cells' volume fraction")
    for key, style in (("cells", "C1"), ("platelets", "C0")):
        rs = np.concatenate([r for _, r in radii[key].values()]) if radii[key] else []
        if len(rs):
            hist, _ = np.histogram(rs, bins=bins, density=True)
            ax[1].step(mid, hist, where="mid", color=style,
                       label=f"platelet centroids, {'with' if key == 'cells' else 'without'} RBC")
    ax[1].set_xlabel("r [um]")
    ax[1].set_title("radial distributions")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    png2 = ctx.outdir / "radial_profiles.png"
    fig.savefig(png2, dpi=110)
    plt.close(fig)
    return [str(png1), str(png2)]
