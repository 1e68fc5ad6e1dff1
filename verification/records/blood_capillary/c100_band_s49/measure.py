"""capillary_coarse with stiff-area red cells (Skalak C = 100) and the increment damping
confined to the membranes' bands (time.increment_damping = 9, increment_damping_on =
"membranes"), against the same scene without it (the session-47 run of record c100_s47),
both on 2 ranks to 1 ms. F = 9 relaxes the red cells' membrane limit (6.84e-4 ms at cfl 0.5)
past the platelets' elastic limit (6e-3 ms), which then sets the step. Per run: c100_s47's
measures (steps, time step, seconds per ms, the red cells' stored-strain drift, area change,
reference-area change, max tr Gs, volume drift, the largest overlap of two bodies over the
snapshots), and at each field snapshot the flow rate and the cell-free layer (the
blood_capillary study's definitions, one snapshot each). Writes result.md beside this file.

    /usr/bin/python3 verification/records/blood_capillary/c100_band_s49/measure.py \
        build/runs/cap_C100 build/runs/cap_C100_band9 build/runs/cap_C100_band9_t3 \
        build/runs/c100cont_plain build/runs/c100cont_band4 build/runs/c100cont_band9

where the two runs were made by (2 ranks; the first in two legs of 0.5 ms, c100_s47)
    mpirun -np 2 build/bin/efsi run cases/capillary_coarse -o build/runs/cap_C100 \
        --set 'seeding.kind[1].body.area_dilation=100' --set time.end_time=1
    mpirun -np 2 build/bin/efsi run cases/capillary_coarse -o build/runs/cap_C100_band9 \
        --set 'seeding.kind[1].body.area_dilation=100' --set time.end_time=1 \
        --set time.increment_damping=9 --set 'time.increment_damping_on="membranes"'
cap_C100_band9_t3 continues the second from its checkpoint to 3 ms (--restart, end_time 3);
the c100cont_* runs continue the FIRST (undamped) run from its 1 ms checkpoint with
output.fields = false, output.diagnostics_every = 5 and time.increment_damping = 1 (plain,
to 1.3 ms, then continued from its checkpoint to 1.6 ms), 4.5 (band4, to 1.6 ms) and 9
(band9, to 1.6 ms), increment_damping_on =
"membranes": the same state, three dampings. c100cont_flow9 is band9 with the damping
applied to v* - (v^n + dt A^n), v^n carried one step by its own advection (a key
time.increment_damping_frame = "flow" of an uncommitted binary, 1de4f18 plus
that change, tried and not kept: docs/method.md). The second table gives, per interval, the
largest speed (diagnostics.csv) and the largest tr Gs over the red cells (bodies.csv).

    /usr/bin/python3 verification/records/blood_capillary/c100_band_s49/measure.py \
        build/runs/cap_C100 build/runs/cap_C100_band9 build/runs/cap_C100_band9_t3 \
        build/runs/c100cont_plain build/runs/c100cont_band4 build/runs/c100cont_band9 \
        build/runs/c100cont_flow9
"""
import csv
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2] / "studies"))
sys.path.insert(0, str(HERE.parent / "c100_s47"))
from blood_capillary import (R_LUMEN, flow_rate, rbc_edge_radii, snapshot_time,  # noqa: E402
                             snapshots)
from measure import measure, worst_overlap  # noqa: E402 (c100_s47's)


def per_snapshot(out: Path, h: float) -> dict:
    """{t: (flow rate [um^3/ms], cell-free layer [um])} at each field snapshot after t = 0."""
    rows = {}
    for p in snapshots(out):
        t = snapshot_time(p)
        if t > 0:
            edges = rbc_edge_radii(p, h)
            rows[round(t, 6)] = (flow_rate(p, h), R_LUMEN - float(np.mean(edges)))
    return rows


def growth(out: Path, edges) -> list:
    """Per interval (a, b] of `edges`: (largest speed, largest tr Gs over the red cells), or
    None past the run's end."""
    with open(out / "diagnostics.csv") as f:
        d = [(float(r["time"]), float(r["max_speed"])) for r in csv.DictReader(f)]
    with open(out / "bodies.csv") as f:
        b = [(float(r["time"]), float(r["tensor_trace_max"])) for r in csv.DictReader(f)
             if r["body"].startswith("rbc")]
    cells = []
    for a, e in zip(edges[:-1], edges[1:]):
        v = [x for t, x in d if a < t <= e + 1e-9]
        g = [x for t, x in b if a < t <= e + 1e-9]
        cells.append((max(v), max(g)) if v and g and max(t for t, _ in d) >= e - 1e-9 else None)
    return cells


