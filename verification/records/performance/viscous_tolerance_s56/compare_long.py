"""capillary_coarse from t = 0 to 1 ms on 1 rank with solver.viscous.tolerance = 1e-6 against
the blood_capillary full tier's run with cells (the default 1e-10, same binary's solver code,
same output times): the flow rate and the largest velocity difference at each snapshot, and
the bodies' centroids at 1 ms.

    python3 compare_long.py build/verification/blood_capillary/runs/full/cells /tmp/vt_long_1e-6
"""
import csv
import glob
import sys

import h5py
import numpy as np

H = 44.0 / 128  # um


def snaps(d):
    out = {}
    for p in sorted(glob.glob(f"{d}/fields/fields_*.h5")):
        with h5py.File(p, "r") as f:
            out[round(float(f.attrs["time"]), 9)] = p
    return out


def centroids(d, t):
    with open(f"{d}/bodies.csv") as f:
        rows = [r for r in csv.DictReader(f) if abs(float(r["time"]) - t) < 1e-6]
    return {r["body"]: np.array([float(r[k]) for k in ("centroid_x", "centroid_y",
                                                      "centroid_z")]) for r in rows}


a, b = sys.argv[1:3]
sa, sb = snaps(a), snaps(b)
print("| t [ms] | flow rate 1e-10 [um^3/ms] | flow rate 1e-6 | relative difference | "
      "largest |u| difference [um/ms] | largest |u| |")
print("|---|---|---|---|---|---|")
for t in sorted(set(sa) & set(sb)):
    with h5py.File(sa[t], "r") as fa, h5py.File(sb[t], "r") as fb:
        ua, ub = fa["faces_u"][...], fb["faces_u"][...]
    qa, qb = (float(u.sum(axis=(0, 1)).mean() * H * H) for u in (ua, ub))
    rel = abs(qb - qa) / abs(qa) if qa else 0.0
    print(f"| {t:g} | {qa:.6f} | {qb:.6f} | {rel:.2e} | {np.max(np.abs(ua - ub)):.2e} | "
          f"{np.max(np.abs(ua)):.3f} |")
def times(d):
    with open(f"{d}/bodies.csv") as f:
        return {round(float(r["time"]), 6) for r in csv.DictReader(f)}


tl = max(times(a) & times(b))
ca, cb = centroids(a, tl), centroids(b, tl)
d = max(float(np.max(np.abs(ca[k] - cb[k]))) for k in ca if k in cb)
print(f"\nlargest centroid difference at t = {tl:g} ms over {len(ca)} bodies: {d:.2e} um")
