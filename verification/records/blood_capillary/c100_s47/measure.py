"""capillary_coarse with stiff-area red cells (Skalak C = 100; the case has C = 10), issue 20:
"C = 100 must run". Measures the C = 100 run against the blood_capillary study's full-tier
runs of the case over the same time: the 1-rank run with field snapshots (`cells`) and, for
the cost on 2 ranks, the 2-rank run (`cells_2ranks`, to 0.5 ms). Per run: time reached, status,
steps, time step, seconds per ms, and over the red cells and the rows up to the C = 100
run's end the largest stored-strain drift |A_ref / A - 1|, the largest area change
|A / A(0) - 1|, the largest change of the reference area itself |A_ref / A_ref(0) - 1|, max tr Gs and the volume drift; the largest overlap of two bodies over the
snapshots up to that time (the study's measure). Writes result.md beside this file.

    /usr/bin/python3 verification/records/blood_capillary/c100_s47/measure.py C100_RUN \
        build/verification/blood_capillary/runs/full/cells_2ranks \
        build/verification/blood_capillary/runs/full/cells
"""
import csv
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2] / "studies"))
from _overlap import overlap, smoothing_widths  # noqa: E402 (the study's measure)
from blood_capillary import (bodies, reference_area_drift, snapshot_time,  # noqa: E402
                             snapshots, volume_drift)


def rows_to(out: Path, t_max: float) -> dict:
    """The study's bodies.csv rows per body (blood_capillary.bodies), up to t_max."""
    return {name: [r for r in rows if float(r["time"]) <= t_max + 1e-9]
            for name, rows in bodies(out).items()}


def measure(out: Path, t_max: float) -> dict:
    s = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else {}
    per = {name: rows for name, rows in rows_to(out, t_max).items() if rows}
    drift, vol = reference_area_drift(per), volume_drift(per)
    t_last = max(float(rows[-1]["time"]) for name, rows in per.items() if name != "wall")
    area = ref = trace = 0.0
    for name, rows in per.items():
        if not name.startswith("rbc"):
            continue
        a0, r0 = float(rows[0]["area"]), float(rows[0]["reference_area"])
        for r in rows:
            area = max(area, abs(float(r["area"]) / a0 - 1))
            ref = max(ref, abs(float(r["reference_area"]) / r0 - 1))
            trace = max(trace, float(r["tensor_trace_max"]))
    with open(out / "diagnostics.csv") as f:
        diag = [r for r in csv.DictReader(f) if float(r["time"]) <= t_max + 1e-9]
    dts = [float(r["dt"]) for r in diag if float(r["dt"]) > 0]
    steps = int(diag[-1]["step"])
    wall = float(s.get("wall_seconds", np.nan))
    t_run = float(s.get("time", np.nan))
    # A restarted run's summary times its last leg (`steps` of the `final_step`): its seconds
    # per step times the whole run's steps per ms.
    per_ms = wall / float(s.get("steps", np.nan)) * float(s.get("final_step", np.nan)) / t_run
    return {"t reached [ms]": t_last, "status of the run": f"{s.get('status', '-')} at {t_run:.4g} ms",
            "ranks": s.get("ranks", "-"), "steps to t": steps,
            "time step [ms] (median)": float(np.median(dts)),
            "seconds per ms (the last leg's seconds per step)": per_ms,
            "A_ref / A - 1, max over the red cells": drift,
            "area change max over the red cells": area,
            "A_ref / A_ref(0) - 1, max over the red cells": ref,
            "max tr Gs over the red cells": trace,
            "volume drift max": vol}


def worst_overlap(out: Path, t_max: float):
    snaps = [p for p in snapshots(out) if snapshot_time(p) <= t_max + 1e-9]
    w = smoothing_widths(out)
    return max(overlap(p, w) for p in snaps), len(snaps)


def main():
    c100, c10_2, c10_1 = (Path(a) for a in sys.argv[1:4])
    a = measure(c100, np.inf)
    t = a["t reached [ms]"]
    b = measure(c10_1, t)
    cost = measure(c10_2, np.inf)  # the case on 2 ranks (to 0.5 ms): its cost and rank count
    for k in ("ranks", "seconds per ms (the last leg's seconds per step)"):
        b[k] = cost[k]
    ov_a, na = worst_overlap(c100, t)
    ov_b, nb = worst_overlap(c10_1, t)
    fmt = lambda v: v if isinstance(v, str) else (f"{v:.4g}" if isinstance(v, float) else str(v))
    lines = ["# capillary_coarse with C = 100 red cells (session 47)", "",
             "Made by `measure.py` (this folder). The C = 10 column is the case as it is, from the "
             "blood_capillary study's full-tier runs up to the same time: `cells` (1 rank, field "
             "snapshots), but for the ranks and the cost, which are those of `cells_2ranks` (2 "
             "ranks, to 0.5 ms).", "",
             "| quantity | C = 100 | C = 10 (the case) |", "|---|---|---|"]
    for k in a:
        lines.append(f"| {k} | {fmt(a[k])} | {fmt(b[k])} |")
    lines.append(f"| largest overlap of two bodies (sharp red cells), snapshots to t | "
                 f"{ov_a:.3g} ({na} snapshots) | {ov_b:.3g} ({nb} snapshots) |")
    (HERE / "result.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
