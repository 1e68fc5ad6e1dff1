"""Capsule in simple shear (seed Fig. 1d): D(t) and inclination against the literature.

Runs cases/capsule_shear (3D) and capsule_shear_2d at several Ca and resolutions; each
run is cached under build/verification/capsule_shear/runs/<key>/ keyed by its
parameters, and resumed from its last checkpoint if it was cut short, so the study can be
run in parts. Metrics per 3D run: max_abs_D_error_ca<Ca>_n<cells> (max over the part of
shear-rate x t in [0.2, 2] that the reference covers, of |D - D_ref|, D_ref interpolated
from Ramanujan & Pozrikidis 1998, or Pozrikidis 1995 for Ca = 0.0125),
volume_drift_ca<Ca>_n<cells>, wall_seconds_ca<Ca>_n<cells>. 2D runs (the z-invariant
model) are compared with the independent 2D references of reference/ (FE and
boundary-integral D at t = 1), not with the 3D literature.

Figure capsule_fig1d.png is laid out like the seed's Fig. 1d: D against shear-rate x t
for every Ca, one colour per Ca, line style per resolution, Ramanujan & Pozrikidis 1998
(open triangles), Pozrikidis 1995 (filled circles) and Eggleton & Popel 1998 (crosses).

EFSI_VERIFY_CACHED_ONLY=1 reports only the runs already complete in the cache (a 3D d/32
run costs hours); the runs it skipped are listed in the result's notes and table.
"""
import json
import os
from pathlib import Path

import numpy as np

from _flowio import body_series, cached_run, capsule_box_sets, completed

from _bounds import Bound  # noqa: E402

DESCRIPTION = "capsule in shear: D(t) vs Ramanujan & Pozrikidis / Pozrikidis, volume drift, cost"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"volume_drift_.*", "<=", 1e-10, "the VOF keeps the volume to round-off"),
    Bound(r"D2d_t1_vs_bi_rel_ca[0-9.]+_n(32|64)", ">=", -0.1,
          "2D D(1) within 10 % of the boundary integral at d/8-d/16"),
    Bound(r"D2d_t1_vs_bi_rel_ca[0-9.]+_n(32|64)", "<=", 0.1,
          "2D D(1) within 10 % of the boundary integral at d/8-d/16"),
    Bound(r"D2d_t1_vs_bi_rel_ca[0-9.]+_n128", ">=", -0.02,
          "2D D(1) within 2 % of the boundary integral at d/32", tiers=("full",)),
    Bound(r"D2d_t1_vs_bi_rel_ca[0-9.]+_n128", "<=", 0.02,
          "2D D(1) within 2 % of the boundary integral at d/32", tiers=("full",)),
    Bound(r"max_abs_D_error_ca[0-9.]+_n64", "<=", 0.02,
          "3D D(t) within 0.02 of Ramanujan & Pozrikidis 1998 at d/16", tiers=("quick", "full")),
    Bound(r"max_abs_D_error_ca[0-9.]+_n128", "<=", 0.01,
          "3D D(t) within 0.01 of Ramanujan & Pozrikidis 1998 at d/32", tiers=("full",)),
    Bound(r"max_trace_Gs_ca[0-9.]+_n[0-9]+", "<=", 10,
          "the membrane strain stays consistent (tr Gs of a capsule in shear is 2-3; issue 19)",
          tiers=("quick", "full")),
    Bound(r"trace_bound_exceeded_at_t_.*", "absent",
          why="no run with the default keys passes the tensor bound", tiers=("quick", "full")),
    Bound(r"unstable_at_t_ca[0-9.]+_n[0-9]+", "absent",
          why="every run with the default interface width reaches its end time", tiers=("quick", "full")),
]

