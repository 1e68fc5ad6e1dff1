"""Platelet-adhesion kinetics alone (GPIb-alpha / vWF bonds, kinetic Monte Carlo) against
closed forms, then a single platelet over a vWF patch in shear flow (issue 21).

Runs build/bin/efsi_adhesion_kinetics, which drives the solver's own kinetics
(solver/adhesion/kinetics.hpp) on receptors that each face their own ligand at a fixed bond
length (so every bond carries a constant force and the pairs are independent):

- lifetime: n pre-formed bonds under F = 10 pN with the default (Bell) parameters, no
  rebinding; the lifetime (K - 1/2) dt of a bond that breaks in its K-th step estimates the
  exponential lifetime with mean 1/k_off(F) (midpoint bias (k_off dt)^2 / 12 relative, 1e-5
  at k_off dt = 0.01). `bond_lifetime_rel_error` is |mean / (1/k_off) - 1|, its z-score
  the error over the standard error; `bond_lifetime_ks_pvalue` the Kolmogorov-Smirnov
  p-value against the exponential CDF (exact at the step ends: P(K <= k) = 1 - e^{-k k_off dt}).
  The quick and full tiers repeat it at several forces, for the Bell law and for the
  catch-slip law with illustrative two-pathway parameters (not a fit to data).
- equilibrium: N free receptors at F = 5 pN (k_off = 7.9 1/s, k_on = 10 1/s) relax to the
  bound fraction k_on / (k_on + k_off) (`bound_fraction_rel_error`; the discrete chain's own
  fraction p_on / (p_on + p_off) differs by `bound_fraction_dt_bias`), and M samples spaced
  so that they are independent (chain correlation 0.005) give the bond-count distribution,
  compared with the master equation's Binomial(N, k_on / (k_on + k_off)) by chi-square
  (`bond_count_distribution_pvalue`; bins with fewer than 5 expected merged).

Then the coupled problem (issue 21, second part): the single platelet of
cases/platelet_adhesion (a neo-Hookean sphere of radius 1 um, G = 4 Pa, 2000 GPIb-alpha
receptors, its lowest point 30 nm above a vWF patch on the wall y = 0 of a Couette cell)
at several wall shear rates, with and without [adhesion], the case's own parameters
otherwise (k_on = 1000 1/s, the defaults of docs/method.md for the rest; nothing tuned):
bond count and platelet-wall gap (centroid height minus radius) against time
(adhesion.csv, bodies.csv), and the translocation velocity
`translocation_velocity_um_s_at_<rate>`, the platelet centroid's mean x velocity over the
second half of the run, against the same platelet without adhesion
(`free_velocity_um_s_at_<rate>`, `velocity_ratio_at_<rate>`). The bond reactions are taken
by the wall (docs/method.md, "The wall takes the reaction"); `wall_impulse_balance_at_<rate>`
checks that the walls' impulse is minus the bonds' impulse on the platelet. Each rate is run
twice with adhesion: receptors carried by the flow (the default) and receptors moving with
the platelet's fitted rigid motion (adhesion.receptor_motion = "rigid", which loads the
platelet as a rigid body and lets the wall support it; the same metrics suffixed `_rigid`,
e.g. `translocation_velocity_um_s_at_<rate>_rigid`). ci: one coarse
short run (h = 0.5 um, 0.5 ms, 500 1/s); quick: h = 0.25 um, 1 ms at 250, 500 and
1000 1/s. Published translocation velocities (Doggett et al. 2002, Mody & King 2008) could
not be consulted for this study: no comparison with measurements is made (notes).

Then the paper's Fig. 5 scene (cases/platelet_adhesion_rbc), quick and full tiers: seeds
with red cells and without, outcome per seed (`adhered_fraction_with_rbc`, ...); the full
tier runs the five seeds with rigid receptors too (metrics suffixed `_rigid`).

Seeds are fixed, so each tier's numbers are reproducible on any machine.
"""
import json
import math
import re

import numpy as np
from scipy import stats

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from _bounds import Bound  # noqa: E402

DESCRIPTION = ("platelet adhesion: bond lifetime, equilibrium bound fraction and bond-count "
               "distribution vs closed forms; a platelet over a vWF patch in shear flow "
               "(bonds, gap, translocation velocity)")

