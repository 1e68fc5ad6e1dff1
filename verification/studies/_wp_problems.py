"""Work-precision study, the problems: one runner per problem (flow_mms, vof, slab,
capsule_2d, capsule_3d), each solving it with every available solver at several resolutions
and returning its series of timed runs (error, wall and solver time), and their helpers."""
from __future__ import annotations

import json
import math
import os
import re
import sys
import time
from pathlib import Path

import numpy as np

SHORT_RUN = 20.0   # seconds: runs shorter than this are repeated once (not in the ci tier,
#                    whose timings only exercise the code), the minimum is kept
SLAB_WIDTH = 1.0 / 16
SLAB_T_END = 2.0
CAPSULE_CA = 0.05



def fe_3d_measured(repo: Path) -> dict | None:
    """The 3D Eulerian FE capsule (reference/vesicle_shear_3d.py, h = d/8, 1 rank) as the
    stored full tier of `reference_vesicle` measured it (a 15-30 min run, not repeated
    here): its Ca, wall time and D at its sample times, or None when no result is stored."""
    f = repo / "verification" / "results" / "reference_vesicle" / "result.json"
    if not f.exists():
        return None
    res = json.loads(f.read_text())
    m = res.get("metrics", {})
    walls = [k for k in m if re.fullmatch(r"fe3d_wall_seconds_ca[0-9.]+", k)]
    if not walls:
        return None
    ca = float(walls[0].rsplit("_ca", 1)[1])
    d = {float(k.split("_t")[-1]): v for k, v in m.items()
         if re.fullmatch(rf"fe3d_D_ca{ca:g}_t[0-9.]+", k)}
    commit = (res.get("versions") or {}).get("git", "")[:10]
    return {"Ca": ca, "h": f"d/{1 / m.get(f'fe3d_h_over_d_ca{ca:g}', 0.125):.0f}",
            "wall_seconds": m[walls[0]], "D": dict(sorted(d.items())),
            "source": f"verification/results/reference_vesicle (measured, commit {commit}, "
                      f"{res.get('stored', '')})"}


# ----------------------------------------------------------------- running and timing
def timed(ctx, cmd, ranks=1, read=None, repeat=True, check=True):
    """Run ``cmd`` (once more if it was short and ``repeat``), timing the whole process.
    ``read(completed_process)`` (called after each run) returns the run's data dict with
    its ``solver_seconds``; the data of the fastest repeat is returned, with the process
    wall time (minimum), every repeat's time and the 1-minute load average before each."""
    runs = []
    while True:
        load = os.getloadavg()
        t0 = time.perf_counter()
        res = ctx.run(cmd, ranks=ranks, check=check)
        wall = time.perf_counter() - t0
        data = read(res) if read else {}
        runs.append((wall, load, data))
        if not repeat or ctx.tier == "ci" or wall > SHORT_RUN or len(runs) == 2:
            break
    best = min(runs, key=lambda r: r[0])
    out = dict(best[2])
    out.update(wall_seconds=best[0], walls=[r[0] for r in runs],
               loadavg_1min=[round(r[1][0], 2) for r in runs], ranks=ranks)
    if "solver_seconds" in best[2]:
        out["solver_seconds"] = min(r[2]["solver_seconds"] for r in runs)
    return out


def efsi_cmd(ctx, case, out, sets):
    cmd = [ctx.efsi, "run", case, "--output", out, "--quiet"]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    return cmd


PRESSURE_CAP = 500   # solver.pressure.max_iterations default (docs/case-reference.md)


def pressure_cap_rows(out):
    """Rows of an efsi run's diagnostics.csv in which the pressure solve hit its iteration
    cap (the solve stopped unconverged), and the number of rows."""
    import csv
    with open(Path(out) / "diagnostics.csv") as f:
        its = [int(r["pressure_iterations"]) for r in csv.DictReader(f) if int(r["step"]) > 0]
    return {"pressure_cap_rows": sum(i >= PRESSURE_CAP for i in its), "diagnostic_rows": len(its)}