# (dimension, cells per diameter, Ca list) per tier.
# The ci tier ran the 2D capsule at d/8 until session 14; with the normal extension and the
# profile restoration (the default since then) its D(1) at Ca 0.2 is 13 % below the boundary
# integral at d/8 (8 % before; at d/16 the two formulations agree to 0.3 %: docs/method.md,
# "Membranes that last"), which breaks the 10 % bound. The ci smoke run is therefore d/16,
# and the d/8 run moved to the quick tier, where that bound reports the miss.
TIERS = {
    "ci": [(2, 16, [0.2])],
    "quick": [(2, 8, [0.2]), (2, 16, [0.05, 0.2]), (3, 16, [0.2])],
    "full": [(2, 16, [0.05, 0.2]), (2, 32, [0.05, 0.2]),
             (3, 16, [0.0125, 0.025, 0.05, 0.1, 0.2]), (3, 32, [0.0125, 0.025, 0.05, 0.1, 0.2])],
}
T_END = {"ci": 1.0, "quick": 2.0, "full": 2.0}
# Skalak capsules (3D, cells per diameter, Ca = mu shear_rate a / Es, area-dilation C), full
# tier. The seed's Skalak form Ws = Es/6 (...) has the small-strain shear modulus
# Gs = 2 Es / 3 (MODEL.md: Es/6 plays the role of Gs/4), so Ca_G = mu shear_rate a / Gs =
# 1.5 Ca, and its surface Poisson ratio is nu_s = C / (1 + C). Small-deformation theory
# (Barthes-Biesel & Rallison 1981, J Fluid Mech 113): D_inf = (5/4) (2 + nu_s) / (1 + nu_s)
# Ca_G = (5/4) (2 + 3C) / (1 + 2C) Ca_G (the neo-Hookean capsule, nu_s = 1/2 and
# Gs = Es/3, gives the familiar 25/4 Ca). With C = 1 (nu_s = 1/2) and Ca = 0.025 the
# Skalak capsule has the small-strain moduli of the neo-Hookean one at Ca = 0.0125, so at
# small deformation it must follow Pozrikidis (1995)'s Ca = 0.0125 curve; C = 10 deforms
# less, by (32/21) / (5/3) = 0.914.
# Fourth entry: the reach of the surface velocity (body key surface_velocity_reach, cells).
# The default (5) blows up for C = 10, whose area modulus is 14 Es = 560 mu shear_rate a
# (docs/method.md, "The reach of the surface velocity, and stiff membranes"); 1.5 is stable.
SKALAK = {"ci": [], "quick": [], "full": [(16, 0.025, 1.0, 5.0), (16, 0.025, 10.0, 1.5)]}
# Neo-Hookean runs with a shorter reach (3D, cells per diameter, Ca, reach), next to the
# default-reach runs of TIERS: at d/32 and Ca 0.0125 (Es = 80 mu shear_rate a) the default
# reach lets Gs grow from t ~ 0.8 (docs/method.md), and 1.5 is the remedy the UNSTABLE
# message names; the table shows what it costs in D.
REACH = {"ci": [], "quick": [], "full": [(32, 0.0125, 1.5)]}
# Interface-width sweep (3D, full tier): the smoothed membrane is 2 eps thick-ish (phi =
# (1 - tanh(L / eps)) / 2 with eps = smoothing_width x h), and D depends on eps = w h, hardly
# on h alone (d/8 with w = 0.5 and d/16 with w = 1 agree to 4e-4 in D). (Ca, [(cells per
# diameter, w)]) with eps / a = 2 w / n = 0.5, 0.25, 0.125, 0.125, 0.0625.
WIDTH_SWEEP = {"ci": [], "quick": [],
               "full": [(0.025, [(8, 2.0), (8, 1.0), (8, 0.5), (16, 1.0), (16, 0.5)]),
                        (0.05, [(8, 2.0), (8, 1.0), (8, 0.5), (16, 1.0), (16, 0.5)])]}


def skalak_linear_theory(ca: float, c: float) -> float:
    return 1.25 * (2 + 3 * c) / (1 + 2 * c) * 1.5 * ca
