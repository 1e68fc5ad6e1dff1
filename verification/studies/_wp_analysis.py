"""Work-precision study, the analysis: the equal-error comparison of the solvers' curves
(log-log interpolation, no extrapolation; bounds when the error ranges do not overlap), the
2-rank speedup, the per-problem metrics and table rows, the markdown table and the figure."""
from __future__ import annotations

import math
import textwrap

import numpy as np



# ----------------------------------------------------------------- equal-error helpers
def _curve(points):
    """(time, error) pairs as arrays sorted by time; non-positive entries dropped."""
    pts = sorted((float(t), float(e)) for t, e in points if t > 0 and e > 0)
    return np.array([p[0] for p in pts]), np.array([p[1] for p in pts])


def time_at_error(points, target):
    """Wall time a solver needs to reach ``target``, from its runs ``points`` = [(time,
    error), ...]: log(time) interpolated linearly in log(error) between the first two
    consecutive runs (in order of cost) whose errors bracket the target. None if no pair
    brackets it (no extrapolation)."""
    t, e = _curve(points)
    for i in range(len(t)):
        if e[i] == target:
            return float(t[i])
    for i in range(len(t) - 1):
        lo, hi = sorted((e[i], e[i + 1]))
        if lo <= target <= hi and lo < hi:
            s = (math.log(target) - math.log(e[i])) / (math.log(e[i + 1]) - math.log(e[i]))
            return float(math.exp(math.log(t[i]) + s * (math.log(t[i + 1]) - math.log(t[i]))))
    return None


def equal_error(fast, slow, target=None):
    """Compare two work-precision curves at a common error. ``target`` defaults to the
    geometric middle of the error range both reach. Returns a dict with the target, each
    time and ratio = t_slow / t_fast (> 1: ``fast`` is faster), or overlap False."""
    _, ea = _curve(fast)
    _, eb = _curve(slow)
    if len(ea) == 0 or len(eb) == 0:
        return {"overlap": False}
    lo, hi = max(ea.min(), eb.min()), min(ea.max(), eb.max())
    if target is None:
        if lo > hi:
            return {"overlap": False, "range_fast": [float(ea.min()), float(ea.max())],
                    "range_slow": [float(eb.min()), float(eb.max())]}
        target = math.sqrt(lo * hi)
    ta, tb = time_at_error(fast, target), time_at_error(slow, target)
    if ta is None or tb is None:
        return {"overlap": False, "target": target, "t_fast": ta, "t_slow": tb}
    return {"overlap": True, "target": float(target), "t_fast": ta, "t_slow": tb,
            "ratio": tb / ta}


def disjoint_bound(fast, slow):
    """When the error ranges do not overlap and every run of ``fast`` is more accurate than
    every run of ``slow``: reaching the best error of ``slow`` takes ``fast`` at most the
    time of its cheapest run, so t_slow(best) / t_fast(cheapest) is a LOWER bound of the
    speedup at that error (assuming the cost grows as the error falls). None otherwise."""
    ta, ea = _curve(fast)
    tb, eb = _curve(slow)
    if len(ea) == 0 or len(eb) == 0 or ea.max() >= eb.min():
        return None
    j = int(np.argmin(eb))
    return {"error": float(eb[j]), "t_slow": float(tb[j]), "t_fast_cheapest": float(ta.min()),
            "lower_bound": float(tb[j] / ta.min())}


# ----------------------------------------------------------------- analysis
def pts(rows, key="wall_seconds", err="error"):
    return [(r[key], r[err]) for r in rows if r.get(key) and r.get(err)]


def speedup_2ranks(one, two, res_key):
    """t(1 rank) / t(2 ranks) on the finest grid both ran (same grid: the same error to
    round-off; the relative error difference is returned too)."""
    common = sorted(set(r[res_key] for r in one) & set(r[res_key] for r in two))
    if not common:
        return None
    n = common[-1]
    a = next(r for r in one if r[res_key] == n)
    b = next(r for r in two if r[res_key] == n)
    return {"res": n, "ratio": a["wall_seconds"] / b["wall_seconds"],
            "ratio_solver": a["solver_seconds"] / b["solver_seconds"],
            "error_rel_diff": abs(a["error"] - b["error"]) / a["error"]}


