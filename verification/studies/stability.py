"""Stability stress test: fixed dt as a multiple k of the automatic dt.

For the 2D capsule in shear (cases/capsule_shear_2d, several Ca) and the stiff solid slab
(cases/parallel_slab with shear_modulus = 100) the study first runs with the automatic
(adaptive) dt and takes the typical dt it used (median of the diagnostics.csv dt column),
then reruns with a fixed `time.dt = k x dt_auto` for each k of the tier. Per run it records
the status (completed / unstable), the step and time where it stopped, the instability
message, whether any written field snapshot (and the checkpoint) holds a non-finite value,
and for completed runs the max speed over the run.

Metrics: stable_margin_capsule_ca<Ca> and stable_margin_slab (largest k such that every
k' <= k completed; a lower bound when the largest k tried completed, flagged by
*_is_lower_bound = 1), stable_margin_capsule (the smallest over Ca),
unstable_runs_with_nan_fields (unstable runs that wrote a non-finite field; must be 0),
nonfinite_field_runs (any run), a capsule Re sweep (fluid.density = Re, k = 1 and 2) and
a resolution sweep (capsule Ca 0.2 at several cells per diameter, the same k list:
stable_margin_capsule_n<cells>).

Long run: the 3D capsule (cases/capsule_shear, Ca 0.2; d/8 in quick, d/16 in full) with
the automatic dt to shear-rate x t = 10, a steady tank-treading state; its volume and area
drift over the run (capsule_volume_drift_t10, capsule_area_drift_t10; the area is the
integral of |grad phi| and changes physically as the membrane stretches, so its drift is
reported from t = 2 on, when D has settled) and D at the end. In the full tier it is run
twice: with the default reach of the surface velocity (5 cells) and with 1.5, the remedy
docs/method.md gives for the growth of Gs. A long run that stops UNSTABLE (for instance on
stability.max_tensor_trace) is a result: its row says where it stopped, its drift is the
drift up to there (capsule_long_run_unstable_at_t), and capsule_volume_drift_t10 is taken
from a run with the default reach only if it reached t = 10 (otherwise from the reach-1.5 run,
named so: capsule_volume_drift_t10_reach1.5).

Capsule Ca values: at 0.002 the membrane's own limit sets the automatic dt and k probes it;
at 0.05 and 0.2 (box 4d, wall speed 4 a x shear rate) the VOF face Courant limit binds first
and k = 8 / k = 2 are refused by it at the first step.

A capsule whose run with the automatic dt itself stops UNSTABLE has no margin: the row
says where (unstable_with_automatic_dt_at_t_<tag>), and the sweep is repeated with
body.surface_velocity_reach = 1.5, the remedy the UNSTABLE message names for stiff
membranes (tag *_reach1.5); stable_margin_capsule is the smallest margin measured.

Runs are short (end_time 0.5 in quick): a slowly growing instability past the end time is
not seen, so the margins are upper estimates of the long-run margin.
"""
import csv
import json
import shutil
from pathlib import Path

import numpy as np

from _flowio import body_series, cached_run

from _bounds import Bound  # noqa: E402

DESCRIPTION = "stability: fixed dt = k x automatic dt, status / NaN check / margin per case"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"(crashed_runs|nonfinite_field_runs|nonfinite_checkpoint_runs)", "==", 0,
          "no run crashes or writes a non-finite field or checkpoint"),
    Bound(r"unstable_runs_with_nan_fields", "==", 0, "an unstable run stops before NaNs"),
    Bound(r"stable_margin_(capsule|slab)", ">=", 1.0, "the automatic time step is stable"),
    Bound(r"capsule_re[0-9.]+_k1_stable", "==", 1,
          "the automatic time step is stable at every Re", tiers=("quick", "full")),
    Bound(r"unstable_with_automatic_dt_at_t_.*", "absent",
          why="the automatic time step is stable for every case", tiers=("quick", "full")),
    Bound(r"capsule_long_run_unstable_at_t.*", "absent",
          why="the long 3D capsule run reaches shear-rate x t = 10 (issue 19)", tiers=("full",)),
]