def reference_2d(repo: Path) -> dict:
    """Independent 2D references at shear-rate x t = 1, as the stored full tier of
    reference_vesicle measured them: {Ca: {"fe": D (finest FE mesh that reached t = 1),
    "bi": D (boundary integral, finest N)}}; empty when no result is stored."""
    import json
    import re

    f = repo / "verification" / "results" / "reference_vesicle" / "result.json"
    if not f.exists():
        return {}
    m = json.loads(f.read_text()).get("metrics", {})
    out = {}
    for k, v in m.items():
        hit = re.fullmatch(r"(fe|bi)_D_ca([0-9.]+)_t1", k)
        if hit:
            out.setdefault(float(hit.group(2)), {})[hit.group(1)] = v
    return {ca: refs for ca, refs in out.items() if len(refs) == 2}


def read_curve(f: Path):
    """A digitised (t, D) curve, sorted by t; None when the file is absent."""
    if not f.exists():
        return None
    return np.array(sorted(tuple(map(float, line.split(","))) for line in f.read_text().split()))


def window(t, ref):
    """The times compared with a reference: shear-rate x t in [0.2, 2], within its data."""
    lo, hi = max(0.2, ref[0, 0]), min(2.0, ref[-1, 0], t[-1])
    return (t >= lo) & (t <= hi)


def max_abs_diff(t, d, ref) -> float:
    """max |D - D_ref| over window(t, ref), D_ref interpolated linearly."""
    m = window(t, ref)
    return float(np.max(np.abs(d[m] - np.interp(t[m], ref[:, 0], ref[:, 1]))))


def reference_curve(data: Path, ca: float):
    name = "pozrikidis1995" if ca == 0.0125 else "ramanujan_pozrikidis1998"
    pts = read_curve(data / f"{name}_ca{ca:g}.csv")
    return (name, pts) if pts is not None else (None, None)


def run_one(ctx, dim: int, n: int, ca: float, t_end: float, skalak_c: float | None = None,
            width: float | None = None, reach: float = 5.0) -> Path:
    """One cached run; a run that stops UNSTABLE is returned too (see stopped_at)."""
    case = ctx.repo / "cases" / ("capsule_shear" if dim == 3 else "capsule_shear_2d")
    sets = run_sets(dim, n, ca, t_end, skalak_c, width, reach)
    out = run_dir(ctx, dim, n, ca, t_end, skalak_c, width, reach)
    return cached_run(ctx, case, out, sets, t_end, ranks=ctx.long_ranks if dim == 3 else 1,
                      allow_unstable=True)


# The solver's default stability.max_tensor_trace: a run recorded before that bound existed
# (session 10) may have "completed" with tr Gs far beyond it; its rows say from when.
MAX_TENSOR_TRACE = 100.0


def stop_note(out: Path) -> tuple[str, float | None, float]:
    """How the run ended ("completed" / "UNSTABLE at t = ..." / "completed, but tr Gs > 100
    from t = ...: invalid after that"), the time after which it is not valid (None: valid to
    its end) and its largest tr Gs."""
    unstable = stopped_at(out)
    t, tr = body_series(out, columns=("tensor_trace_max",))
    if unstable is not None:
        return f"UNSTABLE at t = {unstable:.4g}", unstable, float(tr.max())
    over = np.nonzero(tr > MAX_TENSOR_TRACE)[0]
    if len(over):
        t_bad = float(t[over[0]])
        return (f"completed, but tr Gs > {MAX_TENSOR_TRACE:g} (the default "
                f"stability.max_tensor_trace) from t = {t_bad:.3g}: invalid after that",
                t_bad, float(tr.max()))
    return "completed", None, float(tr.max())


def stopped_at(out: Path) -> float | None:
    """The time at which the run stopped UNSTABLE, None when it completed."""
    s = json.loads((out / "summary.json").read_text())
    return float(s["time"]) if s.get("status") == "unstable" else None


