"""The largest relative differences (max |a - b| / max |a|) of two checkpoints' datasets: the
six largest, and the velocity's.

    /usr/bin/python3 compare_checkpoints.py A/checkpoint.h5 B/checkpoint.h5
"""
import sys

import h5py
import numpy as np

a, b = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
res = []
for k in a.keys():
    if isinstance(a[k], h5py.Dataset) and a[k].dtype.kind == "f":
        x, y = a[k][...], b[k][...]
        res.append((float(np.max(np.abs(x - y))) / max(1e-300, float(np.max(np.abs(x)))), k))
res.sort(reverse=True)
print(res[:6])
print("velocity", [r for r in res if r[1].startswith("velocity")])
