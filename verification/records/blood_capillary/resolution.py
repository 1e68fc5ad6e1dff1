"""capillary_coarse at twice the resolution: the blood_capillary metrics of a run with
`grid.cells = [128, 64, 64]` (h = 0.344 um) beside the stored full-tier result at the
case's 64 x 32 x 32 (h = 0.6875 um).

    /usr/bin/python3 verification/records/blood_capillary/resolution.py CELLS_RUN PLASMA_RUN \
        [COARSE_BODIES_RUN COARSE_START_RUN]

CELLS_RUN is the scene (capillary_coarse with fields every 0.25 ms to 3 ms), PLASMA_RUN the
wall alone on the same grid (blood_capillary's plasma case); both are measured with
blood_capillary's own functions (the apparent viscosity from the snapshots of the second
half of the run). Prints a markdown table; the coarse column is
verification/results/blood_capillary/result.json, completed, where given, by the red cells'
area change and tr Gs from COARSE_BODIES_RUN's bodies.csv (the record cells_profile0_t3: the
case's keys, 3 ms) and by the overlap of the seeded scene (its first snapshot, t = 0) from
COARSE_START_RUN (the case run for a step or two with fields).
"""
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "verification" / "studies"))
_spec = importlib.util.spec_from_file_location(
    "blood_capillary", REPO / "verification" / "studies" / "blood_capillary.py")
bc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bc)


def area_changes(per: dict) -> tuple[float, float]:
    """Mean and worst over the red cells of A(t_end) / A(0) - 1."""
    ch = [float(rows[-1]["area"]) / float(rows[0]["area"]) - 1
          for name, rows in per.items() if name.startswith("rbc")]
    return float(np.mean(ch)), float(np.max(ch))


def max_trace(per: dict) -> float:
    return max(float(r["tensor_trace_max"]) for name, rows in per.items()
               if name.startswith("rbc") for r in rows)


def measure(cells: Path, plasma: Path) -> dict:
    s = json.loads((cells / "summary.json").read_text())
    h = 44.0 / int(s["grid"][0])
    per = bc.bodies(cells)
    snaps = bc.snapshots(cells)
    t_end = float(s["time"])
    half = 0.5 * t_end
    late = [p for p in snaps if bc.snapshot_time(p) >= half - 1e-9] or snaps[-1:]
    late_plasma = [p for p in bc.snapshots(plasma) if bc.snapshot_time(p) >= half - 1e-9]
    q_cells = float(np.mean([bc.flow_rate(p, h) for p in late]))
    q_plasma = float(np.mean([bc.flow_rate(p, h) for p in late_plasma]))
    edges = [r for p in late for r in bc.rbc_edge_radii(p, h)]
    mean_ch, worst_ch = area_changes(per)
    pries, _ = bc.pries_1992(float(s["seeding"]["achieved_haematocrit"]))
    return {
        "h_um": h,
        "overlap_at_start": bc.overlap(snaps[0]),
        "max_body_overlap_after_start": max(bc.overlap(p) for p in snaps[1:]),
        "t_end_ms": t_end,
        "status": s["status"],
        "steps": s["steps"],
        "ranks": s["ranks"],
        "wall_s": float(s["wall_seconds"]),
        "relative_apparent_viscosity": q_plasma / q_cells,
        "relative_apparent_viscosity_pries1992": pries,
        "flow_rate_cells_um3_per_ms": q_cells,
        "flow_rate_plasma_um3_per_ms": q_plasma,
        "cell_free_layer_um": bc.R_LUMEN - float(np.mean(edges)),
        "rbc_reference_area_drift_max": bc.reference_area_drift(per),
        "max_body_overlap": max(bc.overlap(p) for p in snaps),
        "rbc_area_change_mean": mean_ch,
        "rbc_area_change_worst": worst_ch,
        "rbc_max_trace_Gs": max_trace(per),
        "platelet_radial_rms_fluctuation_with_rbc_um": bc.rms_fluctuation(
            bc.platelet_radii(per), half),
    }


def main() -> int:
    if len(sys.argv) not in (3, 5):
        print(__doc__)
        return 2
    fine = measure(Path(sys.argv[1]), Path(sys.argv[2]))
    coarse = json.loads((REPO / "verification" / "results" / "blood_capillary" /
                         "result.json").read_text())["metrics"]
    if len(sys.argv) == 5:
        per = bc.bodies(Path(sys.argv[3]))
        coarse["rbc_area_change_mean"], coarse["rbc_area_change_worst"] = area_changes(per)
        coarse["rbc_max_trace_Gs"] = max_trace(per)
        coarse["overlap_at_start"] = bc.overlap(bc.snapshots(Path(sys.argv[4]))[0])
    print("| quantity | h = 0.6875 um (stored full tier) | h = %.4f um |" % fine["h_um"])
    print("|---|---|---|")
    for k, v in fine.items():
        c = coarse.get(k, "-")
        fmt = (lambda x: f"{x:.4g}" if isinstance(x, float) else str(x))
        print(f"| {k} | {fmt(c)} | {fmt(v)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
