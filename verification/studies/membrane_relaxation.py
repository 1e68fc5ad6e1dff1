"""The membrane's stiffness, measured by relaxation: a sheared capsule let go.

Runs cases/capsule_shear at Ca 0.0125 (small deformation) and Re 1e-4 (fluid.density =
1e-4, so the flow follows the walls within ~1e-3): sheared to t = 0.6 (D near its steady
25/4 Ca), then the walls stand still (`boundary.*.stop_time = 0.6`) and the capsule relaxes
to the sphere for 0.6 more, with no tank-treading. It tests the membrane's elastic response
alone, the quantity a strain carrier that loses or gains strain gets wrong
(docs/method.md, "The membrane's stiffness, measured by relaxation").

Theory (small deformation, equal viscosities; Barthes-Biesel & Rallison 1981): a sphere
starts deforming at dD/dt = E = shear rate / 2 and settles at D = 25/4 Ca, so a single
relaxation mode has tau = 2 x 25/4 Ca / shear rate = 12.5 Ca = 0.156. The fit: D(t) of the
body bounded by phi = 1/2 (bodies.csv `taylor_deformation_sharp`), log-linear over the
window 0.6 D0 >= D >= 0.15 D0 after the walls stop, D0 its value at the stop.
tau / 12.5 Ca > 1: the discrete membrane is that much softer than the continuous one. The
walls at 4 a slow the relaxation by a few per cent (doubling the box removed 0.04 of the
excess at d/8), so the continuum limit of the ratio is ~1.03, not 1.

Metrics per grid (n = cells per diameter): tau_over_theory_n<n>, tau_n<n>, D0_n<n>,
residual_fraction_n<n> (D at the end over D0: a carrier that forgets its strain leaves the
capsule a new rest shape, and D levels off), completed_n<n>, wall_seconds_n<n>; between consecutive grids, excess_order_n<n>: log2 of
the ratio of the excesses (tau / theory - 1) of the coarser and this grid (first order: 1).

Tiers: ci d/8; quick d/8 and d/16; full d/8, d/16, d/32 (d/32: about 10 minutes).
"""
import csv
from pathlib import Path

import numpy as np

from _bounds import Bound
from _flowio import cached_run, capsule_box_sets

DESCRIPTION = "sheared capsule let go: relaxation time against small-deformation theory"

CA, T_SHEAR, T_RELAX = 0.0125, 0.6, 0.6
TAU_THEORY = 2 * 25.0 / 4.0 * CA
TIERS = {"ci": [8], "quick": [8, 16], "full": [8, 16, 32]}

BOUNDS = [
    Bound(r"completed_.*", "==", 1, "every run reaches its end time"),
    # The walls make the continuum's ratio ~1.03: below 1 the membrane is stiffer than the
    # continuum (a spurious stiffness); above 1.25 it lost strain as a carrier that does not
    # follow the surface does (the carried tensor at d/8: 5.1; the map moved by the local
    # velocity at d/16: 1.54). Measured with the default keys: 1.18 / 1.11 / 1.07 at
    # d/8 / 16 / 32.
    Bound(r"tau_over_theory_n[0-9]+", ">=", 1.0,
          "no spurious stiffness: relaxation no faster than the continuum's"),
    Bound(r"tau_over_theory_n[0-9]+", "<=", 1.25,
          "the membrane keeps its strain: relaxation time within 25 % of theory"),
    # A carrier that forgets its strain leaves a residual D (a new rest shape): the continuum
    # keeps exp(-0.6 / (1.03 x 0.156)) = 0.024 of D0 at the end; the carried tensor moved by
    # the local velocity (the red cells' carrier in capillary_coarse) kept 0.13 / 0.16 at
    # d/8 / 16, its D levelling off; the default map 0.053 / 0.046, still falling.
    Bound(r"residual_fraction_n[0-9]+", "<=", 0.1,
          "the capsule returns to its rest shape: D at the end below 10 % of D0"),
    Bound(r"excess_order_n[0-9]+", ">=", 0.5,
          "the softness shrinks with refinement (first order: 1)", tiers=("quick", "full")),
]