def analyse(name, prob, metrics, table):
    s = prob["series"]
    keys = list(s)
    one = next(k for k in keys if k.startswith("efsi 1 rank") and "automatic" not in k)
    two = next((k for k in keys if k.startswith("efsi 2 ranks")), None)
    fe = next((k for k in keys if k.startswith("FE")), None)
    res_key = "n" if "n" in s[one][0] else "N"
    row = {"problem": name, "error_measure": prob["error"]}
    tkey = prob.get("time_key", "wall_seconds")
    if fe:
        # FE runs that diverged before the end have no error: listed, left off the curve
        div = [r for r in s[fe] if r.get("diverged_at") is not None]
        if div:
            row["fe_diverged"] = [{res_key: r[res_key], "t": r["diverged_at"]} for r in div]
            for r in div:
                metrics[f"fe_diverged_at_t_{name}_{res_key}{r[res_key]}"] = r["diverged_at"]
        for tk, suffix in ((tkey, ""), ("solver_seconds", "_solver_time")):
            if suffix and tk == tkey:
                continue
            eq = equal_error(pts(s[one], tk), pts(s[fe], tk))
            row[f"equal_error{suffix}"] = eq
            if eq.get("overlap"):
                metrics[f"speedup_vs_fe_at_equal_error_{name}{suffix}"] = eq["ratio"]
                if not suffix:
                    metrics[f"target_error_{name}"] = eq["target"]
                    metrics[f"time_efsi_1rank_at_target_{name}"] = eq["t_fast"]
                    metrics[f"time_fe_at_target_{name}"] = eq["t_slow"]
                    if two:
                        t2 = time_at_error(pts(s[two], tk), eq["target"])
                        row["t_2ranks_at_target"] = t2
            else:
                for a, b, sign in ((one, fe, 1), (fe, one, -1)):
                    bound = disjoint_bound(pts(s[a], tk), pts(s[b], tk))
                    if bound:
                        bound["efsi_is_more_accurate"] = sign > 0
                        row[f"disjoint{suffix}"] = bound
                        if sign > 0:
                            metrics[f"speedup_vs_fe_lower_bound_{name}{suffix}"] = \
                                bound["lower_bound"]
                        else:
                            metrics[f"fe_speedup_vs_efsi_lower_bound_{name}{suffix}"] = \
                                bound["lower_bound"]
        auto = next((k for k in keys if "automatic" in k), None)
        if auto:
            eq = equal_error(pts(s[auto], tkey), pts(s[fe], tkey))
            row["equal_error_auto_dt"] = eq
            if eq.get("overlap"):
                metrics[f"speedup_vs_fe_at_equal_error_{name}_efsi_auto_dt"] = eq["ratio"]
    if two:
        sp = speedup_2ranks(s[one], s[two], res_key)
        if sp:
            row["speedup_2ranks"] = sp
            metrics[f"speedup_2ranks_{name}"] = sp["ratio"]
            metrics[f"speedup_2ranks_{name}_solver_time"] = sp["ratio_solver"]
    table.append(row)