def run_sets(dim: int, n: int, ca: float, t_end: float, skalak_c: float | None = None,
             width: float | None = None, reach: float = 5.0) -> dict:
    """The case keys of one run (also used to start a cached run by hand)."""
    sets = {**capsule_box_sets(dim, n), "body[0].elastic_modulus": repr(1.0 / ca),
            "time.end_time": repr(t_end), "output.fields_interval": "0.5",
            "output.checkpoint_every": "50", "output.progress_every": "100000",
            "case.description": repr(f"capsule in shear, {dim}D, Ca = {ca:g}, d/{n}")}
    if skalak_c is not None:
        sets["body[0].law"] = '"skalak"'
        sets["body[0].area_dilation"] = repr(skalak_c)
    if width is not None:  # None: the case's own width (cases/capsule_shear(_2d))
        sets["body[0].smoothing_width"] = repr(width)
    if reach != 5.0:
        sets["body[0].surface_velocity_reach"] = repr(reach)
    return sets


def run_dir(ctx, dim: int, n: int, ca: float, t_end: float, skalak_c: float | None = None,
            width: float | None = None, reach: float = 5.0) -> Path:
    law = "" if skalak_c is None else f"_skalak_C{skalak_c:g}"
    w = "" if width is None else f"_w{width:g}"
    r = "" if reach == 5.0 else f"_reach{reach:g}"
    return ctx.outdir / "runs" / f"{dim}d_n{n}{law}{w}{r}_ca{ca:g}_t{t_end:g}"


def series(out: Path):
    return body_series(out)


def cached(ctx, dim: int, n: int, ca: float, t_end: float, skalak_c: float | None = None,
           reach: float = 5.0) -> bool:
    return completed(run_dir(ctx, dim, n, ca, t_end, skalak_c, reach=reach),
                     allow_unstable=True)