# Per tier: capsule cells per diameter, Ca list, k list, end time, Re list (capsule, Ca 0.2).
TIERS = {
    "ci": {"n": 8, "cas": [0.2], "ks": [0.5, 1.0, 2.0], "t_end": 0.25, "res": [],
           "grids": [], "long": None},
    "quick": {"n": 16, "cas": [0.002, 0.05, 0.2], "ks": [0.5, 1.0, 1.5, 2.0, 4.0, 8.0],
              "t_end": 0.5, "res": [0.01, 1.0, 10.0], "grids": [8, 32], "long": (8, 10.0, [5.0])},
    "full": {"n": 16, "cas": [0.002, 0.05, 0.2], "ks": [0.5, 1.0, 1.5, 2.0, 4.0, 6.0, 8.0],
             "t_end": 2.0, "res": [0.01, 1.0, 10.0], "grids": [8, 32],
             "long": (16, 10.0, [5.0, 1.5])},
}
SLAB_SHEAR_MODULUS = 100.0
COMMON = {"output.progress_every": "100000", "output.checkpoint_every": "0"}


def capsule_sets(n: int, ca: float, t_end: float, re: float | None = None) -> dict:
    cells = 4 * n
    h = 8.0 / cells
    s = {"grid.cells": f"[{cells},{cells},1]", "grid.length": f"[8.0,8.0,{h!r}]",
         "grid.origin": f"[-4.0,-4.0,{-h / 2!r}]", "body[0].elastic_modulus": repr(1.0 / ca),
         "time.end_time": repr(t_end), "output.fields_interval": repr(t_end / 2),
         "output.diagnostics_every": "1", **COMMON}
    if re is not None:
        s["fluid.density"] = repr(re)  # Re = rho * shear_rate * d^2 / (4 mu) = rho here
    return s


def long_capsule(ctx, n: int, t_end: float, reach: float, metrics: dict) -> tuple:
    """3D capsule (Ca 0.2) with the automatic dt to shear-rate x t = t_end, Gs carried with
    the surface velocity over ``reach`` cells; its drift figures. A run that stops UNSTABLE
    is reported up to its stop."""
    cells = 4 * n
    r = "" if reach == 5.0 else f"_reach{reach:g}"
    out = ctx.outdir / "runs" / f"capsule3d_n{cells}{r}_t{t_end:g}"
    sets = {"grid.cells": f"[{cells},{cells},{cells}]", "body[0].elastic_modulus": "5.0",
            "time.end_time": repr(t_end), "output.fields_interval": repr(t_end / 2),
            "output.checkpoint_every": "100", "output.progress_every": "100000"}
    if reach != 5.0:
        sets["body[0].surface_velocity_reach"] = repr(reach)
    summ = out / "summary.json"
    cached_run(ctx, ctx.repo / "cases" / "capsule_shear", out, sets, t_end,
               ranks=ctx.long_ranks, allow_unstable=True)
    t, vol, area, dd, tr = body_series(out, columns=("volume", "area", "taylor_deformation",
                                                     "tensor_trace_max"))
    s = json.loads(summ.read_text())
    late = t >= min(2.0, t[-1] / 2)  # short (test) runs: the second half
    row = {"cells": cells, "surface_velocity_reach": reach, "t_end": float(t[-1]),
           "status": s["status"], "volume_drift": float(np.max(np.abs(vol - vol[0])) / vol[0]),
           "area_drift_after_t2": float((area[late].max() - area[late].min()) / area[late][0]),
           "D_end": float(dd[-1]), "D_min_after_t2": float(dd[late].min()),
           "D_max_after_t2": float(dd[late].max()), "max_trace_Gs": float(tr.max()),
           "wall_seconds": s["wall_seconds"], "steps": s["steps"],
           "resumed": bool(s.get("restarted_from")), "message": s.get("message")}
    row.update(nonfinite(out))
    tag = "" if reach == 5.0 else f"_reach{reach:g}"
    if s["status"] == "completed":
        metrics[f"capsule_volume_drift_t{t_end:g}{tag}"] = row["volume_drift"]
        metrics[f"capsule_area_drift_t{t_end:g}{tag}"] = row["area_drift_after_t2"]
        metrics[f"capsule_D_t{t_end:g}{tag}"] = row["D_end"]
    else:
        metrics[f"capsule_long_run_unstable_at_t{tag}"] = row["t_end"]
        metrics[f"capsule_volume_drift_to_stop{tag}"] = row["volume_drift"]
    metrics[f"capsule_long_run_max_trace_Gs{tag}"] = row["max_trace_Gs"]
    metrics["capsule_long_run_cells"] = cells
    return row, (t, dd, area / area[0], vol / vol[0], tr)