def capsule_3d_analysis(prob, metrics, table):
    """3D: the curves are per Ca; the FE number is one run at Ca 0.05 (error at its three
    sample times), so the comparison needs efsi runs at Ca 0.05."""
    s = prob["series"]
    row = {"problem": "capsule_3d", "error_measure": prob["error"]}
    for key, rows in s.items():
        if key.startswith("efsi, Ca"):
            ca = rows[0]["Ca"]
            for r in rows:
                metrics[f"capsule_3d_error_ca{ca:g}_n{4 * r['n']}"] = r["error"]
    one2 = s.get("efsi, Ca 0.2", [])
    two2 = s.get("efsi 2 ranks, Ca 0.2", [])
    if one2 and two2:
        own = [r for r in one2 if r.get("source") == "run here" and r.get("ranks", 1) == 1]
        sp = speedup_2ranks(own, two2, "n") if own else None
        if sp:
            row["speedup_2ranks"] = sp
            metrics["speedup_2ranks_capsule_3d"] = sp["ratio"]
            metrics["speedup_2ranks_capsule_3d_solver_time"] = sp["ratio_solver"]
    fe_key = next((k for k in s if k.startswith("FE")), None)
    if fe_key is None:
        row["note"] = "no measured FE 3D run stored (reference_vesicle full tier)"
        table.append(row)
        return
    fe = s[fe_key][0]
    # like for like with the FE run (1 process): efsi runs on 1 rank only
    cpp05 = [r for r in s.get(f"efsi, Ca {fe['Ca']:g}", [])
             if r.get("error_at_fe_times") and r.get("ranks", 1) == 1]
    row["fe_error_at_fe_times"] = fe["error_at_fe_times"]
    if cpp05:
        cp = [(r["solver_seconds"], r["error_at_fe_times"]) for r in cpp05]
        fp = [(fe["solver_seconds"], fe["error_at_fe_times"])]
        t_cpp = time_at_error(cp, fe["error_at_fe_times"])
        if t_cpp:
            metrics["speedup_vs_fe_at_equal_error_capsule_3d_solver_time"] = \
                fe["solver_seconds"] / t_cpp
            row["equal_error_solver_time"] = {"target": fe["error_at_fe_times"], "t_fast": t_cpp,
                                              "t_slow": fe["solver_seconds"]}
        else:
            bound = disjoint_bound(cp, fp)
            if bound:
                row["disjoint_solver_time"] = dict(bound, efsi_is_more_accurate=True)
                metrics["speedup_vs_fe_lower_bound_capsule_3d_solver_time"] = bound["lower_bound"]
            else:
                row["equal_error_solver_time"] = {"overlap": False}
    else:
        row["note"] = ("no completed 1-rank efsi 3D run at Ca 0.05 yet: no like-for-like "
                       "comparison with the FE run")
    table.append(row)


def fmt(x, spec=".3g"):
    return "-" if x is None else format(x, spec)