# Acceptance bounds (verification/studies/_bounds.py). The statistical ones are 4 standard
# errors of each tier's sample size (lifetime: 1/sqrt(n); fraction: sqrt((1-f)/(f N M)));
# the p-values are those of fixed seeds (p > 0.001: a correct sampler fails one in 1000 seeds).
BOUNDS = [
    Bound(r"bond_lifetime_zscore(_.*)?", "<=", 4.0,
          "mean lifetime within 4 standard errors of 1/k_off(F) (Bell and catch-slip)"),
    Bound(r"bond_lifetime_rel_error", "<=", 0.057,
          "4 standard errors of the mean of 5000 exponential lifetimes", tiers=("ci",)),
    Bound(r"bond_lifetime_rel_error", "<=", 0.018,
          "4 standard errors of the mean of 50000 exponential lifetimes", tiers=("quick",)),
    Bound(r"bond_lifetime_rel_error", "<=", 0.009,
          "4 standard errors of the mean of 200000 exponential lifetimes", tiers=("full",)),
    Bound(r"bond_lifetime_ks_pvalue(_.*)?", ">=", 1e-3,
          "lifetimes exponential (Kolmogorov-Smirnov against 1 - exp(-k_off t))"),
    Bound(r"bound_fraction_zscore", "<=", 4.0,
          "equilibrium bound fraction within 4 standard errors (+ the dt bias) of "
          "k_on / (k_on + k_off)"),
    Bound(r"bound_fraction_rel_error", "<=", 0.02,
          "4 standard errors of 4e4 samples at f = 0.56", tiers=("ci",)),
    Bound(r"bound_fraction_rel_error", "<=", 0.006,
          "4 standard errors of 5e5 samples at f = 0.56", tiers=("quick", "full")),
    Bound(r"bound_fraction_dt_bias", "<=", 1e-3,
          "the time step's bias of the discrete chain is far below the statistical tolerance"),
    Bound(r"bond_count_distribution_pvalue", ">=", 1e-3,
          "bond count Binomial(N, k_on / (k_on + k_off)), the master equation's stationary law"),
    # The coupled runs: claims of the model, not agreement with measurements (none here).
    Bound(r"max_bonds_at_.*", ">=", 1,
          "the platelet 30 nm above the patch binds (k_on = 1000 1/s, reactive distance 70 nm)"),
    Bound(r"wall_impulse_balance_at_.*", "<=", 1e-12,
          "the walls take exactly the reaction of the bonds' pull on the platelet "
          "(|impulse_walls + impulse_bodies| / |impulse_bodies|)"),
    # The Fig. 5 scene: the runs are what they claim to be; the outcome itself (adhered or
    # not) is reported, not bounded.
    Bound(r"fig5_t_end_reached_fraction_.*", "==", 1.0,
          "every run of the scene reaches its end time (no UNSTABLE stop)", tiers=("quick", "full")),
    Bound(r"fig5_haematocrit_min_with_rbc", ">=", 0.18,
          "the seeding packs the red cells to within one cell of the 20 % target "
          "(4 cells: 18.8 % of the 2000 um^3 box)", tiers=("quick", "full")),
]

PN = 1e-12
TIERS = {
    #        lifetime bonds, forces [pN] (Bell), catch-slip forces, (N, M) fraction, (N, M) distribution
    "ci": dict(bonds=5000, forces=[10], catch=[], fraction=(200, 200), distribution=(20, 1000)),
    "quick": dict(bonds=50000, forces=[0, 5, 10, 20], catch=[0, 5, 10, 20, 40],
                  fraction=(1000, 500), distribution=(20, 10000)),
    "full": dict(bonds=200000, forces=[0, 2.5, 5, 10, 15, 20, 30], catch=[0, 5, 10, 15, 20, 30, 40, 60],
                 fraction=(2000, 1000), distribution=(20, 40000)),
}
# Illustrative two-pathway (catch-slip) parameters, exercising the law's implementation
# only: a lifetime maximum at F* = 16 pN, the catch-then-slip shape Yago et al. 2008 report
# for GPIb-alpha / vWF-A1 (their fitted values are not reproduced here).
CATCH = {"--catch-rate": 20, "--catch-distance": 1.0e-9, "--slip-rate": 0.5,
         "--slip-distance": 0.3e-9}
FRACTION_FORCE = 5 * PN


def lifetime_stats(k_steps, k_off, dt):
    k = np.asarray(k_steps, dtype=float)
    t = (k - 0.5) * dt
    mean, se = t.mean(), t.std(ddof=1) / math.sqrt(len(t))
    tau = 1.0 / k_off
    # KS against the exponential CDF at the step ends, where it is exact: both the empirical
    # and the true CDF of K are step functions of the integer k, so the supremum is over
    # k = 1 .. max K. The lifetimes are discrete, so the asymptotic p-value is conservative.
    n = len(k)
    kk = np.arange(1, int(k.max()) + 1)
    emp = np.cumsum(np.bincount(k.astype(int), minlength=int(k.max()) + 1)[1:]) / n
    d = float(np.max(np.abs(emp + np.expm1(-k_off * dt * kk))))
    p = float(stats.kstwo.sf(d, n))
    return {"mean": float(mean), "se": float(se), "tau": tau, "rel_error": abs(mean / tau - 1),
            "zscore": abs(mean - tau) / se, "ks": float(d), "ks_pvalue": p, "t": t}


