"""The red cells' area measured on the phi = 1/2 surface itself (marching tetrahedra on the
cell centres, x wrapped around the periodic seam) next to the solver's own measure, the
integral of |grad phi| (bodies.csv `area`), in the field snapshots of four runs: the C = 100
and C = 10 red cell in the tube (rbc_in_tube) and the C = 100 and C = 10 blood scene
(capillary_coarse). Asks whether the area growth of docs/method.md ("A red cell in a 10 um
tube") is the measure's or the surface's. Writes result.md beside this script.

    /usr/bin/python3 verification/records/rbc_in_tube/iso_area_s48/measure.py   (from the
        repository root, with the runs under build/: see RUNS)
"""
import csv
import glob
import pathlib
import re

import h5py
import numpy as np

RUNS = [  # label, folder, the record that made it
    ("tube, C = 100", "build/runs/rbc_tube_C100", "rbc_in_tube/c100_t3_s47"),
    ("tube, C = 10", "build/verification/blood_capillary/runs/full/tube",
     "blood_capillary study, full tier"),
    ("capillary_coarse, C = 100", "build/runs/cap_C100", "blood_capillary/c100_s47"),
    ("capillary_coarse, C = 10", "build/verification/blood_capillary/runs/full/cells",
     "blood_capillary study, full tier"),
]
CORNERS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                    [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
TETS = [(0, 5, 1, 6), (0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6)]


def iso_area(f, level):
    """Area (in cells^2) of the level set of f[z, y, x] by marching tetrahedra (six per cube,
    linear along the edges)."""
    f = f - level
    nz, ny, nx = f.shape
    vals = np.stack([f[c[2]:nz - 1 + c[2], c[1]:ny - 1 + c[1], c[0]:nx - 1 + c[0]].ravel()
                     for c in CORNERS])
    cut = (vals.min(0) < 0) & (vals.max(0) > 0)
    vals = vals[:, cut]
    pos = np.stack(np.unravel_index(np.nonzero(cut)[0], (nz - 1, ny - 1, nx - 1))[::-1],
                   1).astype(float)
    total = 0.0
    for t in TETS:
        v = np.stack([vals[k] for k in t], 1)
        p = np.stack([pos + CORNERS[k] for k in t], 1)
        neg = v < 0
        nneg = neg.sum(1)
        for m in (1, 2, 3):
            sel = nneg == m
            if not sel.any():
                continue
            vs, ps = v[sel], p[sel]
            order = np.argsort(~neg[sel], axis=1, kind="stable")  # inside corners first
            vs = np.take_along_axis(vs, order, 1)
            ps = np.take_along_axis(ps, order[:, :, None], 1)

            def at(a, b):
                s = (vs[:, a] / (vs[:, a] - vs[:, b]))[:, None]
                return ps[:, a] + s * (ps[:, b] - ps[:, a])

            def tri(a, b, c):
                return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()

            if m == 1:
                total += tri(at(0, 1), at(0, 2), at(0, 3))
            elif m == 3:
                total += tri(at(3, 0), at(3, 1), at(3, 2))
            else:
                a, b, c, d = at(0, 2), at(0, 3), at(1, 3), at(1, 2)
                total += tri(a, b, c) + tri(a, c, d)
    return total


def snapshot_step(path):
    return int(re.search(r"fields_(\d+)\.h5$", path).group(1))


def measure(folder):
    folder = pathlib.Path(folder)
    rows = {}
    with open(folder / "bodies.csv") as f:
        for r in csv.DictReader(f):
            if r["body"].startswith("rbc"):
                rows[(int(r["step"]), r["body"])] = r
    out = []  # (step, time, body, iso area, csv area, csv reference area)
    for path in sorted(glob.glob(str(folder / "fields" / "fields_*.h5"))):
        step = snapshot_step(path)
        with h5py.File(path) as F:
            shape = F["faces_u"].shape
            names = [k[4:] for k in F if k.startswith("phi_rbc")]
            for name in names:
                row = rows.get((step, name))
                if row is None:
                    continue
                phi = F["phi_" + name][()].reshape(shape)
                phi = np.concatenate([phi, phi[:, :, :1]], axis=2)  # x is periodic
                out.append((step, float(row["time"]), name, iso_area(phi, 0.5),
                            float(row["area"]), float(row["reference_area"])))
    return out


def main():
    here = pathlib.Path(__file__).parent
    lines = ["# The red cells' area on the phi = 1/2 surface (session 48)", "",
             "Made by `measure.py` (this folder) from the runs' field snapshots: A_iso the "
             "area of the phi = 1/2 surface (marching tetrahedra), A the solver's integral of "
             "|grad phi| (bodies.csv), A_ref the area the stored strain implies (bodies.csv "
             "`reference_area`). Relative changes from the first snapshot; for the blood scene "
             "the largest over its red cells (and the cell that has it).", "",
             "| run | t [ms] | A_iso change | A change | A_ref change | A_ref / A_iso - 1 | "
             "A_iso / A - 1 |",
             "|---|---|---|---|---|---|---|"]
    for label, folder, origin in RUNS:
        if not pathlib.Path(folder, "bodies.csv").exists():
            lines.append(f"| {label} | (run not on this machine: {origin}) | | | | |")
            continue
        data = measure(folder)
        bodies = sorted({d[2] for d in data})
        first = {b: next(d for d in data if d[2] == b) for b in bodies}
        cell = (pathlib.Path(folder) / "case.toml").read_text()
        m = re.search(r"cells = \[ *(\d+)", cell)
        ln = re.search(r"length = \[ *([0-9.]+)", cell)
        h = float(ln.group(1)) / int(m.group(1))
        for step in sorted({d[0] for d in data}):
            here_rows = [d for d in data if d[0] == step]
            if step != min(d[0] for d in data) and step != max(d[0] for d in data) \
                    and len(bodies) > 1:
                continue
            def worst(key):
                return max(here_rows, key=key)
            ch = lambda d: d[3] / first[d[2]][3] - 1
            ca = lambda d: d[4] / first[d[2]][4] - 1
            cr = lambda d: d[5] / first[d[2]][5] - 1
            cons = lambda d: d[5] / (d[3] * h * h) - 1
            iso = lambda d: d[3] * h * h / d[4] - 1
            w = worst(ch)
            tag = f" ({w[2]})" if len(bodies) > 1 else ""
            lines.append(f"| {label} | {here_rows[0][1]:.3g} | {ch(w):+.4f}{tag} | "
                         f"{max(map(ca, here_rows)):+.4f} | {max(map(cr, here_rows)):+.4f} | "
                         f"{max(map(cons, here_rows), key=abs):+.4f} | "
                         f"{max(map(iso, here_rows), key=abs):+.4f} |")
    (here / "result.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