def markdown_table(table):
    """One row per problem: the time each solver needs at the target error and the ratios.
    'efsi vs FE' = t_FE / t_efsi (> 1: efsi is faster)."""
    lines = ["| problem | target error | efsi 1 rank [s] | efsi 2 ranks [s] | FE [s] | "
             "efsi vs FE: t_FE / t_efsi (wall) | same, solver timers | "
             "2 ranks vs 1: t_1 / t_2 (grid) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in table:
        eq = r.get("equal_error") or r.get("equal_error_solver_time") or {}
        eqs = r.get("equal_error_solver_time", {})
        sp = r.get("speedup_2ranks")
        sp_s = f"{sp['ratio']:.2f} ({sp['res']})" if sp else "-"
        if eq.get("t_fast") and eq.get("t_slow"):
            ratio = eq["t_slow"] / eq["t_fast"]
            ratio_s = (eqs["t_slow"] / eqs["t_fast"]) if eqs.get("t_fast") else None
            lines.append(f"| {r['problem']} | {eq['target']:.3g} | {eq['t_fast']:.3g} | "
                         f"{fmt(r.get('t_2ranks_at_target'))} | {eq['t_slow']:.3g} | "
                         f"{ratio:.3g} | {fmt(ratio_s)} | {sp_s} |")
            continue
        d = r.get("disjoint") or r.get("disjoint_solver_time")
        ds = r.get("disjoint_solver_time")
        if d and d["efsi_is_more_accurate"]:
            note = (f">= {d['lower_bound']:.3g} (no overlap: efsi's cheapest run is more "
                    f"accurate than FE's best, {d['error']:.3g})")
        elif d:
            note = (f"<= {1 / d['lower_bound']:.2g} (no overlap: FE's cheapest run is more "
                    f"accurate than efsi's best, {d['error']:.3g})")
        elif "fe_error_at_fe_times" in r:
            note = r.get("note", "no overlap of the error ranges")
        elif "equal_error" in r:
            note = "no overlap of the error ranges"
        else:
            note = "no FE solver"
        note_s = "-"
        if ds and ds is not d:
            note_s = (f">= {ds['lower_bound']:.3g}" if ds["efsi_is_more_accurate"]
                      else f"<= {1 / ds['lower_bound']:.2g}")
        lines.append(f"| {r['problem']} | - | - | - | - | {note} | {note_s} | {sp_s} |")
    return "\n".join(lines)


# The 1-minute load average before a run counts the study's own previous runs: about 1
# (2 with 2-rank runs) when it runs alone on the 2-core machine.
IDLE_LOAD_MEDIAN = 1.5


def load_description(loads: list) -> str:
    """Short wording of the machine load the timings were taken at (figure title, notes)."""
    if not loads:
        return "load not recorded"
    med = float(np.median(loads))
    if med <= IDLE_LOAD_MEDIAN:
        return f"run alone on a 2-core machine, median 1-min load {med:.2f}"
    return f"2-core machine UNDER LOAD, median 1-min load {med:.1f}"


def plot(ctx, problems, table, load: str = "load not recorded"):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(problems)
    ncol = min(3, len(names))
    nrow = math.ceil(len(names) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 4.3 * nrow), squeeze=False)
    styles = {"efsi 1 rank": ("C0", "o-"), "efsi 2 ranks": ("C1", "s--"),
              "automatic": ("C2", "^:"), "FE": ("C3", "D-")}
    targets = {r["problem"]: (r.get("equal_error") or {}).get("target") for r in table}
    for ax, name in zip(axes.flat, names):
        prob = problems[name]
        tkey = prob.get("time_key", "wall_seconds")
        for label, rows in prob["series"].items():
            errkey = "error"
            if label.startswith("FE 3D"):
                errkey = "error_at_fe_times"
            p = pts(rows, tkey, errkey)
            if not p:
                continue
            style = next((v for k, v in styles.items() if k in label), ("k", "x-"))
            if "automatic" in label:
                style = styles["automatic"]
            if name == "capsule_3d" and label.startswith("efsi, Ca"):
                ca_colours = {"0.2": "C0", "0.1": "C2", "0.05": "C4", "0.025": "C5",
                              "0.0125": "C6"}
                style = (ca_colours.get(label.split("Ca ")[-1], "k"), "o-")
            t, e = zip(*p)
            ax.loglog(t, e, style[1], color=style[0], mfc="none", label=label)
            res_key = "n" if "n" in rows[0] else "N"
            for r, (tt, ee) in zip([r for r in rows if r.get(tkey) and r.get(errkey)], p):
                note = str(r[res_key])
                if name == "capsule_3d" and label.startswith("efsi, Ca"):
                    note += f" ({r.get('ranks', 1)} rank{'s' if r.get('ranks', 1) > 1 else ''})"
                ax.annotate(note, (tt, ee), fontsize=6, xytext=(3, 3),
                            textcoords="offset points")
        if targets.get(name):
            ax.axhline(targets[name], color="0.5", lw=0.6, ls=":")
        row = next((r for r in table if r["problem"] == name), {})
        eq = row.get("equal_error") or row.get("equal_error_solver_time") or {}
        title = name
        if eq.get("t_fast") and eq.get("t_slow"):
            title += (f": at error {eq['target']:.2g}, "
                      f"t_FE / t_efsi = {eq['t_slow'] / eq['t_fast']:.3g}")
        elif row.get("note"):
            title += " (FE at Ca 0.05: no efsi run at that Ca yet)"
        ax.set_title(title, fontsize=8)
        ax.set_xlabel("wall time [s]" if tkey == "wall_seconds"
                      else "solver wall time [s] (solver's own timer)")
        ax.set_ylabel(textwrap.fill(prob["error"], 48), fontsize=7)
        ax.legend(fontsize=6)
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    fig.suptitle(f"work-precision ({ctx.tier} tier; {load})", fontsize=10)
    fig.tight_layout()
    png = ctx.outdir / "work_precision.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    return png