# The coupled runs: cases/platelet_adhesion at other shear rates (wall velocity U = rate H),
# grids and end times. h = 0.25 um is the case's grid.
SHEAR = {
    "ci": dict(rates=[500], cells=[12, 8, 8], end_time=5.0e-4),
    "quick": dict(rates=[250, 500, 1000], cells=[24, 16, 16], end_time=1.0e-3),
    "full": dict(rates=[250, 500, 1000, 2000], cells=[24, 16, 16], end_time=2.0e-3),
}
CASE = "cases/platelet_adhesion/case.toml"
HEIGHT = 4.0e-6   # channel height H [m] (the case's)
RADIUS = 1.0e-6   # platelet radius [m]


def shear_case(ctx, rate, cells, end_time, adhesion, motion="flow"):
    """The case's text at wall shear rate `rate`, grid `cells`, `end_time`, with or without
    its [adhesion] table (and its sub-tables); `motion` is adhesion.receptor_motion."""
    import re
    text = (ctx.repo / CASE).read_text()
    u = rate * HEIGHT
    text = text.replace("velocity = [2.0e-3, 0.0, 0.0]", f"velocity = [{u!r}, 0.0, 0.0]")
    text = text.replace("amplitude = 2.0e-3", f"amplitude = {u!r}")
    text = re.sub(r"cells = \[24, 16, 16\]", f"cells = [{cells[0]}, {cells[1]}, {cells[2]}]", text)
    text = text.replace("end_time = 5.0e-4", f"end_time = {end_time!r}")
    if not adhesion:
        text = text[:text.index("[adhesion]")] + text[text.index("[output]"):]
    elif motion != "flow":
        text = text.replace("[adhesion]\n", f'[adhesion]\nreceptor_motion = "{motion}"\n', 1)
    return text


def read_csv(path):
    import csv
    with open(path) as f:
        return list(csv.DictReader(f))


def shear_runs(ctx, metrics, tables, notes):
    cfg = SHEAR[ctx.tier]
    rows, series = [], {}
    # Each rate: receptors carried by the flow (the default), receptors moving with the
    # platelet's fitted rigid motion (metrics suffixed _rigid), and no adhesion.
    for rate in cfg["rates"]:
        res = {}
        for variant in ("flow", "rigid", None):
            adhesion = variant is not None
            tag = f"shear{rate}_" + {"flow": "adhesion", "rigid": "adhesion_rigid",
                                     None: "free"}[variant]
            case = ctx.outdir / f"{tag}.toml"
            case.write_text(shear_case(ctx, rate, cfg["cells"], cfg["end_time"], adhesion,
                                       variant or "flow"))
            out = ctx.outdir / tag
            summ = ctx.run_efsi(case, out)
            b = read_csv(out / "bodies.csv")
            t = np.array([float(r["time"]) for r in b])
            x = np.array([float(r["centroid_x"]) for r in b])
            y = np.array([float(r["centroid_y"]) for r in b])
            half = int(np.searchsorted(t, 0.5 * t[-1]))
            v = (x[-1] - x[half]) / (t[-1] - t[half])
            res[variant] = dict(summary=summ, t=t, x=x, gap=y - RADIUS, v=v,
                                adh=read_csv(out / "adhesion.csv") if adhesion else None)
        off = res[None]
        metrics[f"free_velocity_um_s_at_{rate:g}"] = off["v"] * 1e6
        for variant in ("flow", "rigid"):
            on = res[variant]
            a = on["summary"]["adhesion"]
            bonds = np.array([int(r["bonds"]) for r in on["adh"]])
            tb = np.array([float(r["time"]) for r in on["adh"]])
            ib, iw = np.array(a["impulse_on_bodies"]), np.array(a["impulse_on_walls"])
            iw = iw + np.array(a["impulse_on_held"])
            key = f"{rate:g}" + ("" if variant == "flow" else "_rigid")
            metrics[f"translocation_velocity_um_s_at_{key}"] = on["v"] * 1e6
            metrics[f"velocity_ratio_at_{key}"] = on["v"] / off["v"]
            metrics[f"max_bonds_at_{key}"] = int(a["max_bonds"])
            metrics[f"mean_bonds_second_half_at_{key}"] = float(bonds[tb >= 0.5 * tb[-1]].mean())
            metrics[f"min_gap_nm_at_{key}"] = float(on["gap"].min() * 1e9)
            metrics[f"final_gap_nm_at_{key}"] = float(on["gap"][-1] * 1e9)
            metrics[f"impulse_on_platelet_x_Ns_at_{key}"] = float(ib[0])
            nb = float(np.linalg.norm(ib))
            metrics[f"wall_impulse_balance_at_{key}"] = (float(np.linalg.norm(ib + iw)) / nb
                                                        if nb > 0 else 0.0)
            rows.append({"shear_rate_per_s": rate, "receptor_motion": variant,
                         "translocation_velocity_um_s": on["v"] * 1e6,
                         "free_velocity_um_s": off["v"] * 1e6, "ratio": on["v"] / off["v"],
                         "gamma_a_um_s": rate * RADIUS * 1e6, "max_bonds": int(a["max_bonds"]),
                         "bonds_formed": int(a["bonds_formed"]),
                         "bonds_broken": int(a["bonds_broken"]),
                         "first_bond_time_s": a["first_bond_time"],
                         "max_tension_pN": a["max_tension"] * 1e12,
                         "wall_lift_nm": a.get("wall_lift", 0.0) * 1e9,
                         "impulse_on_platelet_Ns": list(ib), "impulse_on_walls_Ns": list(iw),
                         "min_gap_nm": float(on["gap"].min() * 1e9)})
            series[(rate, variant)] = (tb, bonds, on, off)
    tables["translocation"] = rows

    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    colours = {}
    for (rate, variant), (tb, bonds, on, off) in series.items():
        style = "-" if variant == "flow" else ":"
        line, = axes[0].plot(tb * 1e3, bonds, style, color=colours.get(rate),
                             label=f"{rate:g} 1/s, {variant}")
        colours[rate] = line.get_color()
        axes[1].plot(on["t"] * 1e3, on["gap"] * 1e9, style, color=colours[rate],
                     label=f"{rate:g} 1/s, adhesion ({variant})")
        axes[2].plot(on["t"] * 1e3, (on["x"] - on["x"][0]) * 1e6, style, color=colours[rate],
                     label=f"{rate:g} 1/s, adhesion ({variant})")
        if variant == "flow":
            axes[1].plot(off["t"] * 1e3, off["gap"] * 1e9, "--", color=colours[rate],
                         label=f"{rate:g} 1/s, free")
            axes[2].plot(off["t"] * 1e3, (off["x"] - off["x"][0]) * 1e6, "--",
                         color=colours[rate], label=f"{rate:g} 1/s, free")
    axes[0].set(xlabel="t [ms]", ylabel="bonds", title="bond count")
    axes[1].set(xlabel="t [ms]", ylabel="gap [nm]", title="platelet-wall gap (centroid y - a)")
    axes[2].set(xlabel="t [ms]", ylabel="x - x0 [um]", title="platelet displacement")
    for ax in axes:
        ax.legend(fontsize=7)
    fig.tight_layout()
    png = ctx.outdir / "platelet_translocation.png"
    fig.savefig(png, dpi=110)
    h = HEIGHT / cfg["cells"][1]
    notes.append(
        f"Shear runs: cases/platelet_adhesion at {cfg['rates']} 1/s, h = {h * 1e6:g} um, "
        f"{cfg['end_time'] * 1e3:g} ms; translocation velocity = the centroid's mean x "
        "velocity over the second half of the run. The gap is centroid y minus the radius "
        "(a rigid-sphere measure; the soft sphere deforms). The 30 nm gap is far below h, "
        "so lubrication is not resolved, and the runs are short (a few bond lifetimes at "
        "most at k_off0 = 3.45 1/s: no steady stop-and-go is reached); the velocities are "
        "those of the first millisecond. No published translocation velocity was compared: "
        "the values of Doggett et al. 2002 and Mody & King 2008 could not be consulted here.")
    return png


