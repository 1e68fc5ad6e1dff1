"""capillary_coarse to t = 1 ms on one rank, run by the binary before the session-38 patch
fix (b659aa5, patches keep every cell with phi > 0) and after it (residues dropped and put
back on the band): the bodies' total patch cells and volume at t = 0, 0.54 and 1 ms, and the
largest relative differences of the checkpoints' fields.
    efsi run cases/capillary_coarse -o OUT -q --set time.end_time=1.0 --set output.fields=false
    /usr/bin/python3 compare.py OLD_OUT NEW_OUT > result.md"""
import collections
import csv
import sys

import h5py
import numpy as np

old, new = sys.argv[1], sys.argv[2]
print("| run | t [ms] | patch cells, all bodies | volume, all bodies [um^3] |")
print("|---|---|---|---|")
for label, out in (("before", old), ("after", new)):
    by = collections.defaultdict(list)
    for r in csv.DictReader(open(f"{out}/bodies.csv")):
        by[r["time"]].append(r)
    ts = sorted(by, key=float)
    for t in (ts[0], ts[len(ts) // 2], ts[-1]):
        print(f"| {label} | {float(t):g} | {sum(int(x['patch_cells']) for x in by[t])} | "
              f"{sum(float(x['volume']) for x in by[t]):.13g} |")
print()
f, g = h5py.File(f"{new}/checkpoint.h5"), h5py.File(f"{old}/checkpoint.h5")
for k in ("velocity_u", "velocity_v", "velocity_w", "pressure"):
    a, b = f[k][...], g[k][...]
    print(f"- {k}: max |after - before| / max |before| = {np.abs(a - b).max() / np.abs(b).max():.2g}")
