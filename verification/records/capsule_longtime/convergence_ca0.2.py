#!/usr/bin/python3
"""D(t) of the Ca 0.2 capsule at d/16, 24, 32 and 48 against the other references
(docs/method.md, "The offset is grid-converged").

    /usr/bin/python3 verification/records/capsule_longtime/convergence_ca0.2.py

Reads the records ca0.2_n<cells>_t6_s35 beside this script (cases/capsule_shear with
`--set 'body[0].elastic_modulus=5.0' --set time.end_time=6.0`, the grid's cells set; d/24 and
finer on 2 ranks) and the digitised curves in verification/data/capsule_shear. Prints a
markdown table: D of the moments of phi / of the phi = 1/2 body at each grid, then Huet's
front tracking in the same 8a box, Doddi & Bagchi 2008 and RP98, interpolated linearly in t.
"""
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE.parents[1] / "data" / "capsule_shear"
GRIDS = [64, 96, 128, 192]  # cells per direction: d/16, d/24, d/32, d/48
TIMES = [0.5, 1, 1.5, 2, 2.5, 3, 4, 5, 6]
REFS = [("Huet, 8a box", "huet_front_tracking_ca0.2.csv"),
        ("Doddi & Bagchi 2008", "doddi_bagchi2008_ca0.2.csv"),
        ("RP98", "ramanujan_pozrikidis1998_ca0.2.csv")]


def curve(path: Path):
    pts = sorted(tuple(map(float, line.split(","))) for line in path.read_text().split())
    return np.array(pts)


def main():
    runs = {}
    for n in GRIDS:
        a = np.genfromtxt(HERE / f"ca0.2_n{n}_t6_s35" / "bodies.csv", delimiter=",",
                          names=True, dtype=None, encoding=None)
        runs[n] = a
    refs = [(name, curve(DATA / f)) for name, f in REFS]
    head = ["t"] + [f"d/{n // 4}" for n in GRIDS] + [name for name, _ in refs]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for t in TIMES:
        row = [f"{t:g}"]
        for n in GRIDS:
            a = runs[n]
            if a["time"][-1] < t - 1e-9:
                row.append("-")
                continue
            m = np.interp(t, a["time"], a["taylor_deformation"])
            s = np.interp(t, a["time"], a["taylor_deformation_sharp"])
            row.append(f"{m:.4f} / {s:.4f}")
        for _, c in refs:
            row.append(f"{np.interp(t, c[:, 0], c[:, 1]):.4f}" if c[0, 0] <= t <= c[-1, 0] else "-")
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
