"""A body read from a voxel mask (shape = "mask": an HDF5 dataset [nz][ny][nx] of cell
volume fractions): its phi is the mask, on its patch only, on 1 and 2 ranks; a finer mask
with its spacing and origin is resampled to the same volume on 1 and 2 ranks; a mask of the
wrong size, one that misses the box and a missing dataset are input errors naming the
problem, found by `efsi check` before anything is allocated or written; a value outside
[0, 1] is named by its voxel on every rank."""
import csv
import os

import h5py
import numpy as np

from efsi_harness import check, parse_args, run

args = parse_args()
nx, ny = 32, 16
y, x = np.mgrid[0:ny, 0:nx]
mask = ((x - 9.5) ** 2 + (y - 7.5) ** 2 < 16).astype(float)  # a disc of radius 4 cells
mask[2, 20:24] = 0.5                                           # and a half-full strip
path = os.path.join(args.output, "mask.h5")
h = 1.0 / 16
# The same disc on voxels of h/2, shifted by h/4 so that every voxel straddles two cells.
fy, fx = np.mgrid[0:2 * ny + 1, 0:2 * nx + 1]
fine = (((fx + 0.5) * h / 2 - h / 4 - 9.5 * h / 1) ** 2
        + ((fy + 0.5) * h / 2 - h / 4 - 7.5 * h) ** 2 < (4 * h) ** 2).astype(float)
bad = mask.copy()
bad[14, 30] = 1.5
with h5py.File(path, "w") as f:
    f["cells"] = mask[None, :, :]
    f["wrong"] = np.zeros((1, 8, 8))
    f["bad"] = bad[None, :, :]
    for name, origin in (("fine", [-h / 4, -h / 4, 0.0]), ("short", [h / 4, -h / 4, 0.0])):
        f[name] = fine[None, :, :]
        f[name].attrs["spacing"] = [h / 2, h / 2, 0.0625]
        f[name].attrs["origin"] = origin

case = os.path.join(args.output, "mask_case.toml")
with open(os.path.join(args.cases, "body_translation", "case.toml")) as f:
    text = f.read()
head = text.split("[[body]]")[0]
with open(case, "w") as f:
    f.write(head.replace("end_time = 1.0", "end_time = 0.05") + f"""
[[body]]
name = "scan"
shape = "mask"
mask_file = "{path}"
mask_dataset = "cells"
""")
grid = [f"grid.cells=[{nx},{ny},1]", "grid.length=[2.0,1.0,0.0625]"]
for ranks in (1, 2):
    out = os.path.join(args.output, f"np{ranks}")
    run(args, case, out, ranks=ranks, sets=grid)
    with open(os.path.join(out, "bodies.csv")) as f:
        rows = list(csv.DictReader(f))
    v0 = float(rows[0]["volume"])
    check(abs(v0 - mask.sum() * h * h * 0.0625) < 1e-12, f"{ranks} rank(s): initial volume {v0:.6e} = mask sum x dV")
    check(int(rows[0]["patch_cells"]) < nx * ny, f"{ranks} rank(s): patch {rows[0]['patch_cells']} cells, not the whole grid")

# Resampled: cell means of 8 x 8 sub-cell samples, 4 x 4 of them in each voxel, so the
# body holds exactly the voxels' volume.
fine_volume = fine.sum() * (h / 2) ** 2 * 0.0625
told = run(args, case, sets=grid + ['body[0].mask_dataset="fine"'], command="check")
check("resampled" in told.stdout, "efsi check says the finer mask is resampled")
for ranks in (1, 2):
    out = os.path.join(args.output, f"fine{ranks}")
    run(args, case, out, ranks=ranks, sets=grid + ['body[0].mask_dataset="fine"'])
    with open(os.path.join(out, "bodies.csv")) as f:
        v0 = float(next(csv.DictReader(f))["volume"])
    check(abs(v0 / fine_volume - 1) < 1e-12,
          f"{ranks} rank(s): resampled volume {v0:.9e} = the fine voxels' {fine_volume:.9e}")

# Refused by `efsi check`, exit 2, nothing written.
for dataset, words in (("wrong", ["8 x 8 x 1 voxels", "32 x 16 x 1 cells", "body[0].mask_file"]),
                       ("short", ["covers [0.015625, 2.04688] m in x", "grid spans [0, 2] m"]),
                       ("nothing", ["no dataset 'nothing'"])):
    out = os.path.join(args.output, f"refused_{dataset}")
    r = run(args, case, sets=grid + [f'body[0].mask_dataset="{dataset}"'], command="check",
            expect=2)
    check(all(w in r.stderr for w in words), f"mask '{dataset}' refused: {r.stderr.strip()[:160]}")
    r = run(args, case, out, sets=grid + [f'body[0].mask_dataset="{dataset}"'], expect=2)
    check(not os.path.exists(out), f"mask '{dataset}': the run writes nothing")

# A value outside [0, 1], read by one of two ranks: both report it by its voxel.
r = run(args, case, os.path.join(args.output, "bad"), ranks=2,
        sets=grid + ['body[0].mask_dataset="bad"'], expect=2)
check("voxel (30, 14, 0)" in r.stderr, f"the bad voxel is named: {r.stderr.strip()[:200]}")
