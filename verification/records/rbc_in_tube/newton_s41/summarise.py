"""The red cell at h = 0.125 um from t = 0 with Newton foot points (session 41, README here)
against the same run without them (../map125_foot_t10, which stopped UNSTABLE at 5.384 ms):
per run the time reached, how it ended (summary.json where the run ended by itself, else
the last diagnostics row), the flow's largest speed (diagnostics.csv) in windows of 0.5 ms,
the red cell's area change and stored-strain drift and max tr Gs (bodies.csv). Writes
result.md beside this script.

    /usr/bin/python3 verification/records/rbc_in_tube/newton_s41/summarise.py
"""
import csv
import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
RUNS = [(HERE.parent / "map125_foot_t10", "off (session 39)"),
        (HERE / "map125_newton_t10", "on, from t = 0")]
WINDOW = 0.5  # ms


def main():
    out = ["| run | newton_foot_points | t reached [ms] | ended | area / A(0) - 1, largest "
           "| stored-strain drift A_ref / A - 1, largest | max tr Gs | largest speed [um/ms] "
           "per 0.5 ms window |", "|---|---|---|---|---|---|---|---|"]
    for run, key in RUNS:
        if not run.exists():
            continue
        with open(run / "diagnostics.csv") as f:
            d = [(float(r["time"]), float(r["max_speed"])) for r in csv.DictReader(f)]
        with open(run / "bodies.csv") as f:
            cell = [r for r in csv.DictReader(f) if r["body"] == "rbc"]
        summary = run / "summary.json"
        ended = (json.loads(summary.read_text()).get("status", "?") if summary.exists()
                 else "not ended: stopped by hand at the session's end (its checkpoint kept)")
        area = [float(r["area"]) for r in cell]
        drift = max(abs(float(r["reference_area"]) / float(r["area"]) - 1) for r in cell)
        trace = max(float(r["tensor_trace_max"]) for r in cell)
        peaks = []
        a = 0.0
        while a < d[-1][0]:
            v = [u for t, u in d if a < t <= a + WINDOW + 1e-12]
            if v:
                peaks.append(f"{a:.1f}-{a + WINDOW:.1f}: {max(v):.3g}")
            a += WINDOW
        out.append(f"| `{run.name}` | {key} | {d[-1][0]:.3f} | {ended} | "
                   f"{max(abs(x / area[0] - 1) for x in area):.4f} | {drift:.4f} | "
                   f"{trace:.3f} | " + "; ".join(peaks) + " |")
    (HERE / "result.md").write_text("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
