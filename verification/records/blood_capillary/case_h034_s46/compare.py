"""The blood_capillary full-tier result before and after capillary_coarse moved to
128 x 64 x 64 cells (session 46): the stored result.json of commit ac26edd (64 x 32 x 32,
seeding gap 0.2 um) against the one in the working tree. Writes result.md beside this file.

    /usr/bin/python3 verification/records/blood_capillary/case_h034_s46/compare.py
"""
import json
import subprocess
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[3]
RESULT = "verification/results/blood_capillary/result.json"
OLD = "ac26edd"
KEYS = [("max_body_overlap", "<= 1e-3"), ("rbc_reference_area_drift_max", "<= 0.05"),
        ("body_overlap_at_start", ""), ("max_body_overlap_profiles", ""),
        ("relative_apparent_viscosity", ""), ("relative_apparent_viscosity_pries1992", ""),
        ("cell_free_layer_um", ""), ("platelet_radial_rms_fluctuation_with_rbc_um", ""),
        ("platelet_radial_rms_fluctuation_without_rbc_um", ""), ("achieved_ht", ">= 0.19"),
        ("volume_drift_max", "<= 1e-9"), ("seconds_per_ms_physical", ""),
        ("seconds_per_ms_physical_2ranks", "")]

old = json.loads(subprocess.run(["git", "show", f"{OLD}:{RESULT}"], cwd=REPO, check=True,
                                capture_output=True, text=True).stdout)
new = json.loads((REPO / RESULT).read_text())
lines = ["# blood_capillary full tier: capillary_coarse at h = 0.6875 um and at h = 0.34375 um",
         "", f"Made by `compare.py` (this folder) from the stored result of {OLD} and the "
         "working tree's.", "",
         f"| metric | bound | 64 x 32 x 32, gap 0.2 um ({OLD}) | 128 x 64 x 64, gap one cell |",
         "|---|---|---|---|"]
for k, bound in KEYS:
    a, b = old["metrics"].get(k), new["metrics"].get(k)
    lines.append(f"| `{k}` | {bound or '-'} | {a:.4g} | {b:.4g} |")
lines += ["", "Runs (the tables' wall times and loads):", ""]
for label, r in (("before", old), ("after", new)):
    for row in r["tables"]["runs"]:
        lines.append(f"- {label}: {row['run']}: {row['status']}, {row['steps']} steps, "
                     f"{row['ranks']} rank(s), {row['wall [s]']} s, load {row['load before']}")
lines += ["", """The new runs: `EFSI_VERIFY_RANKS` unset (1 rank), `/usr/bin/python3 verification/run.py
blood_capillary --tier full`, 2026-12-06 12:35-13:42 UTC, binary of ac26edd's solver with the
case files of session 46; the runs follow each other, so each run's load before is the
previous run's. During the tube run (the last) a build ran on the other core; no rate is
taken from the tube run. `plasma_coarse` ran in a second pass of the study (the others
cached), made for the memory fit of `rate_flow_bytes_per_cell_hypre`."""]
(HERE / "result.md").write_text("\n".join(lines) + "\n")
print("\n".join(lines))