# The paper's Fig. 5 scene (cases/platelet_adhesion_rbc): a platelet 100 nm above a vWF
# patch in channel flow, with red cells (the case's Ht 20 % target) and without (target 0),
# over several seeds (the seeding's and the kinetics'). No ci tier: a red-cell run costs
# ~0.07 s per 1 us step on one core.
# receptor motions run per tier: the default ("flow") and, in the full tier, receptors
# carried by the platelet's fitted rigid motion (metrics suffixed _rigid)
FIG5 = {
    "quick": dict(seeds=[1, 2], end_time=2.0e-3, motions=("flow",)),
    "full": dict(seeds=[1, 2, 3, 4, 5], end_time=1.0e-2, motions=("flow", "rigid")),
}
FIG5_CASE = "cases/platelet_adhesion_rbc/case.toml"
FIG5_HT = 0.2


def fig5_run(ctx, kind, seed, end_time, motion="flow"):
    """One run of the scene, cached (and resumed from its checkpoint) in runs/<key>; with
    EFSI_VERIFY_RECORDS=1 a committed record stands in for a missing run. `motion` is
    adhesion.receptor_motion ("flow", the default, or "rigid": key suffix _rigid)."""
    from _flowio import cached_run

    key = f"fig5_{kind}_s{seed}_t{end_time * 1e3:g}ms" + ("" if motion == "flow" else f"_{motion}")
    out = ctx.outdir / "runs" / key
    sets = {"time.end_time": repr(end_time),
            "seeding.target_haematocrit": repr(FIG5_HT if kind == "rbc" else 0.0),
            "seeding.seed": seed, "adhesion.seed": seed}
    if motion != "flow":
        sets["adhesion.receptor_motion"] = f'"{motion}"'
    cached_run(ctx, ctx.repo / FIG5_CASE, out, sets, t_end=end_time)
    summ = json.loads((out / "summary.json").read_text())
    adh = read_csv(out / "adhesion.csv")
    t = np.array([float(r["time"]) for r in adh])
    order = np.argsort(t, kind="stable")  # a resumed run repeats the rows after its checkpoint
    t, idx = np.unique(t[order], return_index=True)
    bonds = np.array([int(adh[i]["bonds"]) for i in order[idx]])
    near = np.array([int(adh[i]["free_near"]) for i in order[idx]])
    b = [r for r in read_csv(out / "bodies.csv") if r["body"] == "platelet"]
    tb = np.array([float(r["time"]) for r in b])
    o = np.argsort(tb, kind="stable")
    tb, ib = np.unique(tb[o], return_index=True)
    y = np.array([float(b[i]["centroid_y"]) for i in o[ib]])
    x = np.array([float(b[i]["centroid_x"]) for i in o[ib]])
    drift = receptor_drift(out)
    # time with at least one bond: the rows are diagnostics_every steps apart (10 us)
    dt_rows = np.diff(t, append=t[-1])
    return dict(key=key, out=out, summary=summ, t=t, bonds=bonds, near=near, tb=tb, y=y, x=x,
                adhered=bool(bonds[-1] > 0), time_bound=float(np.sum(dt_rows[bonds > 0])),
                mean_bonds=float(np.sum(dt_rows * bonds) / (t[-1] - t[0])),
                seeding=summ.get("seeding", {}), drift=drift)


