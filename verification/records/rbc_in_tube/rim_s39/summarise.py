"""Table of the session-39 restarts of map125_foot_t10 (README here): per run the time
reached, how it ended, and the flow's largest speed (diagnostics.csv) in windows of 0.05 ms.
Writes result.md beside this script.

    /usr/bin/python3 verification/records/rbc_in_tube/rim_s39/summarise.py
"""
import csv
import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
RUNS = [("rim_ctl", "control: the case's keys (cfl 0.5, min_distance_gradient 0.5)"),
        ("rim_cfl025", "half the step (time.cfl = 0.25)"),
        ("rim_p2", "conservative restoration switched on (profile_iterations = 2)"),
        ("rim_mdg", "min_distance_gradient = 0.8"),
        ("rim_mdg_t65", "min_distance_gradient = 0.8, continued from rim_mdg")]
WINDOWS = [5.214, 5.25, 5.30, 5.35, 5.40, 5.45, 5.50, 5.55, 5.60, 5.65, 5.70]


def rows(run):
    with open(HERE / run / "diagnostics.csv") as f:
        return [(float(r["time"]), float(r["max_speed"])) for r in csv.DictReader(f)]


def main():
    out = ["| run | what | t reached [ms] | ended | largest speed [um/ms] per window |",
           "|---|---|---|---|---|"]
    for run, what in RUNS:
        if not (HERE / run).exists():
            continue
        d = rows(run)
        s = json.loads((HERE / run / "summary.json").read_text())
        peaks = []
        for a, b in zip(WINDOWS[:-1], WINDOWS[1:]):
            v = [u for t, u in d if a < t <= b + 1e-12]
            if v:
                peaks.append(f"{a:.2f}-{b:.2f}: {max(v):.3g}")
        last = [u for t, u in d if d and t > d[-1][0] - 0.05]
        if d and d[-1][0] > WINDOWS[-1]:
            peaks.append(f"last 0.05 ms: {max(last):.3g}")
        ended = s.get("status", "?")
        out.append(f"| `{run}` | {what} | {float(s['time']):.3f} | {ended} | "
                   + "; ".join(peaks) + " |")
    (HERE / "result.md").write_text("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
