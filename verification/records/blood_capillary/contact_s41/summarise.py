"""capillary_coarse to 3 ms with contact stiffnesses k = 0, 20, 200, 2000 Pa (session 41, issue
20): per run the largest body overlap over the snapshots (blood_capillary's
`max_body_overlap`: the bodies' sharp equivalents), its value at 3 ms, the relative apparent
viscosity against the plasma-only run, the cell-free layer and the red cells' stored-strain
drift, all with the study's own measures. The snapshots are not kept (1.3 GB a run); the
runs are remade by the commands in README.md. Writes result.md beside this script.

    /usr/bin/python3 verification/records/blood_capillary/contact_s41/summarise.py \\
        PLASMA_RUN K0_RUN K200_RUN [K2000_RUN]
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
K20 = HERE.parent / "contact_k20_t3" / "overlap_k20.md"  # session 39's k = 20 run (no snapshots)


def second_half(run: Path):
    t_end = float(json.loads((run / "summary.json").read_text())["time"])
    return [p for p in bc.snapshots(run) if bc.snapshot_time(p) >= 0.5 * t_end - 1e-9]


def flow(run: Path) -> float:
    return float(np.mean([bc.flow_rate(p, H) for p in second_half(run)]))


def main(plasma: Path, runs: list[Path]):
    q_plasma = flow(plasma)
    rows = ["| run | contact.stiffness [Pa] | status, t [ms] | max_body_overlap over the "
            "snapshots (at t) | at 3 ms | relative apparent viscosity | cell-free layer [um] | "
            "red cells' stored-strain drift (largest) |", "|---|---|---|---|---|---|---|---|"]
    for run in runs:
        s = json.loads((run / "summary.json").read_text())
        case = (run / "case.toml").read_text()
        k = 0.0
        if "[contact]" in case:
            k = float(case.split("[contact]")[1].split("stiffness =")[1].split()[0])
        widths = bc.smoothing_widths(run)
        series = [(bc.snapshot_time(p), *bc.worst_pair(p, widths)) for p in bc.snapshots(run)]
        t_max, o_max, pair = max(series, key=lambda x: x[1])
        edges = [r for p in second_half(run) for r in bc.rbc_edge_radii(p, H)]
        per = bc.bodies(run)
        rows.append(f"| `{run.name}` | {k:g} | {s['status']}, {float(s['time']):g} | "
                    f"{o_max:.4f} ({t_max:.2f}, {' and '.join(pair)}) | {series[-1][1]:.4f} | "
                    f"{q_plasma / flow(run):.3f} | {bc.R_LUMEN - float(np.mean(edges)):.3f} | "
                    f"{bc.reference_area_drift(per):.4f} |")
    rows += ["", f"k = 20 Pa (session 39, `../contact_k20_t3`, snapshots not kept): its "
             "overlap table, " + K20.name + ", ends at 3 ms with "
             + K20.read_text().strip().splitlines()[-1].split("|")[2].strip() + ".",
             "", "Overlap per snapshot:", ""]
    for run in runs:
        widths = bc.smoothing_widths(run)
        series = [(bc.snapshot_time(p), bc.worst_pair(p, widths)) for p in bc.snapshots(run)]
        rows.append(f"- `{run.name}`: " + ", ".join(
            f"{t:.2f}: {o:.4f}" for t, (o, _) in series))
    (HERE / "result.md").write_text("\n".join(rows) + "\n")
    print("\n".join(rows))


if __name__ == "__main__":
    main(Path(sys.argv[1]), [Path(a) for a in sys.argv[2:]])
