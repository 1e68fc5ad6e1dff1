#!/usr/bin/python3
"""efsi's capsule in shear against the repository's own boundary-integral capsules, 2D and 3D
(docs/method.md, "The offset is the references'").

    /usr/bin/python3 verification/records/capsule_longtime/bi_compare.py

Prints three markdown tables:
1. 2D, Ca 0.2: D(t) of the records 2d_ca0.2_d<n>_box<L>_t6_s36 (cases/capsule_shear_2d in a
   box of L a, walls moving at +-L/2, d/n; D of the phi = 1/2 body) against
   reference/capsule_bi_2d.py (unbounded, Re = 0) at N = 128 and 256 markers, run here
   (seconds);
2. 3D, Ca 0.2: D(t) of the records ca0.2_n<cells>_t6_s35 (8a box; the phi = 1/2 body) and,
   when recorded, ca0.2_n128_box16_t6_s36 (16a box), against reference/capsule_bi_3d.py
   (unbounded, Re = 0) at the levels recorded in bi3d_s36/, and the published curves;
3. 3D steady D per Ca (the mean over the last quarter of each run or curve, as the study's
   steady_D): efsi's records of the study (d/16 to t = 20, d/32 to t = 10; D of the
   moments of phi and, where those records have it, of the phi = 1/2 body), the boundary-integral runs, RP98 (the bound's value; 25/4 Ca at Ca <= 0.025),
   Doddi & Bagchi 2008 and Huet's front tracking;
4. 3D largest area change over each run: efsi's records of the study against the boundary-
   integral runs that wrote the membrane's area (issue 19 bounds it by 5 % at Ca <= 0.05).
"""
import csv
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[2]
sys.path.insert(0, str(REPO / "reference"))
sys.path.insert(0, str(REPO / "verification" / "studies"))
import capsule_bi_2d  # noqa: E402
from capsule_longtime import curve_plateau, other_plateaus, steady_reference  # noqa: E402

DATA = REPO / "verification" / "data" / "capsule_shear"
BI3 = HERE / "bi3d_s36"
PUBLISHED = [("Huet, 8a box", "huet_front_tracking"), ("Doddi & Bagchi 2008", "doddi_bagchi2008"),
             ("RP98", "ramanujan_pozrikidis1998")]


def efsi_curve(run: Path, column="taylor_deformation_sharp"):
    with open(run / "bodies.csv") as f:
        rows = list(csv.DictReader(f))
    if column not in rows[0]:
        return None
    return np.array([(float(r["time"]), float(r[column])) for r in rows])


def read_xy(path: Path):
    pts = sorted(tuple(map(float, line.split(",")[:2])) for line in path.read_text().split()
                 if line[0].isdigit() or line[0] == "-")
    return np.array(pts)


def at(curve, t):
    if curve is None or t > curve[-1, 0] + 1e-9:
        return "-"
    return f"{np.interp(t, curve[:, 0], curve[:, 1]):.4f}"


def bi3_curve(ca, level):
    p = BI3 / f"bi3d_ca{ca:g}_L{level}.csv"
    if not p.exists():
        return None
    a = np.genfromtxt(p, delimiter=",", names=True)
    return np.c_[a["t"], a["D"]]