def receptor_drift(out):
    """Where the receptors are at the end against the platelet they should sit on: the
    lowest receptor's height above y = 0 and the fraction of receptors outside the body
    (phi < 0.05, trilinear between cell centres, periodic in x and z), from the final
    checkpoint's adhesion/receptor_x and the last snapshot's phi_platelet at the same time.
    None when the run has no checkpoint or snapshot (a committed record)."""
    import glob
    ckpt, snaps = out / "checkpoint.h5", sorted(glob.glob(str(out / "fields" / "fields_*.h5")))
    if not ckpt.exists() or not snaps:
        return None
    import h5py
    from scipy.interpolate import RegularGridInterpolator
    cells = [int(v) for v in re.findall(r"\d+", re.search(
        r"cells = \[[^\]]*\]", (out / "case.toml").read_text()).group(0))]
    length = [float(v) for v in re.search(r"length = \[([^\]]*)\]",
                                          (out / "case.toml").read_text()).group(1).split(",")]
    nx, ny, nz = cells
    h = [length[d] / cells[d] for d in range(3)]
    with h5py.File(ckpt, "r") as f:
        x = f["adhesion/receptor_x"][...].reshape(-1, 3)
        t_ckpt = float(f.attrs["time"])
    with h5py.File(snaps[-1], "r") as f:
        if abs(float(f.attrs["time"]) - t_ckpt) > 1e-12 or "phi_platelet" not in f:
            return None
        phi = np.transpose(f["phi_platelet"][...].reshape(nz, ny, nx), (2, 1, 0))
    c = [(np.arange(cells[d]) + 0.5) * h[d] for d in range(3)]
    pad = np.pad(phi, ((1, 1), (0, 0), (1, 1)), mode="wrap")
    ax = [np.concatenate([[c[d][0] - h[d]], c[d], [c[d][-1] + h[d]]]) for d in (0, 2)]
    interp = RegularGridInterpolator((ax[0], c[1], ax[1]), pad)
    q = x.copy()
    q[:, 0] %= length[0]
    q[:, 2] %= length[2]
    q[:, 1] = np.clip(q[:, 1], c[1][0], c[1][-1])
    v = interp(q)
    return {"lowest_receptor_nm": float(x[:, 1].min() * 1e9),
            "outside_fraction": float(np.mean(v < 0.05)),
            "x_spread_um": float(np.ptp(x[:, 0]) * 1e6)}


