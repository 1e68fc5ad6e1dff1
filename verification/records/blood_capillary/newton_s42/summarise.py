"""capillary_coarse (to 3 ms) and rbc_in_tube (to 10 ms) with `newton_foot_points = true` on
the red cells, beside the blood_capillary study's full-tier runs without it (session 42,
issue 20): for the capillary the largest body overlap over the snapshots, the relative
apparent viscosity against the plasma-only run, the cell-free layer and the red cells'
stored-strain drift; for the tube every `rbc_in_tube_*` metric. All with the study's own
measures (verification/studies/blood_capillary.py). The snapshots are not kept; the runs
are remade by the commands in README.md. Writes result.md beside this script.

    /usr/bin/python3 verification/records/blood_capillary/newton_s42/summarise.py \\
        PLASMA CELLS CELLS_NEWTON TUBE TUBE_NEWTON
"""
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[3]
sys.path.insert(0, str(REPO / "verification" / "studies"))
sys.path.insert(0, str(REPO / "verification"))
import blood_capillary as bc  # noqa: E402

H = 44.0 / 64  # um, cases/capillary_coarse
H_TUBE = 24.0 / 96  # um, cases/rbc_in_tube


def second_half(run: Path):
    t_end = float(json.loads((run / "summary.json").read_text())["time"])
    return [p for p in bc.snapshots(run) if bc.snapshot_time(p) >= 0.5 * t_end - 1e-9]


def flow(run: Path) -> float:
    return float(np.mean([bc.flow_rate(p, H) for p in second_half(run)]))


def newton(run: Path) -> bool:
    return "newton_foot_points = true" in (run / "case.toml").read_text()


def main(plasma: Path, cells: list[Path], tubes: list[Path]):
    q_plasma = flow(plasma)
    rows = ["## capillary_coarse to 3 ms", "",
            "| run | newton_foot_points | status, t [ms] | max_body_overlap over the snapshots "
            "(at t) | relative apparent viscosity | cell-free layer [um] | red cells' "
            "stored-strain drift (largest) | largest max tr Gs | wall [s] |",
            "|---|---|---|---|---|---|---|---|---|"]
    for run in cells:
        s = json.loads((run / "summary.json").read_text())
        widths = bc.smoothing_widths(run)
        series = [(bc.snapshot_time(p), *bc.worst_pair(p, widths)) for p in bc.snapshots(run)]
        t_max, o_max, pair = max(series, key=lambda x: x[1])
        edges = [r for p in second_half(run) for r in bc.rbc_edge_radii(p, H)]
        per = bc.bodies(run)
        trace = max(float(r["tensor_trace_max"]) for n, rs in per.items()
                    if n.startswith("rbc") for r in rs)
        rows.append(f"| `{run.name}` | {newton(run)} | {s['status']}, {float(s['time']):g} | "
                    f"{o_max:.4f} ({t_max:.2f}, {' and '.join(pair)}) | "
                    f"{q_plasma / flow(run):.3f} | {bc.R_LUMEN - float(np.mean(edges)):.3f} | "
                    f"{bc.reference_area_drift(per):.4f} | {trace:.3f} | "
                    f"{float(s['wall_seconds']):.0f} |")
    rows += ["", "## rbc_in_tube to 10 ms", ""]
    metrics = []
    for run in tubes:
        s = json.loads((run / "summary.json").read_text())
        m, _ = bc.tube_metrics(run, s, H_TUBE)
        metrics.append((run, m, s))
    keys = sorted({k for _, m, _ in metrics for k in m})
    rows.append("| metric | " + " | ".join(f"`{r.name}` (newton {newton(r)})"
                                            for r, _, _ in metrics) + " |")
    rows.append("|---|" + "---|" * len(metrics))
    for k in keys:
        rows.append(f"| {k} | " + " | ".join(f"{m.get(k, float('nan')):.4g}"
                                            for _, m, _ in metrics) + " |")
    rows.append("| wall [s] | " + " | ".join(f"{float(s['wall_seconds']):.0f}"
                                           for _, _, s in metrics) + " |")
    (HERE / "result.md").write_text("\n".join(rows) + "\n")
    print("\n".join(rows))


if __name__ == "__main__":
    a = [Path(x) for x in sys.argv[1:]]
    main(a[0], a[1:3], a[3:5])
