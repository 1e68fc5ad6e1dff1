"""Strong and weak scaling on 1, 2 and 4 MPI ranks: a 3D flow case and the 3D capsule.

Strong scaling: the same problem (3D Taylor-Green, cases/taylor_green_3d, and the 3D
capsule in shear, cases/capsule_shear at Ca 0.2) for a fixed number of steps on 1, 2, 4
ranks. Weak scaling: the box grows with the ranks along x (N x N x N cells per rank); the
capsule case gets one capsule per rank, spaced along x, so the membrane work per rank is
constant too. Per run: wall time, cell updates per second per rank, parallel efficiency
against 1 rank, and the time of each stage (summary.json "stages") so the dominant stage is
visible.

The machine this runs on in CI and development has 2 cores: runs with more ranks than
cores are oversubscribed and flagged `oversubscribed = 1`; their efficiency measures the
oversubscription, not the code. The load average before each run is recorded (other jobs
on the machine lower and scatter the figures).
"""
from __future__ import annotations

import json
import os
import re

from _bounds import Bound  # noqa: E402

DESCRIPTION = "strong/weak scaling on 1, 2, 4 ranks: 3D Taylor-Green and 3D capsule; time per stage"

# Acceptance bounds (verification/studies/_bounds.py): run.py fails the study, naming the
# metric, when one breaks.
BOUNDS = [
    Bound(r"cell_updates_per_second_per_rank_.*", ">=", 1.0,
          "every run of the sweep finished and was timed"),
    Bound(r"strong_efficiency_flow_np2", ">=", 0.9,
          "2 ranks at least 1.8x faster than 1 on an idle machine (issue 22)", tiers=("full",)),
]

# Per tier: cells per direction per rank-1 problem (flow, capsule), steps, rank counts.
# The capsule's membrane (normal extension of Gs, the default) needs every rank's block to
# be at least 10 cells wide, so its box is 24 (ci) and 48 (quick) cells: 12 per rank at
# the most ranks of the tier.
TIERS = {
    "ci": {"flow_n": 16, "capsule_n": 24, "steps": 3, "ranks": [1, 2]},
    "quick": {"flow_n": 64, "capsule_n": 48, "steps": 10, "ranks": [1, 2, 4]},
    "full": {"flow_n": 128, "capsule_n": 64, "steps": 20, "ranks": [1, 2, 4]},
}
COMMON = {"output.fields": "false", "output.progress_every": "100000000",
          "output.checkpoint_every": "0", "time.end_time": "1000.0"}


def capsule_case(base: str, n: int, ranks: int, weak: bool) -> str:
    """capsule_shear text at n^3 cells per capsule box; weak: `ranks` boxes along x."""
    m = ranks if weak else 1
    t = base.replace("cells = [64, 64, 64]", f"cells = [{n * m}, {n}, {n}]")
    t = t.replace("length = [8.0, 8.0, 8.0]", f"length = [{8.0 * m!r}, 8.0, 8.0]")
    t = t.replace("origin = [-4.0, -4.0, -4.0]", f"origin = [{-4.0 * m!r}, -4.0, -4.0]")
    t = t.replace("elastic_modulus = 20.0", "elastic_modulus = 5.0")  # Ca 0.2
    body = t[t.index("[[body]]"):t.index("[output]")]
    t = t.replace(body, "")
    bodies = []
    for b in range(m):
        x = -4.0 * m + 4.0 + 8.0 * b
        bb = body.replace('name = "capsule"', f'name = "capsule{b}"')
        bodies.append(re.sub(r"centre = \[[^\]]*\]", f"centre = [{x!r}, 0.0, 0.0]", bb))
    return t.replace("[output]", "".join(bodies) + "[output]")


def one(ctx, case, out, ranks, sets) -> dict:
    load = os.getloadavg()[0]
    s = ctx.run_efsi(case, out, ranks=ranks, sets={**COMMON, **sets})
    wall = s["wall_seconds"]
    cells = s["cells"]
    return {"ranks": ranks, "decomposition": s["ranks_per_dim"], "cells": cells,
            "steps": s["steps"], "wall_seconds": wall,
            "cell_updates_per_second_per_rank": s["cell_updates_per_second"] / ranks,
            "oversubscribed": int(ranks > (os.cpu_count() or 1)), "loadavg_before": load,
            "stages": s["stages"],
            "dominant_stage": max(s["stages"], key=s["stages"].get)}