def fig5_scene(ctx, metrics, tables, notes):
    cfg = FIG5.get(ctx.tier)
    if cfg is None:
        notes.append("Fig. 5 scene (cases/platelet_adhesion_rbc): quick and full tiers only.")
        return None
    every = {m: {k: [fig5_run(ctx, k, s, cfg["end_time"], motion=m) for s in cfg["seeds"]]
                 for k in ("rbc", "free")} for m in cfg["motions"]}
    runs = every["flow"]
    rows = []
    for motion, kind, rs in ((m, k, rs) for m, by in every.items() for k, rs in by.items()):
        tag = ("with_rbc" if kind == "rbc" else "without_rbc") + (
            "" if motion == "flow" else f"_{motion}")
        metrics[f"adhered_fraction_{tag}"] = float(np.mean([r["adhered"] for r in rs]))
        metrics[f"fig5_time_bound_fraction_{tag}"] = float(
            np.mean([r["time_bound"] for r in rs]) / cfg["end_time"])
        metrics[f"fig5_mean_bonds_{tag}"] = float(np.mean([r["mean_bonds"] for r in rs]))
        metrics[f"fig5_seeds_bound_ever_{tag}"] = int(sum(r["bonds"].max() > 0 for r in rs))
        metrics[f"fig5_t_end_reached_fraction_{tag}"] = float(np.mean(
            [r["summary"]["status"] == "completed"
             and abs(r["summary"]["time"] - cfg["end_time"]) < 1e-12 for r in rs]))
        metrics[f"fig5_platelet_rise_um_{tag}"] = float(np.mean([(r["y"][-1] - r["y"][0]) * 1e6
                                                                 for r in rs]))
        for r in rs:
            a = r["summary"].get("adhesion", {})
            rows.append({"scene": tag, "receptor_motion": motion,
                         "seed": int(r["key"].split("_s")[1].split("_")[0]),
                         "red_cells": int(r["seeding"].get("placed", {}).get("rbc", 0)),
                         "haematocrit": r["seeding"].get("achieved_haematocrit", 0.0),
                         "adhered": r["adhered"], "bonds_at_end": int(r["bonds"][-1]),
                         "max_bonds": int(r["bonds"].max()),
                         "first_bond_time_ms": a["first_bond_time"] * 1e3
                         if a.get("first_bond_time") is not None else None,
                         "time_bound_ms": r["time_bound"] * 1e3,
                         "mean_bonds": r["mean_bonds"],
                         "centroid_y_start_um": r["y"][0] * 1e6,
                         "centroid_y_end_um": r["y"][-1] * 1e6,
                         "min_centroid_y_um": float(r["y"].min() * 1e6),
                         "receptors_within_reach_plus_margin_end": int(r["near"][-1]),
                         "lowest_receptor_nm_end": r["drift"] and r["drift"]["lowest_receptor_nm"],
                         "receptors_outside_platelet_end": r["drift"] and r["drift"]["outside_fraction"],
                         "receptor_x_spread_um_end": r["drift"] and r["drift"]["x_spread_um"]})
        drifts = [r["drift"]["outside_fraction"] for r in rs if r["drift"]]
        if drifts:
            metrics[f"fig5_receptors_outside_platelet_max_{tag}"] = float(max(drifts))
    metrics["fig5_haematocrit_min_with_rbc"] = float(min(
        r["seeding"].get("achieved_haematocrit", 0.0) for r in runs["rbc"]))
    tables["fig5_scene"] = rows

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.2))
    for motion, style in (("flow", "-"), ("rigid", "--")):
        for kind, colour in (("rbc", "tab:red"), ("free", "tab:blue")):
            for i, r in enumerate(every.get(motion, {}).get(kind, [])):
                lab = (("with red cells" if kind == "rbc" else "without red cells")
                       + ("" if motion == "flow" else ", rigid receptors")) if i == 0 else None
                axes[0].plot(r["tb"] * 1e3, r["y"] * 1e6, style, color=colour, lw=1, label=lab)
                axes[1].plot(r["t"] * 1e3, r["bonds"], style, color=colour, lw=1, label=lab)
    axes[0].set(xlabel="t [ms]", ylabel="platelet centroid y [um]",
                title="platelet height above the vWF wall (start 0.7 um)")
    axes[1].set(xlabel="t [ms]", ylabel="bonds", title="GPIb-alpha / vWF bonds")
    for ax in axes[:2]:
        ax.legend(fontsize=8)
    # the scene at the end of the first seed with red cells: the slice z = 5 um through the
    # platelet's start and the middle of the patch, each body's phi = 1/2 contour
    ax = axes[2]
    snaps = sorted((runs["rbc"][0]["out"] / "fields").glob("fields_*.h5"))
    if snaps:
        import h5py
        nx, ny, nz = (int(v) for v in re.findall(r"\d+", re.search(
            r"cells = \[[^\]]*\]", (runs["rbc"][0]["out"] / "case.toml").read_text()).group(0)))
        lx, ly, lz = 20.0, 10.0, 10.0
        k = min(nz - 1, int(5.0 / (lz / nz)))
        xc = (np.arange(nx) + 0.5) * lx / nx
        yc = (np.arange(ny) + 0.5) * ly / ny
        with h5py.File(snaps[-1], "r") as f:
            t_snap = float(f.attrs["time"]) if "time" in f.attrs else None
            for name in sorted(f):
                if not name.startswith("phi_"):
                    continue
                sl = f[name][...].reshape(nz, ny, nx)[k]
                if name == "phi_platelet":
                    ax.contourf(xc, yc, sl, levels=[0.5, 2], colors=["0.3"])
                else:
                    ax.contourf(xc, yc, sl, levels=[0.5, 2], colors=["tab:red"], alpha=0.6)
                    ax.contour(xc, yc, sl, levels=[0.5], colors=["darkred"], linewidths=0.8)
        ax.axhline(0.05, color="goldenrod", lw=4, label="vWF patch")
        ax.set(xlim=(0, lx), ylim=(0, ly), xlabel="x [um]", ylabel="y [um]", aspect="equal",
               title=f"seed {cfg['seeds'][0]} with red cells, t = "
                     f"{(t_snap if t_snap is not None else cfg['end_time']) * 1e3:.3g} ms, "
                     f"slice z = {(k + 0.5) * lz / nz:g} um")
        ax.legend(fontsize=7, loc="upper right")
    else:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no field snapshots (run taken from its record)", ha="center")
    fig.tight_layout()
    png = ctx.outdir / "platelet_fig5.png"
    fig.savefig(png, dpi=110)
    notes.append(
        f"Fig. 5 scene (cases/platelet_adhesion_rbc, its README gives every parameter): "
        f"seeds {cfg['seeds']}, {cfg['end_time'] * 1e3:g} ms each, with red cells (target Ht "
        f"{FIG5_HT:g}) and without, receptor motions {list(cfg['motions'])} (metrics of "
        "'rigid' suffixed _rigid; dashed in the figure). 'Adhered' = the platelet holds at least one bond at the "
        "end of the run; time bound = time with at least one bond; mean bonds = time average "
        "over the run. The platelet starts 100 nm above the vWF patch, 30 nm beyond the "
        "reactive distance, so a bond needs the platelet to approach the wall. Without red "
        "cells the seed changes only the receptors' places on the platelet (and the bond "
        "draws), so the platelet's path is the same for every seed until a first bond forms.")
    return png


