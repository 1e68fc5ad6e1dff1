#!/usr/bin/python3
"""Table of the recorded capsule runs with the reference map next to the carried Gs.

    /usr/bin/python3 verification/records/capsule_longtime/refmap_table.py

Reads the records in this folder (record.py) with capsule_longtime's own measure() and
published steady values, and prints a markdown table: per run the strain model, the time
reached, D at t = 1 / 2 / 3 / 5 / 10 (RP98 beside), the steady D over the last quarter and
its error, the largest |D - D_ref| over the reference curve's full range
(capsule_longtime's max_abs_D_error_full), max tr Gs over the band, the largest area change,
the reference-area drift, and the wall time per unit of shear-rate x t with the rank count
(the machine's load is in each record.json; the runs shared the 2 cores, so it is loose).
"reference_map" records before session 18 extend the map with the trilinear interpolant
(`map_interpolation = "linear"`; suffix `_linear` where a later record took the plain name);
those with suffix `_cubic` use the cubic default.
docs/method.md quotes its output (section "The reference map").
"""
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "studies"))
from _flowio import body_series  # noqa: E402
from capsule_longtime import full_range_error, measure, steady_reference  # noqa: E402

# (record, strain model, Ca, law, C)
RUNS = [
    ("ca0.05_n64_t20_face4", "tensor", 0.05, "neo_hookean", None),
    ("ca0.05_n64_t20_refmap", "reference_map", 0.05, "neo_hookean", None),
    ("ca0.2_n64_t10_face4", "tensor", 0.2, "neo_hookean", None),
    ("ca0.2_n64_t5_refmap", "reference_map", 0.2, "neo_hookean", None),
    ("ca0.2_n128_t3.5_refmap", "reference_map", 0.2, "neo_hookean", None),
    ("ca0.1_n64_t10_refmap", "reference_map", 0.1, "neo_hookean", None),
    ("ca0.0125_n64_t5_refmap", "reference_map", 0.0125, "neo_hookean", None),
    ("ca0.05_n64_bend0.01_t5_refmap", "reference_map", 0.05, "neo_hookean", None),
    ("ca0.025_n64_skalak_C10_t2_refmap", "reference_map", 0.025, "skalak", 10.0),
    ("ca0.1_n64_t20_linear", "reference_map", 0.1, "neo_hookean", None),
    ("ca0.025_n64_t20_linear", "reference_map", 0.025, "neo_hookean", None),
    ("ca0.0125_n64_t20_linear", "reference_map", 0.0125, "neo_hookean", None),
    ("ca0.05_n64_bend0.01_t20_w1", "reference_map", 0.05, "neo_hookean", None),
    ("ca0.05_n32_t10", "reference_map", 0.05, "neo_hookean", None),
    ("ca0.2_n32_t10", "reference_map", 0.2, "neo_hookean", None),
    ("ca0.05_n128_t10_w1", "reference_map", 0.05, "neo_hookean", None),
    ("ca0.05_n64_t20_cubic", "reference_map, cubic", 0.05, "neo_hookean", None),
    ("ca0.1_n64_t20_cubic", "reference_map, cubic", 0.1, "neo_hookean", None),
    ("ca0.025_n64_t20_cubic", "reference_map, cubic", 0.025, "neo_hookean", None),
    ("ca0.0125_n64_t20_cubic", "reference_map, cubic", 0.0125, "neo_hookean", None),
    ("ca0.05_n64_bend0.01_t20_cubic", "reference_map, cubic", 0.05, "neo_hookean", None),
    ("ca0.025_n64_skalak_C10_t3_cubic", "reference_map, cubic", 0.025, "skalak", 10.0),
    ("ca0.05_n128_t10_cubic", "reference_map, cubic", 0.05, "neo_hookean", None),
    # Session 21: the smoothing width eps (cells) of the membrane's profile, 0.5 and 0.75
    # instead of the case's 1 (`--set body[0].smoothing_width=...`), the default keys else.
    ("ca0.2_n64_t5_w05", "reference_map, cubic, eps 0.5", 0.2, "neo_hookean", None),
    ("ca0.05_n64_t10_w05", "reference_map, cubic, eps 0.5", 0.05, "neo_hookean", None),
    ("ca0.1_n64_t10_w05", "reference_map, cubic, eps 0.5", 0.1, "neo_hookean", None),
    ("ca0.05_n32_t10_w05", "reference_map, cubic, eps 0.5", 0.05, "neo_hookean", None),
    ("ca0.2_n32_t10_w05", "reference_map, cubic, eps 0.5", 0.2, "neo_hookean", None),
    ("ca0.2_n64_t10_w075", "reference_map, cubic, eps 0.75", 0.2, "neo_hookean", None),
    ("ca0.2_n64_t6_w075", "reference_map, cubic, eps 0.75", 0.2, "neo_hookean", None),
    ("ca0.05_n64_t6_w075", "reference_map, cubic, eps 0.75", 0.05, "neo_hookean", None),
    ("ca0.1_n64_t10_w075", "reference_map, cubic, eps 0.75", 0.1, "neo_hookean", None),
    ("ca0.025_n64_t5_w075", "reference_map, cubic, eps 0.75", 0.025, "neo_hookean", None),
    ("ca0.0125_n64_t5_w075", "reference_map, cubic, eps 0.75", 0.0125, "neo_hookean", None),
    ("ca0.05_n64_bend0.01_t5_w075", "reference_map, cubic, eps 0.75", 0.05, "neo_hookean", None),
    ("ca0.05_n32_t10_w075", "reference_map, cubic, eps 0.75", 0.05, "neo_hookean", None),
    ("ca0.2_n32_t10_w075", "reference_map, cubic, eps 0.75", 0.2, "neo_hookean", None),
    ("ca0.2_n128_t6_w075", "reference_map, cubic, eps 0.75", 0.2, "neo_hookean", None),
    # the capsule_longtime study's own runs with the cases' width since session 22
    ("ca0.0125_n64_t20", "reference_map, cubic, eps 0.75", 0.0125, "neo_hookean", None),
    ("ca0.025_n64_t20", "reference_map, cubic, eps 0.75", 0.025, "neo_hookean", None),
    ("ca0.05_n64_t20", "reference_map, cubic, eps 0.75", 0.05, "neo_hookean", None),
    ("ca0.1_n64_t20", "reference_map, cubic, eps 0.75", 0.1, "neo_hookean", None),
    ("ca0.2_n64_t20", "reference_map, cubic, eps 0.75", 0.2, "neo_hookean", None),
    # the same capsule in a box twice as large (16 a, walls at y = -8 / +8 moving at -8 / +8):
    # the confinement's share of D (docs/method.md)
    ("ca0.2_n64_box16_t6", "reference_map, cubic, eps 0.75, box 16 a", 0.2, "neo_hookean",
     None),
    # session 23: the study's bending and Skalak runs with the cases' width
    ("ca0.05_n64_bend0.01_t20", "reference_map, cubic, eps 0.75", 0.05, "neo_hookean", None),
    ("ca0.025_n64_skalak_C1_t20", "reference_map, cubic, eps 0.75", 0.025, "skalak", 1.0),
    ("ca0.025_n64_skalak_C10_t20", "reference_map, cubic, eps 0.75", 0.025, "skalak", 10.0),
    # session 24: the study's d/32 runs with the cases' width
    ("ca0.2_n128_t10", "reference_map, cubic, eps 0.75", 0.2, "neo_hookean", None),
    ("ca0.1_n128_t10", "reference_map, cubic, eps 0.75", 0.1, "neo_hookean", None),
    ("ca0.05_n128_t10", "reference_map, cubic, eps 0.75", 0.05, "neo_hookean", None),
    # session 24: the same runs with the map projected onto the reference sphere
    # (map_projection, the default since session 24)
    ("ca0.0125_n64_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.0125, "neo_hookean", None),
    ("ca0.025_n64_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.025, "neo_hookean", None),
    ("ca0.05_n64_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.05, "neo_hookean", None),
    ("ca0.1_n64_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.1, "neo_hookean", None),
    ("ca0.2_n64_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.2, "neo_hookean", None),
    ("ca0.05_n64_bend0.01_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.05, "neo_hookean", None),
    ("ca0.025_n64_skalak_C1_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.025, "skalak", 1.0),
    ("ca0.025_n64_skalak_C10_t20_proj", "reference_map, cubic, eps 0.75, projected", 0.025, "skalak", 10.0),
    ("ca0.05_n32_t10_proj", "reference_map, cubic, eps 0.75, projected", 0.05, "neo_hookean", None),
    ("ca0.2_n32_t10_proj", "reference_map, cubic, eps 0.75, projected", 0.2, "neo_hookean", None),
    ("ca0.2_n128_t10_proj", "reference_map, cubic, eps 0.75, projected", 0.2, "neo_hookean", None),
    ("ca0.1_n128_t10_proj", "reference_map, cubic, eps 0.75, projected", 0.1, "neo_hookean", None),
    ("ca0.05_n128_t10_proj", "reference_map, cubic, eps 0.75, projected", 0.05, "neo_hookean", None),
    # session 25: Skalak C = 100 projected (the grid-scale area mode), and the area ratio
    # low-passed (map_area_filter, the default since session 25)
    ("ca0.025_n64_skalak_C100_t0.3_proj", "reference_map, cubic, eps 0.75, projected", 0.025, "skalak", 100.0),
    ("ca0.025_n64_skalak_C10_from9_t14_areafilter", "projected; area filter from t = 9", 0.025, "skalak", 10.0),
    ("ca0.05_n64_t4_areafilter", "projected, area filter", 0.05, "neo_hookean", None),
    ("ca0.025_n64_skalak_C10_t20_areafilter", "projected, area filter", 0.025, "skalak", 10.0),
    # session 26: each copy turned into its cell's tangent plane before the projection
    # (93ed07a), with the area-filter runs before it (d/8; d/16 Ca 0.2)
    ("ca0.05_n32_t10_areafilter", "projected, area filter", 0.05, "neo_hookean", None),
    ("ca0.05_n32_t10_turn", "projected, area filter, turned copy", 0.05, "neo_hookean", None),
    ("ca0.2_n32_t10_turn", "projected, area filter, turned copy", 0.2, "neo_hookean", None),
    ("ca0.05_n64_t4_turn", "projected, area filter, turned copy", 0.05, "neo_hookean", None),
    ("ca0.2_n32_t10_areafilter", "projected, area filter", 0.2, "neo_hookean", None),
    ("ca0.2_n64_t20_areafilter", "projected, area filter", 0.2, "neo_hookean", None),
    ("ca0.2_n64_t20_turn", "projected, area filter, turned copy", 0.2, "neo_hookean", None),
    # session 26: with the foot-point check (ad9d416): a cell whose foot point is off the
    # surface holds no strain
    ("ca0.2_n64_t20_foot", "projected, area filter, turned copy, foot check", 0.2, "neo_hookean", None),
    # session 26: the study's runs with the default of ad9d416 (d/8 to t = 10, d/16 to t = 20, d/32 to t = 10)
    ("ca0.05_n32_t10_foot", "projected, area filter, turned copy, foot check", 0.05, "neo_hookean", None),
    ("ca0.2_n32_t10_foot", "projected, area filter, turned copy, foot check", 0.2, "neo_hookean", None),
    ("ca0.1_n64_t20_foot", "projected, area filter, turned copy, foot check", 0.1, "neo_hookean", None),
    ("ca0.05_n64_t20_foot", "projected, area filter, turned copy, foot check", 0.05, "neo_hookean", None),
    ("ca0.025_n64_t20_foot", "projected, area filter, turned copy, foot check", 0.025, "neo_hookean", None),
    ("ca0.0125_n64_t20_foot", "projected, area filter, turned copy, foot check", 0.0125, "neo_hookean", None),
    ("ca0.05_n64_bend0.01_t20_foot", "projected, area filter, turned copy, foot check", 0.05, "neo_hookean", None),
    ("ca0.0125_n128_t10_turn", "projected, area filter, turned copy", 0.0125, "neo_hookean", None),
    ("ca0.025_n64_skalak_C1_t20_foot", "projected, area filter, turned copy, foot check", 0.025, "skalak", 1.0),
    ("ca0.025_n64_skalak_C10_t3_foot", "projected, area filter, turned copy, foot check", 0.025, "skalak", 10.0),
    ("ca0.2_n128_t10_foot", "projected, area filter, turned copy, foot check", 0.2, "neo_hookean", None),
    ("ca0.05_n128_t10_foot", "projected, area filter, turned copy, foot check", 0.05, "neo_hookean", None),
    ("ca0.1_n128_t10_foot", "projected, area filter, turned copy, foot check", 0.1, "neo_hookean", None),
    ("ca0.025_n128_t10_foot", "projected, area filter, turned copy, foot check", 0.025, "neo_hookean", None),
    ("ca0.025_n64_skalak_C10_t8_foot", "projected, area filter, turned copy, foot check", 0.025, "skalak", 10.0),
    # session 27: Skalak C = 10 continued to t = 20
    ("ca0.025_n64_skalak_C10_t20_foot", "projected, area filter, turned copy, foot check", 0.025, "skalak", 10.0),
]


def d_at(t, D, when):
    if when > t[-1] + 1e-9:
        return "-"
    return f"{D[int(np.argmin(np.abs(t - when)))]:.3f}"


def main() -> int:
    print("| run | strain model | t reached | D(1) | D(2) | D(3) | D(5) | D(10) | steady D "
          "| published | error | max abs D error, full range | max tr Gs | max area change "
          "| reference-area drift | wall per shear time [s] (ranks) |")
    print("|---" * 16 + "|")
    for name, model, ca, law, c in RUNS:
        rec = HERE / name
        if not (rec / "bodies.csv").exists():
            continue
        m = measure(rec)
        t, D, _, _ = body_series(rec)
        # no published steady value with bending (capsule_longtime compares none either)
        ref = None if "_bend" in name else steady_reference(ca, law, c)
        published = "-" if ref is None else f"{ref:.3f}"
        error = "-" if ref is None else f"{m['steady_D'] - ref:+.3f}"
        full = full_range_error(t, D, ca, law, 1.0 if "_bend" in name else 0.0)
        full = "-" if full is None else f"{full:.3f}"
        drift = m["reference_area_drift"]
        # (records made before reference_area left out rank-lost cells hold ~1e143)
        ref_drift = ("-" if drift is None else f"{drift:.2%}" if drift < 10
                     else "not measurable (rank-lost cells counted)")
        # a run resumed from a checkpoint: summary.json times the last part only
        resumed = bool(json.loads((rec / "summary.json").read_text()).get("restarted_from"))
        wall = ("-" if not m.get("wall_seconds") or m["t_end"] <= 0
                else "- (resumed)" if resumed
                else f"{m['wall_seconds'] / m['t_end']:.0f} ({m['ranks']})")
        print(f"| {name} | {model} | {m['t_end']:.3g} ({m['status']}) | "
              + " | ".join(d_at(t, D, w) for w in (1, 2, 3, 5, 10))
              + f" | {m['steady_D']:.3f} | {published} | {error} | {full} "
              f"| {m['max_trace_Gs']:.2f} | {m['max_area_change']:.1%} | {ref_drift} "
              f"| {wall} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
