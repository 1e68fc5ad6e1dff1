"""Lid-driven cavity at Re = 100 and 1000 against the centreline tables of Ghia, Ghia & Shin
(1982): u along x = 0.5 (Table I) and v along y = 0.5 (Table II)."""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from _flowio import last_snapshot, read_snapshot, read_summary

from _bounds import Bound  # noqa: E402

DESCRIPTION = "efsi flow core: lid-driven cavity Re 100 / 1000 vs Ghia et al. (1982)"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"ghia_max_abs_[uv]_error_re100", "<=", 0.01,
          "centre-line velocities within 0.01 of Ghia et al. 1982 at Re 100"),
    Bound(r"ghia_max_abs_[uv]_error_re1000", "<=", 0.02,
          "centre-line velocities within 0.02 of Ghia et al. 1982 at Re 1000", tiers=("quick", "full")),
    Bound(r"ke_rel_change_last_chunk_re[0-9]+", "<=", 1e-5, "the run reached a steady state"),
]

# Grid per tier and Reynolds number (None: skipped in that tier).
GRIDS = {"ci": {100: 32, 1000: None}, "quick": {100: 64, 1000: 64},
         "full": {100: 128, 1000: 128}}
# Run to steady state in chunks (restarting from the checkpoint) until the relative change
# of the kinetic energy over one chunk falls below STEADY_TOL, or T_MAX is reached.
CHUNK = {100: 10.0, 1000: 25.0}
T_MAX = {100: 60.0, 1000: 400.0}
STEADY_TOL = 1e-5
CASES = {100: "cases/lid_cavity", 1000: "cases/lid_cavity_re1000"}


def read_ghia(repo: Path, re: int):
    path = repo / "cases" / "lid_cavity" / f"ghia1982_re{re}.csv"
    lines = [ln for ln in path.read_text().splitlines() if ln and not ln.startswith("#")]
    rows = list(csv.DictReader(lines))
    col = lambda k: np.array([float(r[k]) for r in rows])  # noqa: E731
    return col("y"), col("u"), col("x"), col("v")


def interp_cubic(xs: np.ndarray, ys: np.ndarray, xq: np.ndarray) -> np.ndarray:
    """Piecewise-cubic Lagrange interpolation on the 4 nearest samples (xs increasing).

    Fourth-order accurate, so the interpolation adds nothing visible to the O(h^2) error
    of the solution itself (linear interpolation would add an O(h^2) term of its own)."""
    out = np.empty_like(xq, dtype=float)
    n = len(xs)
    for q, x in enumerate(xq):
        i = int(np.clip(np.searchsorted(xs, x) - 2, 0, n - 4))
        xx, yy = xs[i:i + 4], ys[i:i + 4]
        val = 0.0
        for a in range(4):
            w = 1.0
            for b in range(4):
                if b != a:
                    w *= (x - xx[b]) / (xx[a] - xx[b])
            val += w * yy[a]
        out[q] = val
    return out