def run(ctx):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cfg = TIERS[ctx.tier]
    steps = str(cfg["steps"])
    base = (ctx.repo / "cases" / "capsule_shear" / "case.toml").read_text()
    rows, metrics = [], {}
    for kind in ("strong", "weak"):
        for problem in ("flow", "capsule"):
            for r in cfg["ranks"]:
                out = ctx.outdir / f"{problem}_{kind}_np{r}"
                if problem == "flow":
                    n = cfg["flow_n"]
                    nx = n * r if kind == "weak" else n
                    sets = {"grid.cells": f"[{nx},{n},{n}]", "time.max_steps": steps}
                    if kind == "weak":  # keep h: the box grows with the cells
                        sets["grid.length"] = f"[{6.283185307179586 * r!r},6.283185307179586,6.283185307179586]"
                    row = one(ctx, "cases/taylor_green_3d", out, r, sets)
                else:
                    case = ctx.outdir / f"capsule_{kind}_np{r}.toml"
                    case.write_text(capsule_case(base, cfg["capsule_n"], r, kind == "weak"))
                    row = one(ctx, case, out, r, {"time.max_steps": steps})
                row.update(problem=problem, kind=kind)
                rows.append(row)
    for kind in ("strong", "weak"):
        for problem in ("flow", "capsule"):
            sel = [x for x in rows if x["kind"] == kind and x["problem"] == problem]
            t1 = sel[0]["wall_seconds"] / sel[0]["steps"]
            for x in sel:
                per_step = x["wall_seconds"] / x["steps"]
                # strong: T1 / (p Tp); weak: T1 / Tp (work per rank constant)
                x["efficiency"] = t1 / (x["ranks"] * per_step) if kind == "strong" else t1 / per_step
                metrics[f"{kind}_efficiency_{problem}_np{x['ranks']}"] = x["efficiency"]
                metrics[f"cell_updates_per_second_per_rank_{problem}_{kind}_np{x['ranks']}"] = \
                    x["cell_updates_per_second_per_rank"]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for kind, a in zip(("strong", "weak"), ax[:2]):
        for problem, mk in (("flow", "o-"), ("capsule", "s-")):
            sel = [x for x in rows if x["kind"] == kind and x["problem"] == problem]
            a.plot([x["ranks"] for x in sel], [x["efficiency"] for x in sel], mk, label=problem)
        a.axvline(os.cpu_count() or 1, color="gray", ls=":", lw=1)
        a.set(xlabel="MPI ranks (right of the dotted line: oversubscribed)",
              ylabel="parallel efficiency", title=f"{kind} scaling", xscale="log", ylim=(0, 1.2))
        a.set_xticks(cfg["ranks"])
        a.set_xticklabels([str(r) for r in cfg["ranks"]])
        a.legend()
    # time per stage, strong scaling of the capsule
    sel = [x for x in rows if x["kind"] == "strong" and x["problem"] == "capsule"]
    stages = sorted({k for x in sel for k in x["stages"]}, key=lambda k: -sel[0]["stages"][k])
    bottom = [0.0] * len(sel)
    for st in stages:
        vals = [x["stages"].get(st, 0.0) / x["steps"] for x in sel]
        ax[2].bar([str(x["ranks"]) for x in sel], vals, bottom=bottom, label=st)
        bottom = [b + v for b, v in zip(bottom, vals)]
    ax[2].set(xlabel="MPI ranks", ylabel="seconds per step", title="3D capsule: time per stage")
    ax[2].legend(fontsize=6)
    fig.tight_layout()
    png = ctx.outdir / "scaling.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    stage_rows = [{"problem": x["problem"], "kind": x["kind"], "ranks": x["ranks"],
                   **{k: round(v / x["steps"], 5) for k, v in x["stages"].items()}} for x in rows]
    table = [{k: v for k, v in x.items() if k != "stages"} for x in rows]
    return {"metrics": metrics, "tables": {"runs": table, "seconds_per_step_by_stage": stage_rows},
            "figures": [str(png)],
            "notes": (f"{os.cpu_count()} cores on this machine; rank counts above it are "
                      "oversubscribed (flagged). Flow: cases/taylor_green_3d, "
                      f"{cfg['flow_n']}^3 per rank-1 problem; capsule: cases/capsule_shear at "
                      f"Ca 0.2, {cfg['capsule_n']}^3 per capsule box; {steps} steps each. "
                      "Efficiency: strong T1/(p Tp), weak T1/Tp (per step). Timings taken "
                      "while other jobs ran are scattered; loadavg_before is recorded per run.")}
