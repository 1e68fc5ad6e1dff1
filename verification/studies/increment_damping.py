"""Increment damping (time.increment_damping = F): steps saved against accuracy lost.

A stiff membrane's explicit force limits the time step to dt <= cfl 10 mu h / K (K the
area-dilation modulus: 14 Es for a Skalak membrane at C = 10), which at low Reynolds
number sets the cost of the red-cell and stiff-capsule runs. With F > 1 the implicit
viscous solve also damps the velocity increment, b lap_h (v* - v^n) with
b = dt (F - 1) mu / rho, which relaxes that limit F-fold and vanishes at steady state
(docs/method.md, "Increment damping").

Runs cases/capsule_shear (3D, Skalak C = 10, Ca = 0.025, one rank) at F = 1, 2, 4 with the
default cfl 0.5, and F = 1 at cfl 0.25 as the time-step reference (half the default step);
and the damping confined to the membrane's band (time.increment_damping_on = "membranes",
tags M<F>) at F = 2, 4, 8.
Per run (tag F<F>, and F1_half for the reference): steps, wall seconds, steady D (mean over
the last quarter), max tr Gs; and
- D_change_F<F>: max |D_F(t) - D_F1(t)| over the run (what the larger step costs);
- dt_error_F1: max |D_F1(t) - D_F1_half(t)| over the run, the default step's own error;
- step_ratio_F<F>: steps of F = 1 / steps of F (deterministic, unlike wall time).

Bounds: every run reaches its end time; F = 2 takes at least 1.9x fewer steps and changes
D by no more than the default step's own error (dt_error_F1); so does the band damping at
F = 4 (M4). The uniform F = 4 is reported, not bounded (it rings near t = 2.5 at d/8:
docs/method.md), and so is M8.

Tiers: ci d/8 to t = 0.3 (F = 1, 2 and M2 only, no reference run); quick d/8 to t = 1; full
d/8 to t = 3 (about a quarter of an hour on one core). Not yet measured: d/16 (F = 1 to t = 1 alone takes
about 14 minutes there).
"""
import numpy as np

from _bounds import Bound
from _flowio import body_series, cached_run, capsule_box_sets, run_status

DESCRIPTION = "increment damping: time steps saved against the change in D (stiff Skalak capsule)"

CA, C = 0.025, 10.0
# (cells per diameter, end time, damping factors, band damping factors, with the half-step
# reference?)
TIERS = {
    "ci": (8, 0.3, (1, 2), (2,), False),
    "quick": (8, 1.0, (1, 2, 4), (2, 4, 8), True),
    "full": (8, 3.0, (1, 2, 4), (2, 4, 8), True),
}

BOUNDS = [
    Bound(r"reached_end_.*", "==", 1, "every run reaches its end time (no UNSTABLE stop)"),
    Bound(r"step_ratio_F2", ">=", 1.9, "F = 2 takes at least 1.9x fewer steps than F = 1"),
    Bound(r"D_change_over_dt_error_F2", "<=", 1.0,
          "F = 2 changes D(t) by no more than the default step's own error (F = 1, half dt)",
          tiers=("quick", "full")),
    Bound(r"step_ratio_M2", ">=", 1.9, "the band damping at F = 2 takes at least 1.9x fewer "
          "steps than F = 1"),
    Bound(r"D_change_over_dt_error_M4", "<=", 1.0,
          "the band damping at F = 4 changes D(t) by no more than the default step's own error",
          tiers=("quick", "full")),
]


def run_sets(n: int, t_end: float, F: float, cfl: float, region: str = "everywhere") -> dict:
    band = {} if region == "everywhere" else {"time.increment_damping_on": f'"{region}"'}
    return {**capsule_box_sets(3, n), **band, "body[0].law": '"skalak"',
            "body[0].area_dilation": repr(C), "body[0].elastic_modulus": repr(1.0 / CA),
            "time.end_time": repr(t_end), "time.increment_damping": repr(float(F)),
            "time.cfl": repr(cfl), "output.fields": "false",
            "output.progress_every": "100000",
            "case.description": repr(f"Skalak capsule, C = {C:g}, Ca = {CA:g}, d/{n}, F = {F:g}")}