def centrelines(snap: dict, n: int, lid: float = 1.0):
    """u(y) on x = 0.5 and v(x) on y = 0.5 from the raw staggered faces, with wall values.

    u faces sit at x = i h, y = (j + 1/2) h: with n even, face i = n/2 is exactly x = 0.5.
    v faces sit at x = (i + 1/2) h, y = j h: face j = n/2 is exactly y = 0.5."""
    h = 1.0 / n
    centres = (np.arange(n) + 0.5) * h
    u = snap["u"][0][:, n // 2]
    v = snap["v"][0][n // 2, :]
    y = np.concatenate([[0.0], centres, [1.0]])
    x = np.concatenate([[0.0], centres, [1.0]])
    return y, np.concatenate([[0.0], u, [lid]]), x, np.concatenate([[0.0], v, [0.0]])


def kinetic_energy_history(run_dirs: list[Path]):
    """Time and KE from the chunks' diagnostics.csv. A restarted run's file may lack the
    header row (solver behaviour at the time of writing), so the first chunk's header is
    used for all of them."""
    header = None
    t, ke = [], []
    for d in run_dirs:
        lines = (d / "diagnostics.csv").read_text().splitlines()
        if lines and lines[0].startswith("step"):
            header, lines = lines[0].split(","), lines[1:]
        it, ik = header.index("time"), header.index("kinetic_energy")
        for ln in lines:
            f = ln.split(",")
            if len(f) == len(header):
                t.append(float(f[it]))
                ke.append(float(f[ik]))
    return np.array(t), np.array(ke)


def run_to_steady(ctx, re: int, n: int):
    """Chunked run with restarts; returns the chunk directories and the steadiness record."""
    sets = {"grid.cells": f"[{n},{n},1]", "grid.length": f"[1.0,1.0,{1.0 / n!r}]",
            "output.fields_interval": "0", "output.progress_every": "100000000",
            "output.diagnostics_every": "50"}
    dirs, t_end, ke_prev, rel = [], 0.0, None, None
    while True:
        t_end += CHUNK[re]
        out = ctx.outdir / f"re{re}_n{n}" / f"t{t_end:07.1f}"
        extra = ["--restart", str(dirs[-1] / "checkpoint.h5")] if dirs else []
        summ = ctx.run_efsi(CASES[re], out, sets={**sets, "time.end_time": repr(t_end)},
                            extra=extra)
        if summ.get("status") != "completed":
            raise RuntimeError(f"Re {re}: run ended with {summ.get('status')}: "
                               f"{summ.get('message')}")
        dirs.append(out)
        ke = summ["final"]["kinetic_energy"]
        if ke_prev is not None:
            rel = abs(ke - ke_prev) / ke
            if rel < STEADY_TOL or t_end >= T_MAX[re] - 1e-9:
                break
        ke_prev = ke
    return dirs, {"end_time": t_end, "ke_rel_change_last_chunk": rel, "chunk": CHUNK[re],
                  "steady": bool(rel is not None and rel < STEADY_TOL),
                  "final_max_divergence": summ["final"]["max_divergence"]}


def run(ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    metrics, tables, figs, notes = {}, {}, [], []
    res_list = [re for re in (100, 1000) if GRIDS[ctx.tier][re]]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    colours = {100: "tab:blue", 1000: "tab:red"}
    for re in res_list:
        n = GRIDS[ctx.tier][re]
        dirs, steady = run_to_steady(ctx, re, n)
        summ = read_summary(dirs[-1])
        snap = read_snapshot(last_snapshot(dirs[-1]))
        y, u, x, v = centrelines(snap, n)
        gy, gu, gx, gv = read_ghia(ctx.repo, re)
        ou = np.argsort(gy)
        ov = np.argsort(gx)
        gy, gu, gx, gv = gy[ou], gu[ou], gx[ov], gv[ov]
        u_at = interp_cubic(y, u, gy)
        v_at = interp_cubic(x, v, gx)
        du, dv = u_at - gu, v_at - gv
        metrics[f"ghia_max_abs_u_error_re{re}"] = float(np.abs(du).max())
        metrics[f"ghia_max_abs_v_error_re{re}"] = float(np.abs(dv).max())
        metrics[f"ghia_rms_u_error_re{re}"] = float(np.sqrt(np.mean(du[1:-1] ** 2)))
        metrics[f"ghia_rms_v_error_re{re}"] = float(np.sqrt(np.mean(dv[1:-1] ** 2)))
        metrics[f"grid_re{re}"] = n
        metrics[f"end_time_re{re}"] = steady["end_time"]
        metrics[f"ke_rel_change_last_chunk_re{re}"] = steady["ke_rel_change_last_chunk"]
        # Extremes, the quantities usually quoted (Ghia: u_min on x = 0.5, v_max/v_min on y = 0.5).
        fine = np.linspace(0, 1, 2001)
        uf, vf = interp_cubic(y, u, fine), interp_cubic(x, v, fine)
        metrics[f"u_min_re{re}"] = float(uf.min())
        metrics[f"v_max_re{re}"] = float(vf.max())
        metrics[f"v_min_re{re}"] = float(vf.min())
        tables[f"re{re}_u_x0.5"] = [{"y": float(a), "ghia_u": float(b), "efsi_u": float(c),
                                     "diff": float(c - b)} for a, b, c in zip(gy, gu, u_at)]
        tables[f"re{re}_v_y0.5"] = [{"x": float(a), "ghia_v": float(b), "efsi_v": float(c),
                                     "diff": float(c - b)} for a, b, c in zip(gx, gv, v_at)]
        tables[f"re{re}_steady"] = {**steady, "chunks": len(dirs),
                                     "steps": summ["final"]["step"]}
        t, ke = kinetic_energy_history(dirs)
        tables[f"re{re}_ke_history"] = {"time": t[::max(1, len(t) // 200)].tolist(),
                                        "ke": ke[::max(1, len(t) // 200)].tolist()}
        c = colours[re]
        axes[0].plot(u, y, "-", color=c, label=f"efsi Re {re}, {n}$^2$")
        axes[0].plot(gu, gy, "o", mfc="none", color=c, label=f"Ghia et al. Re {re}")
        axes[1].plot(x, v, "-", color=c, label=f"efsi Re {re}, {n}$^2$")
        axes[1].plot(gx, gv, "o", mfc="none", color=c, label=f"Ghia et al. Re {re}")
        notes.append(f"Re {re}: {n}x{n} cells, steady by t = {steady['end_time']:g} "
                     f"(relative KE change over the last {CHUNK[re]:g} time units "
                     f"{steady['ke_rel_change_last_chunk']:.1e}); max |u - u_Ghia| = "
                     f"{metrics[f'ghia_max_abs_u_error_re{re}']:.4f}, max |v - v_Ghia| = "
                     f"{metrics[f'ghia_max_abs_v_error_re{re}']:.4f}.")
    axes[0].set_xlabel("u / U  on x = 0.5")
    axes[0].set_ylabel("y / L")
    axes[1].set_xlabel("x / L")
    axes[1].set_ylabel("v / U  on y = 0.5")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Lid-driven cavity: centreline velocities vs Ghia, Ghia & Shin (1982)")
    fig.tight_layout()
    png = ctx.outdir / "lid_cavity_ghia.png"
    fig.savefig(png, dpi=120)
    plt.close(fig)
    figs.append(str(png))

    # KE history figure (steady-state monitor).
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    for re in res_list:
        h = tables[f"re{re}_ke_history"]
        ax.plot(h["time"], h["ke"], color=colours[re], label=f"Re {re}")
    ax.set_xlabel("t U / L")
    ax.set_ylabel("kinetic energy")
    ax.legend()
    fig.tight_layout()
    png2 = ctx.outdir / "lid_cavity_ke.png"
    fig.savefig(png2, dpi=120)
    plt.close(fig)
    figs.append(str(png2))

    notes_text = (
        "Unit square, lid u = 1 at y = 1, no-slip elsewhere, Re = U L / nu; CN viscous, AB2 "
        "central advection, adaptive dt (CFL 0.5). Run to steady state in chunks with restarts "
        f"until the kinetic energy changes by less than {STEADY_TOL:g} (relative) over one chunk. "
        "The centreline profiles are taken from the raw staggered faces (u faces lie exactly on "
        "x = 0.5, v faces exactly on y = 0.5 for even N), completed with the wall values, and "
        "interpolated to Ghia's 17 points with 4-point cubic Lagrange interpolation; the errors "
        "are the maximum absolute differences at those points, in units of the lid speed. "
        "Ghia's data are themselves a 129x129 second-order multigrid solution (quoted to 5 "
        "digits), so differences of order 1e-3 are at the level of the reference. "
        + " ".join(notes))
    if 1000 not in res_list:
        notes_text += " Re 1000 is skipped in the ci tier (long transient)."
    return {"metrics": metrics, "figures": figs, "tables": tables, "notes": notes_text}