def run(ctx):
    exe = ctx.efsi.parent / "efsi_adhesion_kinetics"
    tier = TIERS[ctx.tier]
    metrics, notes, tables = {}, [], {}
    fig, axes = plt.subplots(1, 4 if tier["forces"][1:] else 3, figsize=(17 if tier["forces"][1:] else 13, 4))

    # ---- lifetime under constant force ---------------------------------------------------
    rows = []
    for law, forces in (("bell", tier["forces"]), ("catch_slip", tier["catch"])):
        for f_pn in forces:
            csv = ctx.outdir / f"lifetime_{law}_{f_pn:g}pN.csv"
            extra = [] if law == "bell" else [str(v) for kv in CATCH.items() for v in kv]
            seed = 1000 + int(10 * f_pn) + (0 if law == "bell" else 500)
            info = json.loads(ctx.run([exe, "lifetime", "--force", f_pn * PN, "--bonds", tier["bonds"],
                                       "--seed", seed, "--law", law, "--csv", csv] + extra).stdout)
            k = np.loadtxt(csv, skiprows=1)
            s = lifetime_stats(k, info["k_off"], info["dt"])
            rows.append({"law": law, "force_pN": f_pn, "k_off_per_s": info["k_off"],
                         "mean_lifetime_s": s["mean"], "expected_s": s["tau"],
                         "rel_error": s["rel_error"], "zscore": s["zscore"],
                         "ks_pvalue": s["ks_pvalue"]})
            tag = f"{law}_{f_pn:g}pN".replace(".", "p")
            metrics[f"bond_lifetime_zscore_{tag}"] = s["zscore"]
            metrics[f"bond_lifetime_ks_pvalue_{tag}"] = s["ks_pvalue"]
            if law == "bell" and f_pn == 10:
                metrics["bond_lifetime_rel_error"] = s["rel_error"]
                metrics["bond_lifetime_zscore"] = s["zscore"]
                metrics["bond_lifetime_ks_pvalue"] = s["ks_pvalue"]
                metrics["bond_lifetime_mean_s"] = s["mean"]
                metrics["bond_lifetime_expected_s"] = s["tau"]
                ax = axes[0]
                t = np.sort(s["t"])
                surv = 1 - np.arange(1, len(t) + 1) / len(t)
                ax.semilogy(t[:-1], surv[:-1], "b.", ms=2, label=f"kinetic MC, n = {len(t)}")
                tt = np.linspace(0, t.max(), 200)
                ax.semilogy(tt, np.exp(-tt / s["tau"]), "k-", label="exp(-k_off t)")
                ax.set(xlabel="bond lifetime t [s]", ylabel="survival P(T > t)",
                       title=f"Bell, F = 10 pN: k_off = {info['k_off']:.2f} 1/s")
                ax.legend(fontsize=8)
    tables["bond_lifetime"] = rows
    if tier["forces"][1:]:
        ax = axes[3]
        for law, style in (("bell", "b"), ("catch_slip", "r")):
            r = [x for x in rows if x["law"] == law]
            if not r:
                continue
            f = np.array([x["force_pN"] for x in r])
            ax.errorbar(f, [x["mean_lifetime_s"] for x in r],
                        yerr=[4 * x["mean_lifetime_s"] / math.sqrt(tier["bonds"]) for x in r],
                        fmt=style + "o", ms=4, label=f"kinetic MC ({law.replace('_', '-')})")
            ax.plot(f, [x["expected_s"] for x in r], style + "-", lw=1,
                    label=f"1/k_off(F) at these F ({law.replace('_', '-')})")
        ax.set(xlabel="bond force F [pN]", ylabel="mean lifetime [s]", yscale="log",
               title="lifetime vs force (catch-slip illustrative)")
        ax.legend(fontsize=7)

    # ---- equilibrium bound fraction ------------------------------------------------------
    n, m = tier["fraction"]
    csv, relax = ctx.outdir / "fraction_samples.csv", ctx.outdir / "fraction_relaxation.csv"
    info = json.loads(ctx.run([exe, "equilibrium", "--force", FRACTION_FORCE, "--receptors", n,
                               "--samples", m, "--seed", 31337, "--csv", csv,
                               "--relaxation-csv", relax]).stdout)
    counts = np.loadtxt(csv, delimiter=",", skiprows=1, ndmin=2)[:, 1]
    f_exact = info["k_on"] / (info["k_on"] + info["k_off"])
    f_chain = info["p_on"] / (info["p_on"] + info["p_off"])
    f = counts.sum() / (n * m)
    se = math.sqrt(f_exact * (1 - f_exact) / (n * m))
    metrics["bound_fraction"] = f
    metrics["bound_fraction_expected"] = f_exact
    metrics["bound_fraction_rel_error"] = abs(f / f_exact - 1)
    metrics["bound_fraction_dt_bias"] = abs(f_chain / f_exact - 1)
    metrics["bound_fraction_zscore"] = max(0.0, abs(f - f_exact) - abs(f_chain - f_exact)) / se
    r = np.loadtxt(relax, delimiter=",", skiprows=1)
    ax = axes[1]
    ax.plot(r[:, 1], r[:, 2] / n, "b-", lw=1, label=f"kinetic MC, N = {n}")
    k_sum = info["k_on"] + info["k_off"]
    ax.plot(r[:, 1], f_exact * (1 - np.exp(-k_sum * r[:, 1])), "k--",
            label="k_on/(k_on+k_off) (1 - exp(-(k_on+k_off) t))")
    ax.axhline(f, color="r", lw=0.8, label=f"sampled equilibrium {f:.4f}")
    ax.set(xlabel="t [s]", ylabel="bound fraction", title="relaxation from all free, F = 5 pN")
    ax.legend(fontsize=7)

    # ---- bond-count distribution ---------------------------------------------------------
    n, m = tier["distribution"]
    csv = ctx.outdir / "distribution_samples.csv"
    info = json.loads(ctx.run([exe, "equilibrium", "--force", FRACTION_FORCE, "--receptors", n,
                               "--samples", m, "--seed", 4242, "--csv", csv]).stdout)
    counts = np.loadtxt(csv, delimiter=",", skiprows=1, ndmin=2)[:, 1].astype(int)
    f_exact = info["k_on"] / (info["k_on"] + info["k_off"])
    observed = np.bincount(counts, minlength=n + 1).astype(float)
    expected = m * stats.binom.pmf(np.arange(n + 1), n, f_exact)
    obs_b, exp_b, so, se_ = [], [], 0.0, 0.0
    for o, e in zip(observed, expected):  # merge bins until each expects >= 5
        so += o
        se_ += e
        if se_ >= 5:
            obs_b.append(so)
            exp_b.append(se_)
            so = se_ = 0.0
    obs_b[-1] += so
    exp_b[-1] += se_
    chi2 = float(np.sum((np.array(obs_b) - np.array(exp_b)) ** 2 / np.array(exp_b)))
    dof = len(obs_b) - 1
    metrics["bond_count_distribution_pvalue"] = float(stats.chi2.sf(chi2, dof))
    metrics["bond_count_distribution_chi2"] = chi2
    metrics["bond_count_distribution_dof"] = dof
    ax = axes[2]
    k = np.arange(n + 1)
    ax.bar(k, observed / m, color="tab:blue", alpha=0.6, label=f"kinetic MC, {m} samples")
    ax.plot(k, expected / m, "ko-", ms=3, label=f"Binomial({n}, {f_exact:.3f})")
    ax.set(xlabel="bonds", ylabel="probability",
           title=f"bond count, chi2 p = {metrics['bond_count_distribution_pvalue']:.3f}")
    ax.legend(fontsize=8)

    fig.tight_layout()
    png = ctx.outdir / "platelet_adhesion.png"
    fig.savefig(png, dpi=110)
    png2 = shear_runs(ctx, metrics, tables, notes)
    png3 = fig5_scene(ctx, metrics, tables, notes)
    notes.append("Kinetics alone: receptors held still facing their own ligands, so each bond "
                 "carries a constant force; no flow in that part (docs/method.md, 'Platelet "
                 "adhesion (kinetic Monte Carlo)'). The mean lifetime is estimated by "
                 "(K - 1/2) dt with K the step in which the bond broke (bias "
                 "(k_off dt)^2 / 12 = 1e-5). The bound fraction is compared with the "
                 "continuous closed form; the discrete chain's own value differs by "
                 "bound_fraction_dt_bias. The catch-slip parameters are illustrative, not a fit.")
    figures = [str(png), str(png2)] + ([str(png3)] if png3 else [])
    return {"metrics": metrics, "tables": tables, "figures": figures,
            "notes": " ".join(notes)}