def main():
    plain, band = Path(sys.argv[1]), Path(sys.argv[2])
    h = 22.0 / 64
    a, b = measure(plain, np.inf), measure(band, np.inf)
    ov = [worst_overlap(o, min(a["t reached [ms]"], b["t reached [ms]"])) for o in (plain, band)]
    sa, sb = per_snapshot(plain, h), per_snapshot(band, h)
    load = json.loads((band / "summary.json").read_text()).get("load_before", ["-"])
    fmt = lambda v: v if isinstance(v, str) else (f"{v:.4g}" if isinstance(v, float) else str(v))
    lines = ["# C = 100 red cells with the increment damping on their bands (session 49)", "",
             "Made by `measure.py` (this folder). capillary_coarse with "
             "`seeding.kind[1].body.area_dilation = 100`, 2 ranks, to 1 ms: without damping "
             "(the run of record c100_s47) and with `time.increment_damping = 9`, "
             "`time.increment_damping_on = \"membranes\"`. 1-minute load before the damped "
             f"run: {load[0]}.", "",
             "| quantity | C = 100 | C = 100, band damping F = 9 |", "|---|---|---|"]
    for k in a:
        lines.append(f"| {k} | {fmt(a[k])} | {fmt(b[k])} |")
    lines.append(f"| largest overlap of two bodies (sharp red cells), snapshots | "
                 f"{ov[0][0]:.3g} ({ov[0][1]} snapshots) | {ov[1][0]:.3g} ({ov[1][1]} snapshots) |")
    lines += ["", "| t [ms] | flow rate [um^3/ms] | with damping | relative difference | "
              "cell-free layer [um] | with damping |", "|---|---|---|---|---|---|"]
    for t in sorted(set(sa) & set(sb)):
        qa, ca = sa[t]
        qb, cb = sb[t]
        lines.append(f"| {t:g} | {qa:.2f} | {qb:.2f} | {qb / qa - 1:+.2e} | {ca:.3f} | "
                     f"{cb:.3f} |")
    if len(sys.argv) > 3:
        t3 = Path(sys.argv[3])
        edges = [0.0, 1.0, 2.0, 2.8, 3.0]
        lines += ["", "The damped run continued to 3 ms (largest speed [um/ms] / max tr Gs over "
                  "the red cells, per interval; the flow's own speed is about 8 um/ms):", "",
                  "| run | " + " | ".join(f"({a:g}, {e:g}] ms" for a, e in
                                          zip(edges[:-1], edges[1:])) + " |",
                  "|---|" + "---|" * (len(edges) - 1)]
        lines.append(f"| {t3.name} | " + " | ".join(
            "-" if c is None else f"{c[0]:.1f} / {c[1]:.2f}" for c in growth(t3, edges)) + " |")
        edges = [1.0, 1.1, 1.2, 1.3, 1.45, 1.6]
        lines += ["", "From the undamped run's 1 ms state (largest speed [um/ms] / max tr Gs over "
                  "the red cells, per interval):", "",
                  "| run | F | damped increment | " + " | ".join(f"({a:g}, {e:g}] ms" for a, e in
                                              zip(edges[:-1], edges[1:])) + " |",
                  "|---|---|---|" + "---|" * (len(edges) - 1)]
        for arg in sys.argv[4:]:
            out = Path(arg)
            case = (out / "case.toml").read_text()
            F = next((ln.split("=")[1].strip() for ln in case.splitlines()
                      if ln.startswith("increment_damping =")), "1")
            frame = ("v* - (v^n + dt A^n)" if "increment_damping_frame = 'flow'" in case
                     else "v* - v^n")
            lines.append(f"| {out.name} | {F} | {frame if F != '1' else '-'} | " + " | ".join(
                "-" if c is None else f"{c[0]:.1f} / {c[1]:.2f}" for c in growth(out, edges)) +
                " |")
    (HERE / "result.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