def max_change(a, b) -> float:
    """max |D_a - D_b| over the times of a within b's range (b interpolated)."""
    (ta, Da), (tb, Db) = a, b
    m = (ta >= tb[0]) & (ta <= tb[-1])
    return float(np.max(np.abs(Da[m] - np.interp(ta[m], tb, Db))))


def run(ctx):
    n, t_end, factors, band_factors, with_reference = TIERS[ctx.tier]
    metrics, rows, series = {}, [], {}
    runs = [(f"F{F}", F, 0.5, "everywhere") for F in factors]
    runs += [(f"M{F}", F, 0.5, "membranes") for F in band_factors]
    if with_reference:
        runs.append(("F1_half", 1, 0.25, "everywhere"))
    for tag, F, cfl, region in runs:
        out = ctx.outdir / "runs" / f"n{4 * n}_{tag}_t{t_end:g}"
        cached_run(ctx, ctx.repo / "cases" / "capsule_shear", out,
                   run_sets(n, t_end, F, cfl, region), t_end, ranks=1, allow_unstable=True)
        t, D, _, _ = body_series(out)
        _, trace = body_series(out, columns=("tensor_trace_max",))
        summary = run_status(out)
        series[tag] = (t, D)
        last = t >= 0.75 * t[-1]
        metrics[f"reached_end_{tag}"] = int(abs(t[-1] - t_end) <= 1e-9)
        metrics[f"steps_{tag}"] = int(summary["steps"])
        metrics[f"wall_seconds_{tag}"] = float(summary["wall_seconds"])
        metrics[f"steady_D_{tag}"] = float(np.mean(D[last]))
        metrics[f"max_trace_Gs_{tag}"] = float(np.max(trace))
        rows.append({"run": tag, "F": F, "damped": region, "cfl": cfl,
                     "t reached": round(float(t[-1]), 4),
                     "steps": int(summary["steps"]),
                     "wall [s]": round(float(summary["wall_seconds"]), 1),
                     "steady D": round(float(np.mean(D[last])), 5),
                     "max tr Gs": round(float(np.max(trace)), 3)})
    for tag, F, cfl, _ in runs:
        if tag in ("F1", "F1_half"):
            continue
        metrics[f"D_change_{tag}"] = max_change(series["F1"], series[tag])
        metrics[f"step_ratio_{tag}"] = metrics["steps_F1"] / metrics[f"steps_{tag}"]
    if with_reference:
        err = max_change(series["F1_half"], series["F1"])
        metrics["dt_error_F1"] = err
        for tag, F, _, _ in runs:
            if F != 1:
                metrics[f"D_change_over_dt_error_{tag}"] = metrics[f"D_change_{tag}"] / err
    for row in rows:
        tag = row["run"]
        row["max |D - D(F=1)|"] = ("-" if tag == "F1" else
                                   round(metrics.get(f"D_change_{tag}",
                                                     metrics.get("dt_error_F1", 0.0)), 5))
    notes = (f"cases/capsule_shear, Skalak C = {C:g}, Ca = {CA:g}, d/{n}, to t = {t_end:g}, one "
             "rank. D_change_F<F> = max |D_F(t) - D_F1(t)|; dt_error_F1 = max |D_F1 - D_F1_half| "
             "(the default step against half of it); the F1_half row's last column is that "
             "error. M<F>: the same F confined to the membrane's band "
             "(time.increment_damping_on = \"membranes\"; its viscous solve is hypre's, the "
             "others' the FFT's, so its wall seconds are not comparable per step). Wall seconds "
             "depend on the machine's load; step ratios do not.")
    return {"metrics": metrics, "tables": {"runs": rows}, "notes": notes}
