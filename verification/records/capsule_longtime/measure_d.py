#!/usr/bin/python3
"""Three measures of a capsule's Taylor deformation D on field snapshots (docs/method.md,
"Measuring D"):

    /usr/bin/python3 verification/records/capsule_longtime/measure_d.py [RUNS_DIR] > measure_d.json
    /usr/bin/python3 verification/records/capsule_longtime/measure_d.py --table  (docs/method.md's table)
    /usr/bin/python3 verification/records/capsule_longtime/measure_d.py --early  (D(t) of the
        d/32 records at early times against both published curves, docs/method.md)

- moments: the second moments of phi in the shear plane (bodies.csv `taylor_deformation`,
  what the studies' steady_D are the means of);
- sharp: the same moments of the body bounded by phi = 1/2, phi replaced by the one-cell
  ramp chi = clamp(1/2 + (phi - 1/2) / (h |grad phi|), 0, 1) (bodies.csv
  `taylor_deformation_sharp` since it existed), with the volume that body has;
- section: the largest and smallest distance from the centroid of the phi = 1/2 contour in
  the plane z = 0 (the mean of the two middle cell planes), (L - B) / (L + B).
RUNS_DIR (default build/verification/capsule_longtime/runs) holds the study's runs; each
listed run's last field snapshot is read (the cases' box: 8 x 8 x 8, origin -4).
"""
import csv
import json
import sys
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RUNS = ["ca0.0125_n128_t10", "ca0.025_n128_t10", "ca0.05_n64_t20", "ca0.05_n128_t10",
        "ca0.1_n64_t20", "ca0.1_n128_t10", "ca0.2_n64_t20", "ca0.2_n128_t10"]


def deformation(w, X, Y):
    v = w.sum()
    cx, cy = (w * X).sum() / v, (w * Y).sum() / v
    xx = (w * (X - cx) ** 2).sum() / v
    yy = (w * (Y - cy) ** 2).sum() / v
    xy = (w * (X - cx) * (Y - cy)).sum() / v
    mean, dev = 0.5 * (xx + yy), np.sqrt(0.25 * (xx - yy) ** 2 + xy ** 2)
    L, B = np.sqrt(mean + dev), np.sqrt(mean - dev)
    return (L - B) / (L + B), v, cx, cy


def measure(snapshot: Path, n: int) -> dict:
    h = 8.0 / n
    phi = h5py.File(snapshot)["phi_capsule"][:].reshape(n, n, n)  # (z, y, x)
    x = -4 + (np.arange(n) + 0.5) * h
    Z, Y, X = np.meshgrid(x, x, x, indexing="ij")
    d_mom, v, cx, cy = deformation(phi, X, Y)
    gz, gy, gx = np.gradient(phi, h)
    gn = np.sqrt(gx ** 2 + gy ** 2 + gz ** 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        chi = np.where(gn * h > 1e-12, np.clip(0.5 + (phi - 0.5) / (gn * h), 0, 1),
                       (phi > 0.5) * 1.0)
    d_sharp, v_sharp, _, _ = deformation(chi, X, Y)
    section = 0.5 * (phi[n // 2 - 1] + phi[n // 2])
    contour = plt.contour(x, x, section, levels=[0.5])
    p = max(contour.allsegs[0], key=len)
    r = np.hypot(p[:, 0] - cx, p[:, 1] - cy)
    plt.close("all")
    return {"D_moments": float(d_mom), "D_sharp": float(d_sharp),
            "D_section": float((r.max() - r.min()) / (r.max() + r.min())),
            "volume_phi": float(v * h ** 3), "volume_sharp": float(v_sharp * h ** 3)}


def table():
    """The markdown table of docs/method.md from measure_d.json (beside this script)."""
    d = json.loads((Path(__file__).parent / "measure_d.json").read_text())
    ref = {0.0125: 25 / 4 * 0.0125, 0.025: 25 / 4 * 0.025, 0.05: 0.26, 0.1: 0.38, 0.2: 0.50}
    print("| run (t) | D, moments of phi | D, phi = 1/2 body | D, section | published | "
          "volume of phi / of the phi = 1/2 body / sphere |")
    print("|---|---|---|---|---|---|")
    for name, m in d["runs"].items():
        ca = float(name.split("_")[0][2:])
        print(f"| {name} ({m['time']:g}) | {m['D_moments']:.4f} | {m['D_sharp']:.4f} | "
              f"{m['D_section']:.4f} | {ref[ca]:.3f} | {m['volume_phi']:.3f} / "
              f"{m['volume_sharp']:.3f} / {d['sphere_volume']:.3f} |")


def early():
    """D(t) of the d/32 records (moments of phi, bodies.csv) at t = 0.5 / 1 / 1.5 against
    Pozrikidis 1995 and Ramanujan & Pozrikidis 1998 (verification/data/capsule_shear)."""
    here = Path(__file__).resolve().parent
    data = here.parents[1] / "data" / "capsule_shear"
    print("| Ca | t | efsi d/32 | Pozrikidis 1995 | RP98 |")
    print("|---|---|---|---|---|")
    for ca in (0.05, 0.1, 0.2):
        rows = list(csv.DictReader(open(here / f"ca{ca:g}_n128_t10_foot" / "bodies.csv")))
        t = np.array([float(r["time"]) for r in rows])
        D = np.array([float(r["taylor_deformation"]) for r in rows])
        curves = []
        for name in ("pozrikidis1995", "ramanujan_pozrikidis1998"):
            c = np.loadtxt(data / f"{name}_ca{ca:g}.csv", delimiter=",")
            curves.append(c[np.argsort(c[:, 0])])
        for tt in (0.5, 1.0, 1.5):
            ref = ["%.4f" % np.interp(tt, c[:, 0], c[:, 1]) if c[0, 0] <= tt <= c[-1, 0] else "-"
                   for c in curves]
            print(f"| {ca:g} | {tt:g} | {np.interp(tt, t, D):.4f} | {ref[0]} | {ref[1]} |")


def main():
    if sys.argv[1:] == ["--table"]:
        table()
        return
    if sys.argv[1:] == ["--early"]:
        early()
        return
    runs = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("build/verification/capsule_longtime/runs")
    out = {"sphere_volume": 4 * np.pi / 3, "runs": {}}
    for name in RUNS:
        snaps = sorted((runs / name / "fields").glob("fields_0*.h5"))
        if not snaps:
            continue
        n = 4 * int(name.split("_n")[1].split("_")[0]) // 4
        m = measure(snaps[-1], n)
        m["snapshot"] = snaps[-1].name
        m["time"] = float(json.loads((runs / name / "summary.json").read_text())["time"])
        out["runs"][name] = m
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