# ----------------------------------------------------------------- flow MMS (Taylor-Green)
def flow_mms(ctx, cfg):
    import flow_mms as fm
    from _flowio import last_snapshot, read_snapshot, read_summary

    base = ctx.outdir / "flow_mms"
    L, T = fm.L, fm.T_END

    def cpp(N, ranks, fixed_dt):
        out = base / f"cpp_r{ranks}_N{N}{'' if fixed_dt else '_auto_dt'}"
        h = L / N
        sets = {"grid.cells": f"[{N},{N},1]", "grid.length": f"[{L!r},{L!r},{h!r}]",
                "time.end_time": repr(T), "output.fields_interval": "0",
                "output.progress_every": "1000000"}
        if fixed_dt:   # exactly flow_mms.py's settings
            steps = fm.steps_for(N)
            sets.update({"time.dt": repr(T / steps), "time.viscous": "crank_nicolson",
                         "output.diagnostics_every": str(max(1, steps // 10)),
                         "solver.pressure.tolerance": "1e-12",
                         "solver.viscous.tolerance": "1e-13"})

        def read(_res):
            snap, summ = read_snapshot(last_snapshot(out)), read_summary(out)
            assert abs(snap["time"] - T) < 1e-9 * T, snap["time"]
            ue, ve, _ = fm.exact(snap["time"], N)
            eu, ev = snap["u"][0] - ue, snap["v"][0] - ve
            return {"N": N, "steps": summ["steps"], "solver_seconds": summ["wall_seconds"],
                    "error": float(np.sqrt(np.mean(eu * eu) + np.mean(ev * ev))),
                    **pressure_cap_rows(out)}
        return timed(ctx, efsi_cmd(ctx, fm.CASE, out, sets), ranks, read)

    def fe(N):
        out = base / f"fe_N{N}"

        def read(_res):
            r = json.loads((out / "mms_taylor-green.json").read_text())["rows"][0]
            return {"N": N, "steps": r["steps"], "dofs": r["dofs"],
                    "solver_seconds": r["solve_seconds"], "error": r["err_u_rms"],
                    "error_nodes_rms": r["err_u_nodes_rms"]}
        cmd = [ctx.python, ctx.repo / "reference" / "flow_mms.py", "--equations", "taylor-green",
               "--N", N, "--out", out]
        return timed(ctx, cmd, 1, read)

    series = {"efsi 1 rank": [cpp(N, 1, True) for N in cfg["cpp"]],
              "efsi 2 ranks": [cpp(N, 2, True) for N in cfg["cpp_2ranks"]],
              "FE (Taylor-Hood) 1 rank": [fe(N) for N in cfg["fe"]]}
    if cfg["cpp_auto_dt"]:
        series["efsi 1 rank, automatic dt"] = [cpp(N, 1, False) for N in cfg["cpp_auto_dt"]]
    return {"series": series, "error": "RMS velocity error at t = 1 vs the exact solution",
            "resolution": "N (cells per side; FE: N x N x 2 triangles)"}


# ----------------------------------------------------------------- VOF single vortex
def vof(ctx, cfg):
    binary = ctx.efsi.parent / "efsi_vof_study"

    def read(res):   # efsi_vof_study prints one JSON line on stdout
        r = json.loads([ln for ln in res.stdout.splitlines() if ln.startswith("{")][-1])
        return {"n": r["n"], "error": r["shape_error"], "volume_error": r["volume_error"],
                "steps": r["steps"], "solver_seconds": r["wall_time"]}

    cmd = lambda n: [binary, "single_vortex", "--n", n, "--scheme", "mthinc"]  # noqa: E731
    series = {"efsi 1 rank": [timed(ctx, cmd(n), 1, read) for n in cfg["cpp"]],
              "efsi 2 ranks": [timed(ctx, cmd(n), 2, read) for n in cfg["cpp_2ranks"]]}
    return {"series": series, "error": "shape error sum |phi(T) - phi(0)| dV, T = 8",
            "resolution": "n (cells across the unit box)"}


# ----------------------------------------------------------------- parallel slab
def p2_eval(y_nodes, values, y):
    """Evaluate a 1D P2 finite-element function given at its sorted nodes (vertex, midpoint,
    vertex, ...) at the points y (quadratic Lagrange interpolation on each element)."""
    yv, yn, v = np.asarray(y_nodes), np.asarray(y, float), np.asarray(values)
    verts = yv[::2]
    k = np.clip(np.searchsorted(verts, yn, side="right") - 1, 0, len(verts) - 2)
    a, m, b = yv[2 * k], yv[2 * k + 1], yv[2 * k + 2]
    fa, fm, fb = v[2 * k], v[2 * k + 1], v[2 * k + 2]
    return (fa * (yn - m) * (yn - b) / ((a - m) * (a - b))
            + fm * (yn - a) * (yn - b) / ((m - a) * (m - b))
            + fb * (yn - a) * (yn - m) / ((b - a) * (b - m)))


def slab(ctx, cfg):
    sys.path.insert(0, str(ctx.repo / "reference"))
    import parallel_slab as pstudy
    import parallel_slab_1d as ps

    base_case = (ctx.repo / "cases" / "parallel_slab" / "case.toml").read_text()
    base = ctx.outdir / "slab"
    base.mkdir(parents=True, exist_ok=True)
    problems = {}
    for smooth in (True, False):
        label = "smooth" if smooth else "sharp"
        profile = "tanh" if smooth else "sharp"
        p = dict(ps.DEFAULTS)
        p.update(mode="oscillating", profile=profile, width=SLAB_WIDTH, N=512, dt=5e-4,
                 t_end=SLAB_T_END, times=[SLAB_T_END])
        ref = ps.solve(p)
        yr, ur = np.asarray(ref["y"]), np.asarray(ref["u"])[-1]
        yfine = (np.arange(4096) + 0.5) / 4096
        ufine = p2_eval(yr, ur, yfine)

        def rel_l2(y, u):
            ue = p2_eval(yr, ur, y)
            return float(math.sqrt(np.mean((u - ue) ** 2) / np.mean(ue ** 2)))

        def cpp(n, ranks):
            case = base / f"{label}_{n}.toml"
            case.write_text(pstudy.case_text(base_case, n, smooth))
            out = base / f"cpp_{label}_r{ranks}_{n}"

            def read(_res):
                t, u, _, _ = pstudy.read_last(out)
                assert abs(t - SLAB_T_END) < 1e-9, t
                summ = json.loads((out / "summary.json").read_text())
                return {"n": n, "error": rel_l2((np.arange(n) + 0.5) / n, u),
                        "solver_seconds": summ["wall_seconds"], "steps": summ["steps"],
                        "pressure_solve_seconds": summ["stages"]["pressure_solve"],
                        **pressure_cap_rows(out)}
            return timed(ctx, efsi_cmd(ctx, case, out, {"output.progress_every": 100000}),
                         ranks, read)

        def fe(n):
            out = base / f"fe_{label}_{n}"
            dt = 0.1 / n

            def read(_res):
                r = json.loads((out / f"slab_oscillating_{profile}_N{n}.json").read_text())
                assert abs(r["t"][-1] - SLAB_T_END) < 1e-9
                # the FE function itself (P2 interpolation of its nodes), on the fine points
                u = p2_eval(r["y"], r["u"][-1], yfine)
                err = float(math.sqrt(np.mean((u - ufine) ** 2) / np.mean(ufine ** 2)))
                return {"n": n, "dt": r["dt"], "error": err, "solver_seconds": r["wall_seconds"]}
            cmd = [ctx.python, ctx.repo / "reference" / "parallel_slab_1d.py", "run",
                   "--mode", "oscillating", "--profile", profile, "--width", SLAB_WIDTH,
                   "--N", n, "--dt", dt, "--t-end", SLAB_T_END, "--times", SLAB_T_END,
                   "--out", out]
            return timed(ctx, cmd, 1, read)

        series = {"efsi 1 rank": [cpp(n, 1) for n in cfg["cpp"]]}
        if smooth:
            series["efsi 2 ranks"] = [cpp(n, 2) for n in cfg["cpp_2ranks"]]
        series["FE 1D (P2, CN) 1 rank"] = [fe(n) for n in cfg["fe"]]
        name = "parallel_slab" if smooth else "parallel_slab_sharp"
        problems[name] = {"series": series,
                          "error": f"relative L2 error of u(y, t = 2), {label} layer",
                          "resolution": "cells (efsi) / elements (FE) across the channel"}
    return problems


# ----------------------------------------------------------------- 2D capsule
def capsule_2d(ctx, cfg):
    import capsule_shear as cs

    base = ctx.outdir / "capsule_2d"
    env_threads = os.environ.setdefault("OMP_NUM_THREADS", "1")
    bi_out = base / "bi"
    bi_cmd = [ctx.python, ctx.repo / "reference" / "capsule_bi_2d.py", "--Ca", CAPSULE_CA,
              "--N", *cfg["bi_N"], "--t-end", 1.0, "--out", bi_out]
    t0 = time.perf_counter()
    ctx.run(bi_cmd)
    bi_wall = time.perf_counter() - t0
    bi = sorted(json.loads((bi_out / "bi_summary.json").read_text()), key=lambda s: s["N"])
    d_ref = bi[-1]["D_final"]
    reference = {"D_BI_t1": d_ref, "N": bi[-1]["N"], "D_BI_coarser": bi[-2]["D_final"],
                 "N_coarser": bi[-2]["N"], "bi_change": abs(d_ref - bi[-2]["D_final"]),
                 "bi_wall_seconds": bi_wall, "omp_threads": env_threads}

    def cpp(n, ranks):
        out = base / f"cpp_r{ranks}_n{n}"
        cells = 4 * n
        h = 8.0 / cells
        sets = {"grid.cells": f"[{cells},{cells},1]", "grid.length": f"[8.0,8.0,{h!r}]",
                "grid.origin": f"[-4.0,-4.0,{-h / 2!r}]",
                "body[0].elastic_modulus": repr(1.0 / CAPSULE_CA), "time.end_time": "1.0",
                "output.fields_interval": "0", "output.progress_every": "100000"}

        def read(_res):
            t, d, _, _ = cs.series(out)
            summ = json.loads((out / "summary.json").read_text())
            assert abs(t[-1] - 1.0) < 1e-9, t[-1]
            D1 = float(np.interp(1.0, t, d))
            return {"n": n, "D_t1": D1, "error": abs(D1 - d_ref),
                    "solver_seconds": summ["wall_seconds"], "steps": summ["steps"],
                    **pressure_cap_rows(out)}
        return timed(ctx, efsi_cmd(ctx, ctx.repo / "cases" / "capsule_shear_2d", out, sets),
                     ranks, read)

    def fe(refine):
        out = base / f"fe_r{refine}"

        def read(res):
            # exit 3: the FE run diverged before t = 1 (a result: no error value, where)
            if res.returncode not in (0, 3):
                raise RuntimeError(f"FE capsule refine {refine} failed ({res.returncode}): "
                                   f"{(res.stderr or '')[-2000:]}")
            s = json.loads((out / f"capsule_ca{CAPSULE_CA:g}_r{refine}.json").read_text())
            row = {"n": round(1 / s["h_over_d"]), "refine": refine,
                   "solver_seconds": s["wall_seconds"], "steps": s["steps"]}
            if s.get("status", "completed") == "diverged":
                return {**row, "D_t1": None, "error": None, "diverged_at": s["diverged_at"]}
            return {**row, "D_t1": s["D_final"], "error": abs(s["D_final"] - d_ref)}
        cmd = [ctx.python, ctx.repo / "reference" / "vesicle_shear_2d.py", "--Ca", CAPSULE_CA,
               "--h-far", 0.5, "--refine", refine, "--Lx", 16.0, "--Ly", 8.0, "--t-end", 1.0,
               "--out", out]
        return timed(ctx, cmd, 1, read, check=False)

    series = {"efsi 1 rank": [cpp(n, 1) for n in cfg["cpp"]],
              "efsi 2 ranks": [cpp(n, 2) for n in cfg["cpp_2ranks"]],
              "FE (Eulerian, P2/P1) 1 rank": [fe(r) for r in cfg["fe_refine"]]}
    return {"series": series, "reference": reference,
            "error": f"|D(1) - D_BI(1)|, Ca {CAPSULE_CA}, D_BI = {d_ref:.5f} (boundary "
                     f"integral N = {bi[-1]['N']})",
            "resolution": "cells per diameter d/h"}


# ----------------------------------------------------------------- 3D capsule
def capsule_3d(ctx, cfg):
    import capsule_shear as cs

    data = ctx.repo / "verification" / "data" / "capsule_shear"
    cache = ctx.repo / "build" / "verification" / "capsule_shear" / "runs"
    fe3d = fe_3d_measured(ctx.repo)
    fe3d_times = list(fe3d["D"]) if fe3d else []

    def measure(out, ca):
        t, d, _, _ = cs.series(out)
        name, ref = cs.reference_curve(data, ca)
        if ref is None:
            return None
        lo, hi = max(0.2, ref[0, 0]), min(2.0, ref[-1, 0], t[-1])
        mask = (t >= lo) & (t <= hi)
        dref = lambda tt: np.interp(tt, ref[:, 0], ref[:, 1])  # noqa: E731
        err = float(np.max(np.abs(d[mask] - dref(t[mask]))))
        # at the FE run's sample times (for the like-for-like comparison with it)
        at = {T: float(abs(np.interp(T, t, d) - dref(T))) for T in fe3d_times
              if T <= t[-1]}
        return {"error": err, "error_at_fe_times": max(at.values()) if at else None,
                "reference": name, "t_end": float(t[-1])}

    series, skipped = {}, []
    # cached runs of the capsule_shear study (their own timer; d/16 ran on 1 rank, d/32 on
    # EFSI_VERIFY_RANKS: every row keeps its rank count). Series "efsi, Ca x" holds them and
    # the d/8 1-rank runs made here; "efsi 2 ranks, Ca 0.2" the d/8 2-rank runs.
    # With EFSI_VERIFY_RECORDS=1 (or only) the committed records of those runs count too (a
    # fresh build/ has no cache): completed() copies a finished record into the cache.
    from _flowio import RECORDS, completed, record_dir, records_mode

    names = {p.name for p in cache.glob("3d_n*_ca*_t2")}
    if records_mode() in ("1", "only"):
        names |= {p.name for p in (RECORDS / "capsule_shear").glob("3d_n*_ca*_t2")}
    for name in sorted(names):
        # the neo-Hookean runs at the default width only (not the Skalak or width sweeps)
        key = re.fullmatch(r"3d_n(\d+)_ca([0-9.]+)_t2", name)
        if key is None:
            continue
        run = cache / name
        completed(run, 2.0)
        sfile = run / "summary.json"
        if not sfile.exists():
            skipped.append(f"{run.name}: not finished")
            continue
        s = json.loads(sfile.read_text())
        if s.get("status") != "completed" or abs(s["time"] - 2.0) > 1e-9:
            skipped.append(f"{run.name}: status {s.get('status')}")
            continue
        if s.get("restarted_from"):
            skipped.append(f"{run.name}: resumed from a checkpoint, wall time incomplete")
            continue
        n, ca = int(key.group(1)), float(key.group(2))
        m = measure(run, ca)
        if m is None:
            continue
        m.update(n=n, Ca=ca, solver_seconds=s["wall_seconds"], wall_seconds=None,
                 ranks=s.get("ranks", 1),
                 source=str((record_dir(run) if (run / "record.json").exists() else run)
                            .relative_to(ctx.repo)))
        series.setdefault(f"efsi, Ca {ca:g}", []).append(m)
    # d/8 runs made here (32^3, Ca 0.2, to t = 2): cheap, timed on 1 and 2 ranks
    for n in cfg["run_n"]:
        for ranks in cfg["ranks"]:
            ca = 0.2
            out = ctx.outdir / "capsule_3d" / f"3d_n{n}_ca{ca:g}_t2_r{ranks}"
            cells = 4 * n
            sets = {"grid.cells": f"[{cells},{cells},{cells}]", "grid.length": "[8.0,8.0,8.0]",
                    "grid.origin": "[-4.0,-4.0,-4.0]", "body[0].elastic_modulus": repr(1 / ca),
                    "time.end_time": "2.0", "output.fields_interval": "0",
                    "output.progress_every": "100000"}

            def read(_res, out=out, n=n, ca=ca, ranks=ranks):
                s = json.loads((out / "summary.json").read_text())
                m = measure(out, ca)
                m.update(n=n, Ca=ca, solver_seconds=s["wall_seconds"], ranks=ranks,
                         source="run here", **pressure_cap_rows(out))
                return m
            rec = timed(ctx, efsi_cmd(ctx, ctx.repo / "cases" / "capsule_shear", out, sets),
                        ranks, read, repeat=False)
            key = f"efsi, Ca {ca:g}" if ranks == 1 else f"efsi {ranks} ranks, Ca {ca:g}"
            series.setdefault(key, []).append(rec)
    for rows in series.values():
        rows.sort(key=lambda r: r["n"])
    # FE 3D (measured by reference_vesicle's full tier): its error at its sample times
    if fe3d:
        name, ref = cs.reference_curve(data, fe3d["Ca"])
        fe_err = max(abs(D - float(np.interp(T, ref[:, 0], ref[:, 1])))
                     for T, D in fe3d["D"].items())
        fe_row = {"n": 8, "Ca": fe3d["Ca"], "error_at_fe_times": fe_err, "error": None,
                  "solver_seconds": fe3d["wall_seconds"], "wall_seconds": None,
                  "source": fe3d["source"]}
        series[f"FE 3D 1 rank, Ca {fe3d['Ca']:g}"] = [fe_row]
    else:
        skipped.append("FE 3D: no stored reference_vesicle full-tier result")
    return {"series": series, "skipped_cached_runs": skipped,
            "error": "max |D - D_ref| over shear rate x t in [0.2, 2] (FE: at t = 0.2, 0.5, 1)",
            "resolution": "cells per diameter", "time_key": "solver_seconds"}
