"""Capsule with bending stiffness in simple shear: D(t) with and without bending.

Runs cases/capsule_shear_2d (2D, z-invariant: a circular capsule, neo-Hookean, Re = 0.01,
Ca = 0.05) with body.bending_modulus = Eb for Eb / (a^2 Es) in {0, 0.01, 0.05} up to
shear-rate x t = 2 at d/16; the full tier adds d/32 (0 and 0.05, to t = 1: is the effect of
bending resolved?) and a coarse 3D check (cases/capsule_shear at d/8, 0 and 0.05, t = 1). kappa_R starts as the initial circle's / sphere's
curvature 1/a, so the capsule starts moment-free. Each run is cached under runs/<key>/
and resumed from its checkpoint.

No published D(t) for this exact model (linear isotropic bending moment of the seed, 2D)
was found to compare with; the expectations are qualitative: bending resists the change of
curvature, so D is reduced, slightly for these bending numbers (Dupont et al., Phys. Fluids
27, 2015, 3D shell FE + boundary integral: for an initially spherical capsule the bending
rigidity has a negligible effect on the overall deformation once the mid-surface
shear modulus is fixed). Metrics: D at t = 1 and t = 2 per bending ratio, the reduction
relative to no bending, the volume drift, the dt limit that set the step, wall seconds.
"""
import csv
import json
from pathlib import Path

import numpy as np

from _flowio import body_series, cached_run, capsule_box_sets

from _bounds import Bound  # noqa: E402

DESCRIPTION = "capsule in shear with bending (Eb/(a^2 Es) = 0.01, 0.05): D(t) vs no bending"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"completed_.*", "==", 1, "every run reaches its end time"),
    Bound(r"volume_drift_.*", "<=", 1e-10, "the VOF keeps the volume to round-off"),
    Bound(r"D_reduction_t[12]_.*", ">=", 0.02,
          "bending (Eb / (a^2 Es) >= 0.01) lowers D measurably", tiers=("quick", "full")),
]

# (dimension, cells per diameter, [Eb / (a^2 Es)], end time) per tier.
TIERS = {
    "ci": [(2, 8, [0.0, 0.05], 0.5)],
    "quick": [(2, 16, [0.0, 0.01, 0.05], 2.0)],
    "full": [(2, 16, [0.0, 0.01, 0.05], 2.0), (2, 32, [0.0, 0.05], 1.0),
             (3, 8, [0.0, 0.05], 1.0)],
}
CA = 0.05


def run_one(ctx, dim: int, n: int, ratio: float, t_end: float) -> Path:
    out = ctx.outdir / "runs" / f"{dim}d_n{n}_ca{CA:g}_eb{ratio:g}_t{t_end:g}"
    case = ctx.repo / "cases" / ("capsule_shear" if dim == 3 else "capsule_shear_2d")
    es = 1.0 / CA  # a = 1, mu = 1, shear rate 1
    sets = {**capsule_box_sets(dim, n), "body[0].elastic_modulus": repr(es),
            "body[0].bending_modulus": repr(ratio * es),  # Eb = ratio a^2 Es, a = 1
            "time.end_time": repr(t_end), "output.fields_interval": "0.5",
            "output.checkpoint_every": "200", "output.progress_every": "100000"}
    return cached_run(ctx, case, out, sets, t_end)


def series(out: Path):
    return body_series(out)


def run(ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    metrics, rows = {}, []
    groups = TIERS[ctx.tier]
    fig, axes = plt.subplots(1, len(groups), figsize=(6 * len(groups), 4.5), squeeze=False)
    for ax, (dim, n, ratios, t_end) in zip(axes[0], groups):
        base = {}
        for ratio in ratios:
            out = run_one(ctx, dim, n, ratio, t_end)
            t, d, th, vol = series(out)
            s = json.loads((out / "summary.json").read_text())
            with open(out / "diagnostics.csv") as f:
                diag = list(csv.DictReader(f))
            steps = int(float(diag[-1]["step"])) if diag and "step" in diag[0] else None
            tag = f"{dim}d_n{n}_eb{ratio:g}"
            row = {"dim": dim, "n": n, "Eb_over_a2Es": ratio, "status": s["status"],
                   "t_end": float(t[-1]), "steps": steps,
                   "volume_drift": float(abs(vol[-1] - vol[0]) / vol[0]),
                   "wall_seconds": s["wall_seconds"]}
            for tt in (0.5, 1.0, 2.0):
                if t[-1] >= tt - 1e-9:
                    row[f"D_t{tt:g}"] = float(np.interp(tt, t, d))
                    row[f"angle_over_pi_t{tt:g}"] = float(np.interp(tt, t, th))
                    metrics[f"D_t{tt:g}_{tag}"] = row[f"D_t{tt:g}"]
            if ratio == 0:
                base = row
            elif base:
                for tt in (1.0, 2.0):
                    k = f"D_t{tt:g}"
                    if k in row and k in base:
                        row[f"D_reduction_t{tt:g}"] = 1 - row[k] / base[k]
                        metrics[f"D_reduction_t{tt:g}_{tag}"] = row[f"D_reduction_t{tt:g}"]
            metrics[f"volume_drift_{tag}"] = row["volume_drift"]
            metrics[f"wall_seconds_{tag}"] = row["wall_seconds"]
            metrics[f"completed_{tag}"] = 1.0 if s["status"] == "completed" else 0.0
            rows.append(row)
            ax.plot(t, d, label=f"Eb/(a^2 Es) = {ratio:g}")
        ax.set(xlabel="shear rate x t", ylabel="D",
               title=f"{dim}D capsule, Ca = {CA:g}, d/{n}: bending vs none")
        ax.legend(fontsize=8)
    fig.tight_layout()
    png = ctx.outdir / "capsule_bending.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    notes = ("Runs are cached under runs/ and resumed from checkpoints. No published D(t) for "
             "this model was found; bending is expected to reduce D slightly (Dupont et al. "
             "2015: negligible effect of bending on the overall deformation of an initially "
             "spherical capsule).")
    return {"metrics": metrics, "tables": {"runs": rows}, "figures": [str(png)], "notes": notes}