def table(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print()


def main():
    times = [0.5, 1, 1.5, 2, 3, 4, 5, 6]
    # 1. 2D
    cols = {}
    for p in sorted(HERE.glob("2d_ca0.2_d*_box*_t6_s36"), key=lambda p: (len(p.name), p.name)):
        d, box = p.name.split("_")[2:4]
        cols[f"efsi {d.replace('d', 'd/')}, {box.replace('box', '')}a box"] = efsi_curve(p)
    for n in (128, 256):
        rows, _, _ = capsule_bi_2d.run(0.2, n, 6.0)
        cols[f"BI 2D, N = {n}"] = rows[:, [0, 2]]
    print("2D capsule, Ca 0.2, D(t):\n")
    table(["t", *cols], [[f"{t:g}", *(at(c, t) for c in cols.values())] for t in times])
    # 2. 3D Ca 0.2
    cols = {}
    for n in (64, 128, 192):
        cols[f"efsi d/{n // 4}, 8a box"] = efsi_curve(HERE / f"ca0.2_n{n}_t6_s35")
    box16 = HERE / "ca0.2_n128_box16_t6_s36"
    if box16.exists():
        cols["efsi d/16, 16a box"] = efsi_curve(box16)
    for level in (2, 3, 4):
        c = bi3_curve(0.2, level)
        if c is not None:
            cols[f"BI 3D, level {level}"] = c
    for label, stem in PUBLISHED:
        cols[label] = read_xy(DATA / f"{stem}_ca0.2.csv")
    print("3D capsule, Ca 0.2, D(t) (efsi: the phi = 1/2 body):\n")
    table(["t", *cols], [[f"{t:g}", *(at(c, t) for c in cols.values())] for t in times])
    # 3. steady D
    header = ["Ca", "efsi d/16 (t = 20), moments / body", "efsi d/32 (t = 10), moments / body"]
    levels = [lv for lv in (3, 4) if any(bi3_curve(ca, lv) is not None
                                          for ca in (0.0125, 0.025, 0.05, 0.1, 0.2))]
    header += [f"BI 3D level {lv} (t = 10)" for lv in levels]
    header += ["BI finest level: volume change at t = 10"]
    header += ["RP98 (bound)", "Doddi & Bagchi 2008", "Huet, 8a box"]
    rows = []
    for ca in (0.0125, 0.025, 0.05, 0.1, 0.2):
        row = [f"{ca:g}"]
        for n, t_end in ((64, 20), (128, 10)):
            run = HERE / f"ca{ca:g}_n{n}_t{t_end}_foot"
            vals = [efsi_curve(run, col) if run.exists() else None
                    for col in ("taylor_deformation", "taylor_deformation_sharp")]
            row.append(" / ".join("-" if c is None else f"{curve_plateau(c):.4f}" for c in vals))
        for lv in levels:
            c = bi3_curve(ca, lv)
            row.append("-" if c is None or c[-1, 0] < 9.99 else f"{curve_plateau(c):.4f}")
        finest = [lv for lv in levels if bi3_curve(ca, lv) is not None]
        if finest:
            v = np.genfromtxt(BI3 / f"bi3d_ca{ca:g}_L{finest[-1]}.csv", delimiter=",",
                              names=True)["volume"]
            row.append(f"{v[-1] / v[0] - 1:+.1e} (level {finest[-1]})")
        else:
            row.append("-")
        others = other_plateaus(ca)
        row += [f"{steady_reference(ca, 'neo_hookean', None):.4f}",
                *(f"{others[k]:.4f}" if k in others else "-"
                  for k in ("doddi_bagchi2008", "huet_ft"))]
        rows.append(row)
    print("3D steady D (mean over the last quarter of each run or curve):\n")
    table(header, rows)
    # 4. area
    header = ["Ca", "efsi d/16 (t = 20)", "efsi d/32 (t = 10)", "BI 3D (level, t = 10)"]
    rows = []
    for ca in (0.0125, 0.025, 0.05, 0.1, 0.2):
        row = [f"{ca:g}"]
        for n, t_end in ((64, 20), (128, 10)):
            run = HERE / f"ca{ca:g}_n{n}_t{t_end}_foot"
            a = efsi_curve(run, "area") if run.exists() else None
            row.append("-" if a is None else f"{np.max(np.abs(a[:, 1] / a[0, 1] - 1)):.4f}")
        cell = "-"
        for lv in (4, 3, 2):
            p = BI3 / f"bi3d_ca{ca:g}_L{lv}.csv"
            if p.exists():
                a = np.genfromtxt(p, delimiter=",", names=True)
                if "area" in a.dtype.names and a["t"][-1] >= 9.99:
                    cell = f"{np.max(np.abs(a['area'] / a['area'][0] - 1)):.4f} ({lv})"
                    break
        row.append(cell)
        rows.append(row)
    print("3D largest relative area change |A/A0 - 1| over the run (efsi: the integral of "
          "|grad phi|; BI: the triangles'):\n")
    table(header, rows)


if __name__ == "__main__":
    main()
