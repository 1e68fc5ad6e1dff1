"""A body read from a voxel mask (shape = "mask": an HDF5 dataset [nz][ny][nx] of cell
volume fractions): its phi is the mask, on its patch only, on 1 and 2 ranks; a mask of the
wrong size and a missing dataset are input errors naming the problem."""
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
with h5py.File(path, "w") as f:
    f["cells"] = mask[None, :, :]
    f["wrong"] = np.zeros((1, 8, 8))

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
h = 1.0 / 16
for ranks in (1, 2):
    out = os.path.join(args.output, f"np{ranks}")
    run(args, case, out, ranks=ranks, sets=grid)
    with open(os.path.join(out, "bodies.csv")) as f:
        rows = list(csv.DictReader(f))
    v0 = float(rows[0]["volume"])
    check(abs(v0 - mask.sum() * h * h * 0.0625) < 1e-12, f"{ranks} rank(s): initial volume {v0:.6e} = mask sum x dV")
    check(int(rows[0]["patch_cells"]) < nx * ny, f"{ranks} rank(s): patch {rows[0]['patch_cells']} cells, not the whole grid")
bad = run(args, case, os.path.join(args.output, "bad"), sets=grid + ['body[0].mask_dataset="wrong"'], expect=None)
check(bad.returncode != 0 and "wrong" in bad.stderr, f"wrong-size mask is refused: {bad.stderr.strip()[:120]}")
missing = run(args, case, os.path.join(args.output, "missing"), sets=grid + ['body[0].mask_dataset="nothing"'], expect=2)
check("nothing" in missing.stderr, f"missing dataset is named: {missing.stderr.strip()[:120]}")