def fig1d(data: Path, runs: list, png: Path) -> None:
    """D(t) of the 3D runs laid out like the seed's Fig. 1d."""
    import matplotlib.pyplot as plt

    cas = [0.0125, 0.025, 0.05, 0.1, 0.2]
    colour = dict(zip(cas, ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]))
    style = {16: "--", 32: "-", 64: ":"}
    fig, ax = plt.subplots(figsize=(7, 5.5))
    for ca in cas:
        for name, mk, fill in (("ramanujan_pozrikidis1998", "^", "none"),
                               ("pozrikidis1995", "o", colour[ca]),
                               ("eggleton_popel1998", "x", colour[ca])):
            f = data / f"{name}_ca{ca:g}.csv"
            if f.exists():
                pts = np.loadtxt(f, delimiter=",", ndmin=2)
                ax.plot(pts[:, 0], pts[:, 1], mk, ms=3.5, mfc=fill, color=colour[ca], alpha=0.6,
                        zorder=1)
    for n, ca, t, d in runs:
        ax.plot(t, d, style.get(n, "-."), color=colour.get(ca, "k"), lw=2, zorder=3)
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=colour[c], lw=2, label=f"Ca={c:g}") for c in cas]
    handles += [Line2D([], [], color="gray", marker="^", mfc="none", ls="",
                       label="Ramanujan & Pozrikidis 1998 (BEM)"),
                Line2D([], [], color="gray", marker="o", ls="", label="Pozrikidis 1995 (BEM)"),
                Line2D([], [], color="gray", marker="x", ls="", label="Eggleton & Popel 1998 (IB)")]
    handles += [Line2D([], [], color="k", ls=style[n], label=f"efsi, dx = d/{n}")
                for n in sorted({r[0] for r in runs})]
    ax.legend(handles=handles, fontsize=7, loc="lower right")
    ax.set(xlabel="shear rate x t", ylabel="D", xlim=(0, 2), ylim=(0, 0.6),
           title="capsule in shear (3D, Re = 0.01), layout of the seed's Fig. 1d")
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def run(ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = ctx.repo / "verification" / "data" / "capsule_shear"
    ref_2d = reference_2d(ctx.repo)
    t_end = T_END[ctx.tier]
    cached_only = os.environ.get("EFSI_VERIFY_CACHED_ONLY") == "1"
    metrics, rows, skipped, runs3d, runs_skalak = {}, [], [], [], []
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    plan = [(dim, n, ca, 5.0) for dim, n, cas in TIERS[ctx.tier] for ca in cas]
    plan += [(3, n, ca, reach) for n, ca, reach in REACH[ctx.tier]]
    for dim, n, ca, reach in plan:
        r = "" if reach == 5.0 else f", surface velocity reach {reach:g}"
        if cached_only and not cached(ctx, dim, n, ca, t_end, reach=reach):
            skipped.append(f"{dim}D d/{n} Ca {ca:g}{r}")
            continue
        out = run_one(ctx, dim, n, ca, t_end, reach=reach)
        t, d, th, vol = series(out)
        summary = json.loads((out / "summary.json").read_text())
        wall = summary["wall_seconds"]
        drift = float(abs(vol[-1] - vol[0]) / vol[0])
        unstable = stopped_at(out)
        # the membrane's health: 3 when unstrained, ~7 at the largest physical strains here;
        # the stiff-membrane growth of docs/method.md shows as 10^2..10^5
        stopped, invalid_after, max_tr = stop_note(out)
        row = {"dim": dim, "n": n, "Ca": ca, "surface_velocity_reach": reach,
               "D_t1": float(np.interp(1.0, t, d)) if t[-1] >= 1.0 else float("nan"),
               "D_end": float(d[-1]), "t_end": float(t[-1]), "stopped": stopped,
               "volume_drift": drift, "max_trace_Gs": max_tr,
               "wall_seconds": wall,
               # a resumed run's wall time is that of its last part only
               "resumed": bool(summary.get("restarted_from"))}
        tag = f"ca{ca:g}_n{4 * n}" + ("" if reach == 5.0 else f"_reach{reach:g}")
        if unstable is not None:
            metrics[f"unstable_at_t_{tag}"] = unstable
        elif invalid_after is not None:
            metrics[f"trace_bound_exceeded_at_t_{tag}"] = invalid_after
        if dim == 3:
            metrics[f"max_trace_Gs_{tag}"] = row["max_trace_Gs"]
        if dim == 3:
            name, ref = reference_curve(data, ca)
            if ref is not None:
                mask = window(t, ref)
                err = max_abs_diff(t, d, ref)
                metrics[f"max_abs_D_error_{tag}"] = err
                row["max_abs_D_error"] = err
                row["reference"] = name
                row["mean_D_minus_reference"] = float(np.mean(
                    d[mask] - np.interp(t[mask], ref[:, 0], ref[:, 1])))
                ax[0].plot(ref[:, 0], ref[:, 1], "o", ms=2.5, color="gray")
                # The other boundary-element curve, Pozrikidis (1995), over the same
                # interval: the spread of the two references is part of the uncertainty.
                p95 = read_curve(data / f"pozrikidis1995_ca{ca:g}.csv")
                if name != "pozrikidis1995" and p95 is not None:
                    m2 = mask & (t <= p95[-1, 0])
                    diff = np.abs(d[m2] - np.interp(t[m2], p95[:, 0], p95[:, 1]))
                    spread = np.abs(np.interp(t[m2], ref[:, 0], ref[:, 1]) -
                                    np.interp(t[m2], p95[:, 0], p95[:, 1]))
                    metrics[f"max_abs_D_diff_pozrikidis1995_{tag}"] = float(diff.max())
                    metrics[f"reference_spread_ca{ca:g}"] = float(spread.max())
                    row["max_abs_D_diff_pozrikidis1995"] = float(diff.max())
            metrics[f"volume_drift_{tag}"] = drift
            if not row["resumed"]:
                metrics[f"wall_seconds_{tag}"] = wall
            ax[0].plot(t, d, "-" if reach == 5.0 else ":", label=f"3D d/{n}, Ca={ca:g}{r}")
            if reach == 5.0:
                runs3d.append((n, ca, t, d))
        else:
            metrics[f"D2d_t1_{tag}"] = row["D_t1"]
            metrics[f"volume_drift_2d_{tag}"] = drift
            if ca in ref_2d and t[-1] >= 1.0:
                for k, v in ref_2d[ca].items():
                    metrics[f"D2d_t1_vs_{k}_rel_{tag}"] = row["D_t1"] / v - 1
            ax[1].plot(t, d, "-", label=f"2D d/{n}, Ca={ca:g}")
        rows.append(row)
    for ca, refs in ref_2d.items():
        ax[1].plot([1.0, 1.0], [refs["fe"], refs["bi"]], "ks", ms=4)
    ax[0].set(xlabel="shear rate x t", ylabel="D", title="3D (gray: Ramanujan & Pozrikidis / Pozrikidis)")
    ax[1].set(xlabel="shear rate x t", ylabel="D", title="2D (squares: FE and BI references at t = 1)")
    for a in ax:
        a.legend(fontsize=7)
    fig.tight_layout()
    png = ctx.outdir / "capsule_shear.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    figures = [str(png)]
    if runs3d:
        png1d = ctx.outdir / "capsule_fig1d.png"
        fig1d(data, runs3d, png1d)
        figures.insert(0, str(png1d))
    skalak_rows = []
    for n, ca, c, reach in SKALAK[ctx.tier]:
        if cached_only and not cached(ctx, 3, n, ca, t_end, c, reach):
            skipped.append(f"3D d/{n} Skalak C {c:g} Ca {ca:g} (surface velocity reach {reach:g})")
            continue
        out = run_one(ctx, 3, n, ca, t_end, skalak_c=c, reach=reach)
        t, d, th, vol = series(out)
        lin = skalak_linear_theory(ca, c)
        unstable = stopped_at(out)
        stopped, _, max_tr = stop_note(out)
        row = {"n": n, "Ca": ca, "C": c, "surface_velocity_reach": reach,
               "D_t1": at_or_nan(1.0, t, d), "D_end": float(d[-1]), "t_end": float(t[-1]),
               "stopped": stopped, "max_trace_Gs": max_tr,
               "D_linear_theory": lin,
               "D_end_over_linear": float(d[-1] / lin),
               "inclination_end_over_pi": float(th[-1]),
               "volume_drift": float(abs(vol[-1] - vol[0]) / vol[0]),
               "wall_seconds": json.loads((out / "summary.json").read_text())["wall_seconds"]}
        _, ref = reference_curve(data, 0.0125)  # same small-strain moduli when C = 1
        if ref is not None:
            row["max_abs_D_minus_pozrikidis1995_ca0.0125"] = max_abs_diff(t, d, ref)
        tag = f"skalak_C{c:g}_ca{ca:g}_n{4 * n}"
        if unstable is not None:
            metrics[f"unstable_at_t_{tag}"] = unstable
        metrics[f"D_end_{tag}"] = row["D_end"]
        if unstable is None:  # D at the stop of an UNSTABLE run is no steady value
            metrics[f"D_end_over_linear_theory_{tag}"] = row["D_end_over_linear"]
        metrics[f"volume_drift_{tag}"] = row["volume_drift"]
        skalak_rows.append(row)
        runs_skalak.append((c, t, d))
    if runs_skalak:
        png_sk = ctx.outdir / "capsule_skalak.png"
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        _, ref = reference_curve(data, 0.0125)
        if ref is not None:
            ax.plot(ref[:, 0], ref[:, 1], "ko", ms=3, mfc="none",
                    label="neo-Hookean Ca = 0.0125, Pozrikidis 1995 (same Gs, nu_s)")
        for c, t, d in runs_skalak:
            line, = ax.plot(t, d, "-", lw=2, label=f"efsi Skalak C = {c:g}, Ca = 0.025, d/16")
            ax.axhline(skalak_linear_theory(0.025, c), color=line.get_color(), ls=":",
                       label=f"small-deformation theory, C = {c:g}")
        for n, ca, t, d in runs3d:
            if ca == 0.0125:
                ax.plot(t, d, "k--", label=f"efsi neo-Hookean Ca = 0.0125, d/{n}")
        ax.set(xlabel="shear rate x t", ylabel="D", title="Skalak capsules in shear (3D, Re = 0.01)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(png_sk, dpi=120)
        plt.close(fig)
        figures.append(str(png_sk))
    wrows = width_sweep(ctx, data, t_end, cached_only, skipped, metrics, figures)
    notes = "Runs are cached per parameters under runs/ and resumed from checkpoints."
    if skipped:
        notes += " Not run (EFSI_VERIFY_CACHED_ONLY=1, no cached result): " + ", ".join(skipped) + "."
    from _flowio import USED_RECORDS
    if USED_RECORDS:
        notes += (" Taken from committed records (EFSI_VERIFY_RECORDS=1, verification/records/): "
                  + ", ".join(USED_RECORDS) + ".")
    return {"metrics": metrics, "tables": {"runs": rows, "skalak": skalak_rows,
                                           "interface_width": wrows,
                                           "not_run": [{"run": r} for r in skipped]},
            "figures": figures, "notes": notes}


def width_sweep(ctx, data: Path, t_end: float, cached_only: bool, skipped: list, metrics: dict,
                figures: list) -> list:
    """D(t) against the interface width eps = w h at fixed Ca: error per eps, the observed
    order in eps of D at t = 0.5, 1, 2 and the eps -> 0 (Richardson) estimate."""
    import matplotlib.pyplot as plt

    rows = []
    for ca, runs in WIDTH_SWEEP[ctx.tier]:
        name, ref = reference_curve(data, ca)
        p95 = read_curve(data / f"pozrikidis1995_ca{ca:g}.csv")
        curves = []
        for n, w in runs:
            if cached_only and not cached_w(ctx, n, ca, t_end, w):
                skipped.append(f"3D d/{n} w {w:g} Ca {ca:g}")
                continue
            out = run_one(ctx, 3, n, ca, t_end, width=w)
            t, d, th, vol = series(out)
            eps = w * 2.0 / n  # in units of the radius a = 1
            err = max_abs_diff(t, d, ref)
            unstable = stopped_at(out)
            stopped, _, max_tr = stop_note(out)
            row = {"n": n, "w": w, "eps_over_a": eps, "Ca": ca,
                   "D_t0.5": at_or_nan(0.5, t, d), "D_t1": at_or_nan(1.0, t, d),
                   "D_end": float(d[-1]), "t_end": float(t[-1]),
                   "stopped": stopped, "max_trace_Gs": max_tr,
                   "max_abs_D_error": err,
                   "volume_drift": float(abs(vol[-1] - vol[0]) / vol[0]),
                   "wall_seconds": json.loads((out / "summary.json").read_text())["wall_seconds"]}
            tag = f"ca{ca:g}_n{4 * n}_w{w:g}"
            if unstable is not None:
                metrics[f"unstable_at_t_{tag}"] = unstable
            metrics[f"max_abs_D_error_{tag}"] = err
            metrics[f"volume_drift_{tag}"] = row["volume_drift"]
            rows.append(row)
            curves.append((eps, n, w, t, d))
        # Observed order in eps at fixed h (one grid, widths w, w/2, w/4: the smallest three
        # at ratio 2) and the Richardson estimate of D at eps -> 0; and, at fixed eps, the
        # effect of h alone (the same eps on two grids).
        for n in sorted({c[1] for c in curves}):
            fam = sorted((c for c in curves if c[1] == n), key=lambda c: c[0])
            if len(fam) < 3 or any(abs(fam[i + 1][0] / fam[i][0] - 2) > 1e-9 for i in range(2)):
                continue
            for tq in (0.5, 1.0, t_end):
                v = [at_or_nan(tq, c[3], c[4]) for c in fam[:3]]
                # a run that stopped before tq (UNSTABLE) gives no value there
                if not np.all(np.isfinite(v)) or (v[2] - v[1]) * (v[1] - v[0]) <= 0:
                    continue
                p = float(np.log2((v[2] - v[1]) / (v[1] - v[0])))
                d0 = v[0] - (v[1] - v[0]) / (2 ** p - 1)
                tag = f"ca{ca:g}_n{4 * n}_t{tq:g}"
                metrics[f"D_eps_order_{tag}"] = p
                metrics[f"D_eps_extrapolated_{tag}"] = d0
                metrics[f"D_eps_extrapolated_minus_reference_{tag}"] = \
                    d0 - float(np.interp(tq, ref[:, 0], ref[:, 1]))
                if p95 is not None and tq <= p95[-1, 0]:
                    metrics[f"D_eps_extrapolated_minus_pozrikidis1995_{tag}"] = \
                        d0 - float(np.interp(tq, p95[:, 0], p95[:, 1]))
        for a in curves:
            for b in curves:
                if abs(a[0] - b[0]) < 1e-12 and b[1] == 2 * a[1]:
                    for tq in (0.5, 1.0, t_end):
                        diff = at_or_nan(tq, b[3], b[4]) - at_or_nan(tq, a[3], a[4])
                        if np.isfinite(diff):
                            metrics[f"D_h_effect_at_fixed_eps_ca{ca:g}_eps{a[0]:g}_t{tq:g}"] = diff
        if curves:
            png = ctx.outdir / f"capsule_width_ca{ca:g}.png"
            fig, ax = plt.subplots(1, 2, figsize=(11, 4.3))
            ax[0].plot(ref[:, 0], ref[:, 1], "k^", ms=4, mfc="none", label=name)
            if p95 is not None:
                ax[0].plot(p95[:, 0], p95[:, 1], "ko", ms=3, label="pozrikidis1995")
            for eps, n, w, t, d in sorted(curves, key=lambda c: (-c[0], c[1])):
                ax[0].plot(t, d, "-" if w == 1.0 else "--",
                           label=f"d/{n}, w = {w:g} (eps = {eps:g} a)")
                if t[-1] >= 1.0:
                    ax[1].plot(eps, float(np.interp(1.0, t, d)), "o" if w == 1.0 else "s")
            ax[1].axhline(float(np.interp(1.0, ref[:, 0], ref[:, 1])), color="k", ls=":",
                          label=f"{name}, t = 1")
            for k in [k for k in metrics if k.startswith(f"D_eps_extrapolated_ca{ca:g}_n")
                      and k.endswith("_t1")]:
                ax[1].plot([0.0], [metrics[k]], "k*", ms=10,
                           label=f"Richardson eps -> 0 ({k.split('_')[4]})")
            ax[0].set(xlabel="shear rate x t", ylabel="D",
                      title=f"3D capsule, Ca = {ca:g}: interface width eps = w h")
            ax[1].set(xlabel="eps / a", ylabel="D at shear rate x t = 1", xlim=(-0.02, None),
                      title="circles: w = 1, squares: other w")
            for a in ax:
                a.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(png, dpi=110)
            plt.close(fig)
            figures.append(str(png))
    return rows


def cached_w(ctx, n: int, ca: float, t_end: float, w: float) -> bool:
    return completed(run_dir(ctx, 3, n, ca, t_end, None, w), allow_unstable=True)


def at_or_nan(tq: float, t, d) -> float:
    """D at time tq, NaN when the run stopped (UNSTABLE) before tq."""
    return float(np.interp(tq, t, d)) if t[-1] >= tq - 1e-9 else float("nan")