def run_sets(n: int, ca: float = CA, t_shear: float = T_SHEAR, t_relax: float = T_RELAX,
             box: float = 8.0) -> dict:
    """Keys of one relaxation run: capsule_shear at Ca `ca`, Re 1e-4, walls stopping at
    `t_shear`, to t_shear + t_relax; box in radii (the case's 8 unless given)."""
    sets = {**capsule_box_sets(3, n), "body[0].elastic_modulus": repr(1.0 / ca),
            "fluid.density": "0.0001", "time.end_time": repr(t_shear + t_relax),
            "output.checkpoint_every": "100000", "output.fields_interval": "1000.0",
            "output.diagnostics_every": "1", "output.progress_every": "100000"}
    half = box / 2
    if box != 8.0:
        cells = int(n * box / 2)
        sets.update({"grid.cells": f"[{cells},{cells},{cells}]",
                     "grid.length": f"[{box!r},{box!r},{box!r}]",
                     "grid.origin": f"[{-half!r},{-half!r},{-half!r}]",
                     "initial.amplitude": repr(half)})
    # The walls at y = -+box/2 move at -+box/2 (shear rate 1) until t_shear.
    for face, v in (("y_low", -half), ("y_high", half)):
        sets[f"boundary.{face}"] = (f'{{type="wall",velocity=[{v!r},0.0,0.0],'
                                    f'stop_time={t_shear!r}}}')
    return sets


def fit(out: Path, t0: float = T_SHEAR, tau_theory: float = TAU_THEORY) -> dict:
    """tau from D(t) of the phi = 1/2 body after t0 (see the docstring)."""
    with open(Path(out) / "bodies.csv") as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["time"]) for r in rows])
    D = np.array([float(r["taylor_deformation_sharp"]) for r in rows])
    keep = t >= t0 - 1e-9
    t, D = t[keep] - t0, D[keep]
    w = (D <= 0.6 * D[0]) & (D >= 0.15 * D[0])
    if w.sum() < 3:
        raise RuntimeError(f"{out}: fewer than 3 points of D in [0.15, 0.6] D0 after t = {t0}")
    slope = np.polyfit(t[w], np.log(D[w]), 1)[0]
    tau = -1.0 / slope
    return {"D0": float(D[0]), "tau": float(tau), "tau_theory": tau_theory,
            "tau_over_theory": float(tau / tau_theory), "fit_points": int(w.sum()),
            "fit_window": [float(t[w][0]), float(t[w][-1])],
            "residual_fraction": float(D[-1] / D[0]), "t": t, "D": D}


def run(ctx):
    import json

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    metrics, rows = {}, []
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    prev = None
    case = ctx.repo / "cases" / "capsule_shear"
    for n in TIERS[ctx.tier]:
        out = cached_run(ctx, case, ctx.outdir / "runs" / f"n{n}", run_sets(n),
                         T_SHEAR + T_RELAX)
        s = json.loads((out / "summary.json").read_text())
        f = fit(out)
        tag = f"n{n}"
        metrics[f"tau_over_theory_{tag}"] = f["tau_over_theory"]
        metrics[f"tau_{tag}"] = f["tau"]
        metrics[f"D0_{tag}"] = f["D0"]
        metrics[f"residual_fraction_{tag}"] = f["residual_fraction"]
        metrics[f"completed_{tag}"] = 1.0 if s["status"] == "completed" else 0.0
        metrics[f"wall_seconds_{tag}"] = s["wall_seconds"]
        row = {"cells_per_diameter": n, "D0": f["D0"], "tau": f["tau"],
               "tau_theory": f["tau_theory"], "tau_over_theory": f["tau_over_theory"],
               "fit_points": f["fit_points"], "residual_fraction": f["residual_fraction"],
               "wall_seconds": s["wall_seconds"]}
        if prev is not None:
            order = float(np.log2((prev - 1) / (f["tau_over_theory"] - 1)))
            metrics[f"excess_order_{tag}"] = order
            row["excess_order"] = order
        prev = f["tau_over_theory"]
        rows.append(row)
        ax.semilogy(f["t"], f["D"] / f["D0"], label=f"d/{n}: tau / theory {f['tau_over_theory']:.3f}")
    tt = np.linspace(0, T_RELAX, 50)
    ax.semilogy(tt, np.exp(-tt / TAU_THEORY), "k--", label="exp(-t / 12.5 Ca)")
    ax.axhspan(0.15, 0.6, color="0.9", zorder=0)
    ax.set(xlabel="shear rate x (t - 0.6), walls at rest", ylabel="D / D0", ylim=(0.03, 1.1),
           title=f"capsule relaxation, Ca = {CA:g} (fit window shaded)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    png = ctx.outdir / "membrane_relaxation.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    notes = ("tau from a log-linear fit of the phi = 1/2 body's D between 0.6 D0 and 0.15 D0 "
             "after the walls stop; theory 12.5 Ca (small deformation). The walls at 4 a add a "
             "few per cent (continuum limit ~1.03). Variants (box, band width, carriers, "
             "laws): verification/records/capsule_longtime/relaxation.py, docs/method.md.")
    return {"metrics": metrics, "tables": {"runs": rows}, "figures": [str(png)], "notes": notes}
