"""Where the red cell's phi reaches at the end of a run (checkpoint.h5): the cell index range
along each axis of the cells with phi above a few thresholds, and the fitted patch box.
    efsi run verification/records/rbc_in_tube/tens250/case.toml -o OUT -q \
        --set output.fields=false --set time.end_time=3.0
    /usr/bin/python3 extents.py OUT/checkpoint.h5 > extents_t3.md"""
import sys

import h5py
import numpy as np

f = h5py.File(sys.argv[1], "r")
phi = f["body_rbc_phi"][...]  # (z, y, x)
box = [(int(f.attrs[f"body_rbc_fitted_lo{d}"]), int(f.attrs[f"body_rbc_fitted_hi{d}"]))
       for d in range(3)]
print(f"fitted patch box (x, y, z): {box}")
print()
print("| phi above | x range | y range | z range | cells |")
print("|---|---|---|---|---|")
for th in (0.0, 1e-8, 1e-6, 1e-4, 1e-2, 0.5):
    idx = np.argwhere(phi > th)
    lo, hi = idx.min(0)[::-1], idx.max(0)[::-1] + 1
    print(f"| {th:g} | {lo[0]}-{hi[0]} | {lo[1]}-{hi[1]} | {lo[2]}-{hi[2]} | {int((phi > th).sum())} |")
