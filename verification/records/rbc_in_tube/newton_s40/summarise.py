"""Table of the session-40 restarts of map125_foot_t10 with Newton foot points (README
here): per run the time reached, how it ended, and the flow's largest speed
(diagnostics.csv) in windows of 0.25 ms. Writes result.md beside this script.

    /usr/bin/python3 verification/records/rbc_in_tube/newton_s40/summarise.py
"""
import csv
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[3]
sys.path.insert(0, str(REPO / "verification" / "studies"))
sys.path.insert(0, str(REPO / "verification"))
CAPSULES = REPO / "verification" / "records" / "capsule_longtime"
START = 5.214  # ms, the checkpoint both runs start from
RUNS = [("rim_newton", "newton_foot_points = true from the 5.214 ms checkpoint, to 6.5 ms"),
        ("rim_newton_t10", "the same, continued from rim_newton's end towards 10 ms")]
# The undisturbed flow's largest speed (the tube's centreline, G R^2 / (4 mu) = 2.08 um/ms;
# map125_foot_t10 measured 1.89-2.11 from 0.5 to 5 ms in its field snapshots).


def rows(run):
    with open(HERE / run / "diagnostics.csv") as f:
        return [(float(r["time"]), float(r["max_speed"])) for r in csv.DictReader(f)]


def cell_rows(run):
    """bodies.csv rows of the red cell (body `rbc`) from the 5.214 ms checkpoint on."""
    with open(HERE / run / "bodies.csv") as f:
        return [r for r in csv.DictReader(f) if r["body"] == "rbc" and float(r["time"]) >= START]


def main():
    out = ["| run | what | t reached [ms] | ended | red cell's area / at 5.214 ms - 1, at the end "
           "| stored-strain drift A_ref / A - 1, largest | max tr Gs | largest speed [um/ms] per "
           "0.25 ms window |", "|---|---|---|---|---|---|---|---|"]
    for run, what in RUNS:
        if not (HERE / run).exists():
            continue
        d = [(t, u) for t, u in rows(run) if t > START]
        s = json.loads((HERE / run / "summary.json").read_text())
        peaks = []
        a = START
        while d and a < d[-1][0]:
            b = 5.25 if a == START else a + 0.25
            v = [u for t, u in d if a < t <= b + 1e-12]
            if v:
                peaks.append(f"{a:.2f}-{b:.2f}: {max(v):.3g}")
            a = b
        cell = cell_rows(run)
        area = [float(r["area"]) for r in cell]
        drift = max(abs(float(r["reference_area"]) / float(r["area"]) - 1) for r in cell)
        trace = max(float(r["tensor_trace_max"]) for r in cell)
        out.append(f"| `{run}` | {what} | {float(s['time']):.3f} | {s.get('status', '?')} | "
                   f"{area[-1] / area[0] - 1:+.4f} | {drift:.4f} | {trace:.3f} | "
                   + "; ".join(peaks) + " |")
    out += ["", "Capsules at d/16 to t = 20 (capsule_longtime's measures; same binary):", "",
            "| run | key | t reached | steady D | angle / pi | D drift | max tr Gs | "
            "max area change | reference area drift |", "|---|---|---|---|---|---|---|---|---|"]
    import capsule_longtime  # the study's own measures

    for tag in ("ca0.05_n64_t20", "ca0.2_n64_t20"):
        for suffix, key in (("_s40", "off"), ("_newton", "on")):
            folder = CAPSULES / (tag + suffix)
            if not folder.exists():
                continue
            m = capsule_longtime.measure(folder)
            out.append(f"| `{tag + suffix}` | {key} | {m['t_end']:g} | {m['steady_D']:.4f} | "
                       f"{m['steady_angle_over_pi']:.4f} | {m['steady_D_drift']:.4f} | "
                       f"{m['max_trace_Gs']:.3f} | {m['max_area_change']:.4f} | "
                       f"{m['reference_area_drift']:.4f} |")
    (HERE / "result.md").write_text("\n".join(out) + "\n")
    print("\n".join(out))


if __name__ == "__main__":
    main()