def slab_sets(t_end: float) -> dict:
    return {"body[0].shear_modulus": repr(SLAB_SHEAR_MODULUS), "time.end_time": repr(t_end),
            "output.fields_interval": repr(t_end / 2), "output.diagnostics_every": "1",
            **COMMON}


def nonfinite(out: Path) -> dict:
    """Count non-finite values in every field snapshot and in the checkpoint."""
    import h5py

    def count(path):
        bad = 0
        with h5py.File(path, "r") as f:
            def visit(_, obj):
                nonlocal bad
                if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f":
                    bad += int(np.count_nonzero(~np.isfinite(obj[()])))
            f.visititems(visit)
        return bad

    snaps = sorted((out / "fields").glob("fields_*.h5"))
    ck = out / "checkpoint.h5"
    if not snaps and not ck.exists() and (out / "record.json").exists():
        # Taken from a committed record (EFSI_VERIFY_RECORDS=1), which keeps no fields: the
        # run completed, and the solver stops UNSTABLE at the first non-finite value.
        return {"snapshots": "not kept in the record"}
    return {"snapshots": len(snaps), "nonfinite_in_fields": sum(count(p) for p in snaps),
            "nonfinite_in_checkpoint": count(ck) if ck.exists() else 0}


def diagnostics(out: Path):
    f = out / "diagnostics.csv"
    if not f.exists():
        return np.zeros(0), np.zeros(0)
    with open(f) as fh:
        rows = [r for r in csv.DictReader(fh) if int(r["step"]) > 0]
    return (np.array([float(r["dt"]) for r in rows]),
            np.array([float(r["max_speed"]) for r in rows]))


def one_run(ctx, case: Path, out: Path, sets: dict) -> dict:
    if out.exists():
        shutil.rmtree(out)  # stale snapshots of an earlier run must not be checked
    cmd = [ctx.efsi, "run", case, "--output", out]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    res = ctx.run(cmd, check=False)  # an unstable run exits non-zero by design
    summ = out / "summary.json"
    row = {"exit_code": res.returncode}
    if not summ.exists():
        row.update(status="crashed", message=(res.stderr or res.stdout)[-300:])
        return row
    s = json.loads(summ.read_text())
    dts, speeds = diagnostics(out)
    row.update(status=s.get("status"), message=s.get("message", ""),
               stop_step=s.get("final_step"), stop_time=s.get("time"),
               wall_seconds=s.get("wall_seconds"),
               dt_typical=float(np.median(dts)) if dts.size else None,
               max_speed=float(np.max(speeds)) if (speeds.size and s.get("status") == "completed")
               else None)
    row.update(nonfinite(out))
    return row


def margin(rows: list) -> tuple[float, bool]:
    """Largest k with every k' <= k completed; and whether that is only a lower bound."""
    best = 0.0
    for r in sorted(rows, key=lambda r: r["k"]):
        if r["status"] != "completed":
            return best, False
        best = r["k"]
    return best, True


def sweep(ctx, label: str, case: Path, sets: dict, ks: list) -> tuple[float, list]:
    base = ctx.outdir / "runs" / label
    auto = one_run(ctx, case, base / "auto", sets)
    if auto["status"] == "unstable":
        # unstable with the automatic dt: no margin to measure; the row says where it stopped
        return None, [{"case": label, "k": "auto", "dt": auto.get("dt_typical"), **auto}]
    if auto["status"] != "completed" or not auto.get("dt_typical"):
        raise RuntimeError(f"{label}: the automatic-dt run did not complete: {auto}")
    dt_auto = auto["dt_typical"]
    rows = [{"case": label, "k": "auto", "dt": dt_auto, **auto}]
    for k in ks:
        r = one_run(ctx, case, base / f"k{k:g}", {**sets, "time.dt": repr(k * dt_auto)})
        rows.append({"case": label, "k": k, "dt": k * dt_auto, **r})
    return dt_auto, rows


