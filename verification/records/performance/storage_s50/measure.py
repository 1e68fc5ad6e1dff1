"""Snapshot and checkpoint storage before and after session 50: a body's fields in a snapshot
in deflated chunks, in the checkpoint on its patch box only, instead of contiguous zero-filled
arrays on the whole grid (io/hdf5_file.cpp, io/checkpoint.cpp). cases/capillary_coarse, one
step from a (format 2) checkpoint at step 10 with a snapshot at step 11, on 2 ranks, the efsi
of the session's start (d68bb62) and the session's alternated twice: the files' sizes, the
output and checkpoint stages (the faster leg of each), and the largest difference between
the two binaries' snapshots and checkpoints over every dataset (a checkpoint's patch boxes
placed on the grid: the values must not move). Writes result.md beside this script.

    /usr/bin/python3 verification/records/performance/snapshot_storage_s50/measure.py \
        OLD_EFSI NEW_EFSI START_CHECKPOINT WORKDIR      (from the repository root)

OLD_EFSI: built from d68bb62 (git worktree add /tmp/wt_old d68bb62; cmake -S /tmp/wt_old -B
/tmp/wt_old/build -DCMAKE_BUILD_TYPE=Release; cmake --build /tmp/wt_old/build --target efsi).
START_CHECKPOINT: a checkpoint of cases/capillary_coarse at step 10 (efsi run
cases/capillary_coarse -o DIR --set time.max_steps=10 --set output.fields=false).
"""
import glob
import os
import pathlib
import sys

import h5py
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "blood_capillary"))
from capillary_ab import run_capillary  # noqa: E402

old, new, start, work = sys.argv[1], sys.argv[2], sys.argv[3], pathlib.Path(sys.argv[4])
work.mkdir(parents=True, exist_ok=True)
SETS = ["time.max_steps=11", "output.fields_interval=0.0001"]


def snapshot(out):
    return sorted(glob.glob(str(out / "fields" / "fields_0*.h5")))[-1]


load_before = os.getloadavg()[0]
legs = {"start (d68bb62)": [], "session 50": []}
for rep in range(2):
    for label, exe, tag in (("start (d68bb62)", old, "old"), ("session 50", new, "new")):
        out = work / f"{tag}_{rep}"
        s = run_capillary(exe, out, SETS, restart=start, ranks=2)
        legs[label].append((s["stages"]["output"], s["stages"]["checkpoint"],
                            os.path.getsize(snapshot(out)), out,
                            os.path.getsize(out / "checkpoint.h5")))
worst, worst_name, count = 0.0, "", 0
with h5py.File(snapshot(legs["start (d68bb62)"][0][3])) as a, \
        h5py.File(snapshot(legs["session 50"][0][3])) as b:
    assert sorted(a.keys()) == sorted(b.keys()), "the snapshots hold different datasets"
    body = [k for k in b.keys() if b[k].chunks is not None]
    for k in a.keys():
        x, y = a[k][...], b[k][...]
        d = float(np.max(np.abs(x - y))) if x.size else 0.0
        count += 1
        if d >= worst:
            worst, worst_name = d, k
    compression = {b[k].compression for k in body}


def grid_values(path):
    """Every dataset of a checkpoint, a body's patch box (box_lo) placed on the grid."""
    out = {}
    with h5py.File(path) as f:
        for k in f.keys():
            if isinstance(f[k], h5py.Dataset):
                v = f[k][...]
                if "box_lo" in f[k].attrs:
                    x0, y0, z0 = (int(c) for c in f[k].attrs["box_lo"])
                    full = np.zeros(f["pressure"].shape)
                    full[z0:z0 + v.shape[0], y0:y0 + v.shape[1], x0:x0 + v.shape[2]] = v
                    v = full
                out[k] = v
    return out


ca = grid_values(legs["start (d68bb62)"][0][3] / "checkpoint.h5")
cb = grid_values(legs["session 50"][0][3] / "checkpoint.h5")
assert sorted(ca) == sorted(cb), "the checkpoints hold different datasets"
ck_worst = max((float(np.max(np.abs(ca[k] - cb[k]))) if ca[k].size else 0.0, k) for k in ca)
with open(pathlib.Path(__file__).with_name("result.md"), "w") as f:
    f.write("# Snapshot and checkpoint storage of a body's fields (session 50)\n\n"
            "Made by `measure.py` (this folder): cases/capillary_coarse, one step from its "
            "step-10 checkpoint with a snapshot at step 11, 2 ranks, the two binaries "
            "alternated twice, the faster leg of each kept. 1-minute load before / after the "
            f"runs: {load_before:.2f} / {os.getloadavg()[0]:.2f} (2 cores).\n\n")
    f.write("| binary | snapshot [MB] | checkpoint [MB] | output stage [s] | "
            "checkpoint stage [s] |\n|---|---|---|---|---|\n")
    for label, rows in legs.items():
        f.write(f"| {label} | {min(r[2] for r in rows) / 1e6:.1f} | "
                f"{min(r[4] for r in rows) / 1e6:.1f} | "
                f"{min(r[0] for r in rows):.2f} | {min(r[1] for r in rows):.2f} |\n")
    f.write(f"\nThe session's snapshot stores {len(body)} datasets in chunks "
            f"({', '.join(sorted(map(str, compression)))}); over all {count} datasets the "
            f"largest difference between the two snapshots is {worst:g} ({worst_name}); over "
            f"the checkpoints' {len(ca)} datasets (a body's patch box placed on the grid) "
            f"{ck_worst[0]:g} ({ck_worst[1]}).\n")
print(open(pathlib.Path(__file__).with_name("result.md")).read())
