"""Compare every dataset of two checkpoints: python3 compare_checkpoints.py A.h5 B.h5"""
import h5py, numpy as np, sys
a, b = h5py.File(sys.argv[1], 'r'), h5py.File(sys.argv[2], 'r')
names = []
a.visit(lambda n: names.append(n) if isinstance(a[n], h5py.Dataset) else None)
worst = 0.0; diff = 0
for n in names:
    x, y = a[n][()], b[n][()]
    if x.dtype.kind in 'fiu':
        d = float(np.max(np.abs(x.astype(float) - y.astype(float)))) if x.size else 0.0
        if d > 0: diff += 1
        worst = max(worst, d)
    elif not np.array_equal(x, y):
        diff += 1
print(f"{len(names)} datasets, {diff} differ, largest difference {worst:g}")