def run(ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cfg = TIERS[ctx.tier]
    t_end = cfg["t_end"]
    cap_case = ctx.repo / "cases" / "capsule_shear_2d"
    metrics, table, per_case = {}, [], {}

    def margin_sweep(label: str, case: Path, sets: dict, tag: str) -> bool:
        """dt sweep of one case: its rows, and stable_margin_<tag> (+ lower-bound flag, dt).
        False when the run with the automatic dt itself stopped UNSTABLE (no margin)."""
        dt_auto, rows = sweep(ctx, label, case, sets, cfg["ks"])
        per_case[label] = rows
        table.extend(rows)
        if dt_auto is None:
            metrics[f"unstable_with_automatic_dt_at_t_{tag}"] = rows[0].get("stop_time")
            return False
        m, lower = margin([r for r in rows if r["k"] != "auto"])
        metrics[f"stable_margin_{tag}"] = m
        metrics[f"stable_margin_{tag}_is_lower_bound"] = int(lower)
        metrics[f"dt_auto_{tag}"] = dt_auto
        return True

    margins = []
    for ca in cfg["cas"]:
        sets = capsule_sets(cfg["n"], ca, t_end)
        if margin_sweep(f"capsule_ca{ca:g}", cap_case, sets, f"capsule_ca{ca:g}"):
            margins.append(metrics[f"stable_margin_capsule_ca{ca:g}"])
            continue
        # Unstable whatever the dt when the membrane is stiff and Gs is carried over the
        # default reach (docs/method.md); the sweep is made with the remedy the UNSTABLE
        # message names, and the margin is that of the remedied case.
        sets["body[0].surface_velocity_reach"] = "1.5"
        if margin_sweep(f"capsule_ca{ca:g}_reach1.5", cap_case, sets,
                        f"capsule_ca{ca:g}_reach1.5"):
            margins.append(metrics[f"stable_margin_capsule_ca{ca:g}_reach1.5"])
    if margins:
        metrics["stable_margin_capsule"] = min(margins)
    margin_sweep("slab_G100", ctx.repo / "cases" / "parallel_slab", slab_sets(t_end), "slab")

    # Re sweep for the capsule at Ca = 0.2: automatic dt, then k = 1 and k = 2.
    re_rows = []
    for re in cfg["res"]:
        label = f"capsule_ca0.2_re{re:g}"
        _, rows = sweep(ctx, label, cap_case, capsule_sets(cfg["n"], 0.2, t_end, re), [1.0, 2.0])
        re_rows += rows
        for r in rows:
            if r["k"] in (1.0, 2.0):
                metrics[f"capsule_re{re:g}_k{r['k']:g}_stable"] = int(r["status"] == "completed")
        metrics[f"dt_auto_capsule_re{re:g}"] = rows[0]["dt"]
    table += re_rows

    # Resolution sweep for the capsule at Ca = 0.2 (the margin against cells per diameter).
    for n in cfg["grids"]:
        margin_sweep(f"capsule_ca0.2_n{4 * n}", cap_case, capsule_sets(n, 0.2, t_end),
                     f"capsule_n{4 * n}")

    long_rows, long_series = [], []
    if cfg["long"]:
        n_long, t_long, reaches = cfg["long"]
        for reach in reaches:
            row, ser = long_capsule(ctx, n_long, t_long, reach, metrics)
            long_rows.append(row)
            long_series.append((reach, ser))

    fixed = [r for r in table if r["k"] != "auto"]
    metrics["unstable_runs"] = sum(r["status"] != "completed" for r in fixed)
    metrics["crashed_runs"] = sum(r["status"] == "crashed" for r in table)
    metrics["unstable_runs_with_nan_fields"] = sum(
        r["status"] != "completed" and r.get("nonfinite_in_fields", 0) > 0 for r in table)
    metrics["nonfinite_field_runs"] = sum(r.get("nonfinite_in_fields", 0) > 0 for r in table)
    metrics["nonfinite_checkpoint_runs"] = sum(r.get("nonfinite_in_checkpoint", 0) > 0
                                               for r in table)
    metrics["unstable_runs_with_message"] = sum(
        r["status"] == "unstable" and "UNSTABLE" in (r.get("message") or "") for r in table)

    # Figure: per case k on x, stable (o) / unstable (x); Re sweep as extra rows.
    groups = dict(per_case)
    for re in cfg["res"]:
        groups[f"capsule_ca0.2_re{re:g}"] = [r for r in re_rows
                                            if r["case"] == f"capsule_ca0.2_re{re:g}"]
    fig, ax = plt.subplots(figsize=(8, 1.0 + 0.55 * len(groups)))
    names = list(groups)
    for y, name in enumerate(names):
        for r in groups[name]:
            if r["k"] == "auto":
                continue
            ok = r["status"] == "completed"
            ax.plot(r["k"], y, "o" if ok else "x", color="tab:green" if ok else "tab:red",
                    ms=9, mew=2)
            if not ok:
                ax.annotate(f"t={r.get('stop_time', float('nan')):.3g}", (r["k"], y),
                            textcoords="offset points", xytext=(0, 8), ha="center", fontsize=7)
    ax.axvline(1.0, color="gray", ls="--", lw=1)
    ax.set_xscale("log", base=2)
    ks = sorted({r["k"] for r in fixed})
    ax.set_xticks(ks)
    ax.set_xticklabels([f"{k:g}" for k in ks])
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels(names, fontsize=8)
    ax.set_ylim(-0.7, len(names) - 0.3)
    ax.set_xlabel("k = fixed dt / automatic dt  (o completed, x unstable)")
    ax.set_title(f"stability sweep, tier {ctx.tier}, end time {t_end:g}")
    fig.tight_layout()
    png = ctx.outdir / "stability.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)

    figures = [str(png)]
    if long_series:
        fig, ax = plt.subplots(1, 3, figsize=(14, 3.8))
        for (reach, (t, dd, area, vol, tr)), row in zip(long_series, long_rows):
            lab = f"surface velocity reach {reach:g}" + (
                "" if row["status"] == "completed" else f" (UNSTABLE at t = {row['t_end']:.3g})")
            line, = ax[0].plot(t, dd, label=lab)
            ax[1].plot(t, area - 1, color=line.get_color(), label=f"area - 1, reach {reach:g}")
            ax[1].plot(t, vol - 1, ":", color=line.get_color(),
                       label=f"volume - 1, reach {reach:g}")
            ax[2].semilogy(t, tr, color=line.get_color(), label=lab)
        ax[0].set(xlabel="shear rate x t", ylabel="D",
                  title=f"3D capsule Ca 0.2, {long_rows[0]['cells']}^3")
        ax[1].set(xlabel="shear rate x t", ylabel="relative to t = 0")
        ax[2].set(xlabel="shear rate x t", ylabel="max tr Gs (3: unstrained)")
        for a in ax:
            a.legend(fontsize=7)
        fig.tight_layout()
        png2 = ctx.outdir / "long_capsule.png"
        fig.savefig(png2, dpi=110)
        plt.close(fig)
        figures.append(str(png2))

    cols = ["case", "k", "dt", "status", "stop_step", "stop_time", "max_speed", "snapshots",
            "nonfinite_in_fields", "nonfinite_in_checkpoint", "exit_code", "message"]
    tab = [{c: r.get(c) for c in cols} for r in table]
    tables = {"runs": tab}
    if long_rows:
        tables["long_capsule"] = long_rows
    return {"metrics": metrics, "tables": tables, "figures": figures,
            "notes": (f"Short runs (end time {t_end:g}); a margin flagged is_lower_bound means "
                      "the largest k tried still completed. Capsule Re sweep at Ca = 0.2 sets "
                      "fluid.density = Re.")}
