"""The end states of two runs of ab.sh: python3 compare_states.py DIR_A DIR_B

The flow's fields (velocity, pressure) are compared in full. The bodies' fields sit on
patches whose boxes differ between the binaries (a patch across the seam against one over
the whole of x), so each body's phi is compared at the cells both boxes hold (the crossing
box's x indices taken modulo n), and the bodies' rows of bodies.csv at the last time."""
import csv
import sys

import h5py
import numpy as np


def last_rows(d):
    with open(f"{d}/bodies.csv") as f:
        rows = list(csv.DictReader(f))
    t = max(float(r["time"]) for r in rows)
    return {r["body"]: r for r in rows if float(r["time"]) == t}


def on_grid(ds, n):
    """A body dataset (z, y, x order; box_lo in x, y, z) spread onto an array whose x runs
    over the n periodic columns, with a mask of the cells its box holds."""
    lo, a = ds.attrs["box_lo"], ds[()]
    full = np.zeros(a.shape[:2] + (n,)); held = np.zeros_like(full, bool)
    for i in range(a.shape[2]):
        full[..., (lo[0] + i) % n] = a[..., i]; held[..., (lo[0] + i) % n] = True
    return full, held, tuple(lo[1:])


a, b = (h5py.File(f"{d}/checkpoint.h5", "r") for d in sys.argv[1:3])
for name in ("velocity_u", "velocity_v", "velocity_w", "pressure"):
    x, y = a[name][()], b[name][()]
    print(f"{name}: largest difference {np.max(np.abs(x - y)):.3e} "
          f"(largest value {np.max(np.abs(x)):.3e})")
n = a["velocity_u"].shape[2]
worst, count = 0.0, 0
for name in a:
    if not (name.startswith("body_") and name.endswith("_phi")) or name not in b:
        continue
    fa, ha, lya = on_grid(a[name], n); fb, hb, lyb = on_grid(b[name], n)
    if tuple(lya) != tuple(lyb) or fa.shape != fb.shape:  # y, z boxes differ: skip
        continue
    both = ha & hb
    worst = max(worst, float(np.max(np.abs(fa - fb)[both]))); count += 1
print(f"bodies' phi, {count} bodies compared where both boxes hold them: "
      f"largest difference {worst:.3e}")
ra, rb = last_rows(sys.argv[1]), last_rows(sys.argv[2])
for key in ("centroid_x", "centroid_y", "centroid_z", "volume"):
    if key not in next(iter(ra.values())):
        continue
    d = max(abs(float(ra[k][key]) - float(rb[k][key])) for k in ra)
    print(f"bodies.csv {key}: largest difference {d:.3e}")
