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
import csv
import json
import os
from pathlib import Path

import numpy as np

DESCRIPTION = "capsule in shear: D(t) vs Ramanujan & Pozrikidis / Pozrikidis, volume drift, cost"

# (dimension, cells per diameter, Ca list) per tier.
TIERS = {
    "ci": [(2, 8, [0.2])],
    "quick": [(2, 16, [0.05, 0.2]), (3, 16, [0.2])],
    "full": [(2, 16, [0.05, 0.2]), (2, 32, [0.05, 0.2]),
             (3, 16, [0.0125, 0.025, 0.05, 0.1, 0.2]), (3, 32, [0.05, 0.2])],
}
T_END = {"ci": 1.0, "quick": 2.0, "full": 2.0}
# Independent 2D references at shear-rate x t = 1 (reference/README.md): FE d/16, BI N=128.
REF_2D = {0.05: {"fe": 0.3471, "bi": 0.3395}, 0.2: {"fe": 0.4161, "bi": 0.4116}}


def reference_curve(data: Path, ca: float):
    name = "pozrikidis1995" if ca == 0.0125 else "ramanujan_pozrikidis1998"
    f = data / f"{name}_ca{ca:g}.csv"
    if not f.exists():
        return None, None
    pts = np.array(sorted(tuple(map(float, line.split(","))) for line in f.read_text().split()))
    return name, pts


def run_one(ctx, dim: int, n: int, ca: float, t_end: float) -> Path:
    key = f"{dim}d_n{n}_ca{ca:g}_t{t_end:g}"
    out = ctx.outdir / "runs" / key
    summary = out / "summary.json"
    if summary.exists():
        s = json.loads(summary.read_text())
        if s.get("status") == "completed" and abs(s["time"] - t_end) < 1e-9:
            return out  # cached
    case = ctx.repo / "cases" / ("capsule_shear" if dim == 3 else "capsule_shear_2d")
    cells = 4 * n
    h = 8.0 / cells
    sets = {"grid.cells": f"[{cells},{cells},{cells if dim == 3 else 1}]",
            "grid.length": f"[8.0,8.0,{8.0 if dim == 3 else h!r}]",
            "grid.origin": f"[-4.0,-4.0,{-4.0 if dim == 3 else -h / 2!r}]",
            "body[0].elastic_modulus": repr(1.0 / ca), "time.end_time": repr(t_end),
            "output.fields_interval": "0.5", "output.checkpoint_every": "50",
            "output.progress_every": "100000",
            "case.description": repr(f"capsule in shear, {dim}D, Ca = {ca:g}, d/{n}")}
    extra = []
    if (out / "checkpoint.h5").exists():
        extra = ["--restart", str(out / "checkpoint.h5")]  # resume a cut-short run
    ctx.run_efsi(case, out, sets=sets, extra=extra, ranks=ctx.long_ranks if dim == 3 else 1)
    return out


def series(out: Path):
    with open(out / "bodies.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["body"] == "capsule"]
    t = np.array([float(r["time"]) for r in rows])
    order = np.argsort(t, kind="stable")
    col = lambda k: np.array([float(r[k]) for r in rows])[order]  # noqa: E731
    return t[order], col("taylor_deformation"), col("inclination_over_pi"), col("volume")


def cached(ctx, dim: int, n: int, ca: float, t_end: float) -> bool:
    s = ctx.outdir / "runs" / f"{dim}d_n{n}_ca{ca:g}_t{t_end:g}" / "summary.json"
    return s.exists() and json.loads(s.read_text()).get("status") == "completed"


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

    data = ctx.repo.parent / "shared" / "data" / "capsule_shear"
    t_end = T_END[ctx.tier]
    cached_only = os.environ.get("EFSI_VERIFY_CACHED_ONLY") == "1"
    metrics, rows, skipped, runs3d = {}, [], [], []
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for dim, n, cas in TIERS[ctx.tier]:
        for ca in cas:
            if cached_only and not cached(ctx, dim, n, ca, t_end):
                skipped.append(f"{dim}D d/{n} Ca {ca:g}")
                continue
            out = run_one(ctx, dim, n, ca, t_end)
            t, d, th, vol = series(out)
            wall = json.loads((out / "summary.json").read_text())["wall_seconds"]
            drift = float(abs(vol[-1] - vol[0]) / vol[0])
            row = {"dim": dim, "n": n, "Ca": ca, "D_t1": float(np.interp(1.0, t, d)),
                   "D_end": float(d[-1]), "volume_drift": drift, "wall_seconds": wall}
            tag = f"ca{ca:g}_n{4 * n}"
            if dim == 3:
                name, ref = reference_curve(data, ca)
                if ref is not None:
                    lo, hi = max(0.2, ref[0, 0]), min(2.0, ref[-1, 0], t[-1])
                    mask = (t >= lo) & (t <= hi)
                    err = float(np.max(np.abs(d[mask] - np.interp(t[mask], ref[:, 0], ref[:, 1]))))
                    metrics[f"max_abs_D_error_{tag}"] = err
                    row["max_abs_D_error"] = err
                    row["reference"] = name
                    ax[0].plot(ref[:, 0], ref[:, 1], "o", ms=2.5, color="gray")
                metrics[f"volume_drift_{tag}"] = drift
                metrics[f"wall_seconds_{tag}"] = wall
                ax[0].plot(t, d, "-", label=f"3D d/{n}, Ca={ca:g}")
                runs3d.append((n, ca, t, d))
            else:
                metrics[f"D2d_t1_{tag}"] = row["D_t1"]
                metrics[f"volume_drift_2d_{tag}"] = drift
                if ca in REF_2D and t[-1] >= 1.0:
                    for k, v in REF_2D[ca].items():
                        metrics[f"D2d_t1_vs_{k}_rel_{tag}"] = row["D_t1"] / v - 1
                ax[1].plot(t, d, "-", label=f"2D d/{n}, Ca={ca:g}")
            rows.append(row)
    for ca, refs in REF_2D.items():
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
    notes = "Runs are cached per parameters under runs/ and resumed from checkpoints."
    if skipped:
        notes += " Not run (EFSI_VERIFY_CACHED_ONLY=1, no cached result): " + ", ".join(skipped) + "."
    return {"metrics": metrics, "tables": {"runs": rows, "not_run": [{"run": r} for r in skipped]},
            "figures": figures, "notes": notes}
