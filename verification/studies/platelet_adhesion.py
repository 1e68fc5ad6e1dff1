"""Platelet-adhesion kinetics alone (GPIb-alpha / vWF bonds, kinetic Monte Carlo) against
closed forms (issue 21, first part: no flow coupling yet).

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

Seeds are fixed, so each tier's numbers are reproducible on any machine.
"""
import json
import math

import numpy as np
from scipy import stats

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from _bounds import Bound  # noqa: E402

DESCRIPTION = ("platelet adhesion kinetics alone: bond lifetime, equilibrium bound fraction and "
               "bond-count distribution vs closed forms")

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
    notes.append("Kinetics alone: receptors held still facing their own ligands, so each bond "
                 "carries a constant force; no flow coupling yet (docs/method.md, 'Platelet "
                 "adhesion (kinetic Monte Carlo)'). The mean lifetime is estimated by "
                 "(K - 1/2) dt with K the step in which the bond broke (bias "
                 "(k_off dt)^2 / 12 = 1e-5). The bound fraction is compared with the "
                 "continuous closed form; the discrete chain's own value differs by "
                 "bound_fraction_dt_bias. The catch-slip parameters are illustrative, not a fit.")
    return {"metrics": metrics, "tables": tables, "figures": [str(png)], "notes": " ".join(notes)}
