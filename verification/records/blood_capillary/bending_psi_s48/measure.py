"""The bending force's psi = eps atanh(2 phi - 1) over the patch with the empty and full cells'
value computed once (session 48) against computing it in every cell: two efsi binaries, 10 steps of
cases/capillary_coarse from one checkpoint at step 10, alternated twice on 1 rank; the
largest relative difference of every dataset of their checkpoints and the stage times.
Writes result.md beside this script.

    /usr/bin/python3 verification/records/blood_capillary/bending_psi_s48/measure.py \
        OLD_EFSI NEW_EFSI START_CHECKPOINT WORKDIR      (from the repository root)

START_CHECKPOINT: a checkpoint of cases/capillary_coarse at step 10 with output.fields=false
and output.diagnostics_every=5 (band_transport_s48/measure.py makes one, WORKDIR/start).
"""
import json
import os
import pathlib
import subprocess
import sys

import h5py
import numpy as np

old, new, start, work = sys.argv[1], sys.argv[2], sys.argv[3], pathlib.Path(sys.argv[4])
work.mkdir(parents=True, exist_ok=True)
SETS = ["output.fields=false", "output.diagnostics_every=5", "time.max_steps=20"]


def run(exe, out):
    cmd = [exe, "run", "cases/capillary_coarse", "-o", str(out), "-q", "--restart", start]
    for s in SETS:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    return json.load(open(out / "summary.json"))


legs = {"every cell (old)": [], "empty and full once (new)": []}
for rep in range(2):
    for label, exe in (("every cell (old)", old), ("empty and full once (new)", new)):
        out = work / f"{'old' if 'old' in label else 'new'}_{rep}"
        s = run(exe, out)
        st = s["stages"]
        legs[label].append((st["body_stress"] / s["steps"],
                            (s["wall_seconds"] - st.get("checkpoint", 0)) / s["steps"], out))
worst = (0.0, "")
with h5py.File(legs["every cell (old)"][0][2] / "checkpoint.h5") as a, \
        h5py.File(legs["empty and full once (new)"][0][2] / "checkpoint.h5") as b:
    for k in a.keys():
        if isinstance(a[k], h5py.Dataset) and a[k].dtype.kind == "f":
            x, y = a[k][...], b[k][...]
            worst = max(worst, (float(np.max(np.abs(x - y))) / max(1e-300, float(np.max(np.abs(x)))), k))
here = pathlib.Path(__file__).parent
with open(here / "result.md", "w") as f:
    f.write("# The bending force's psi, empty and full cells computed once (session 48)\n\nMade by "
            "`measure.py` (this folder): cases/capillary_coarse (C = 10), 10 steps from its "
            "step-10 checkpoint on 1 rank, the two binaries alternated twice, the faster leg of "
            f"each kept. 1-minute load after the runs: {os.getloadavg()[0]:.2f}.\n\n")
    f.write("| psi | body_stress [s/step] | step without checkpoint [s/step] |\n"
            "|---|---|---|\n")
    for label, rows in legs.items():
        f.write(f"| {label} | {min(r[0] for r in rows):.4f} | {min(r[1] for r in rows):.3f} |\n")
    f.write(f"\nLargest relative difference of the two checkpoints' datasets: {worst[0]:.1e} "
            f"({worst[1]}).\n")
print(open(here / "result.md").read())
