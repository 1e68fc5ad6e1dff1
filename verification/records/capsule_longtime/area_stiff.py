#!/usr/bin/python3
"""The area-stiff (Skalak C = 100) capsule: what sets its D (docs/method.md, "The area-stiff
membrane").

    /usr/bin/python3 verification/records/capsule_longtime/area_stiff.py RUN_DIR[:LABEL][@T] ... > area_stiff.json
    /usr/bin/python3 verification/records/capsule_longtime/area_stiff.py --table   (docs/method.md)

Each RUN_DIR is a cases/capsule_shear run (made by verification/studies/capsule_longtime.py's
run_sets with extra keys) with its resolved case.toml and bodies.csv (@T: its rows up to
t = T only). Per run, at its last row and at its largest D: D of the phi = 1/2 body (bodies.csv taylor_deformation_sharp), the
relative change of the area (integral of |grad phi|) and of the reference area (integral of
|grad phi| / J: constant in the continuum, its drift is strain the numerics gain or lose),
the number of steps and the time step. Beside them the small-deformation (first order in
Ca) steady D of Barthes-Biesel & Rallison for the Skalak law, D_lin = 1.25 (2 + 3C)/(1 + 2C)
x 1.5 Ca, and the ratio of the isotropic tension the deformation's own area increase needs
to the shear tension, chi = (1 + 2C) x (A/A0 - 1) / D: a sphere of fixed volume must gain
area to deform (to second order, A/A0 - 1 ~ 0.6 D^2 here), so at large C the area modulus
resists deformation at an order the first-order theory drops, and D_lin holds only where
chi << 1 (C = 100 at Ca 0.025: chi ~ 6).

area_stiff.json's "source" names each run. The d/16 ones are records beside this script.
The d/8 ones (not recorded) are capsule_longtime.run_sets(8, 0.025, 0.3, law, C, 0) with
time.dt (0.5x: 4.666e-5, 2x: 1.866e-4, 4x: 3.732e-4; neo-Hookean 3.125e-3 and down) or the
key in their name added; d8_C100_t1 runs to t = 1.
"""
import csv
import json
import math
import sys
import tomllib
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "studies"))
from capsule_shear import skalak_linear_theory  # noqa: E402


def linear_d(ca: float, law: str, c: float) -> float:
    if law == "skalak":
        return skalak_linear_theory(ca, c)
    return 25.0 / 4.0 * ca


def measure(run: Path, until: float = None) -> dict:
    case = tomllib.loads((run / "case.toml").read_text())
    body = case["body"][0]
    es, c = float(body["elastic_modulus"]), float(body.get("area_dilation", 0.0))
    ca = 1.0 / es  # mu = 1, shear rate 1, a = 1
    cells = int(case["grid"]["cells"][0])
    rows = list(csv.DictReader(open(run / "bodies.csv")))
    if until is not None:
        rows = [r for r in rows if float(r["time"]) <= until + 1e-9]
    t = [float(r["time"]) for r in rows]
    Dm = [float(r["taylor_deformation"]) for r in rows]
    # (a run restarted by a newer version holds nan in the rows before the restart)
    sharp = "taylor_deformation_sharp" in rows[0] and all(
        math.isfinite(float(r["taylor_deformation_sharp"])) for r in rows)
    # Runs from before the column existed: the moments of phi (read D low by up to 0.015
    # at d/16 after long runs; docs/method.md "Measuring D").
    D = [float(r["taylor_deformation_sharp"]) for r in rows] if sharp else Dm
    A = [float(r["area"]) for r in rows]
    R = [float(r["reference_area"]) for r in rows]
    diag = [r for r in csv.DictReader(open(run / "diagnostics.csv"))
            if until is None or float(r["time"]) <= until + 1e-9]
    ipk = max(range(len(D)), key=lambda i: D[i])
    last = len(D) - 1
    law = body.get("law", "neo_hookean")
    dl = linear_d(ca, law, c)
    dts = sorted(float(r["dt"]) for r in diag)

    def at(i):
        return {"t": t[i], "D": D[i], "D_moments": Dm[i], "D_over_linear": D[i] / dl,
                "area_change": A[i] / A[0] - 1, "reference_area_change": R[i] / R[0] - 1,
                "chi": (1 + 2 * c) * (A[i] / A[0] - 1) / D[i] if law == "skalak" and D[i] > 0
                else None}

    return {"Ca": ca, "C": c, "cells_per_diameter": cells // 4, "law": law,
            "D_measure": "phi = 1/2 body" if sharp else "moments of phi",
            "dt": dts[len(dts) // 2], "steps": int(float(diag[-1]["step"])),
            "D_linear": dl, "peak": at(ipk), "end": at(last)}


def table():
    d = json.loads((HERE / "area_stiff.json").read_text())
    print("| run | d/n | Ca | law, C | dt | steps | t | D | D, moments of phi | D / D_lin | area | reference area | chi "
          "| peak D (t) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, m in d.items():
        e, p = m["end"], m["peak"]
        law = f"Skalak {m['C']:g}" if m["law"] == "skalak" else "neo-Hookean"
        print(f"| {name} | {m['cells_per_diameter']} | {m['Ca']:g} | {law} | "
              f"{m['dt']:.3g} | {m['steps']} | {e['t']:.3g} | "
              + (f"{e['D']:.4f}" if m["D_measure"] != "moments of phi" else "-")
              + f" | {e['D_moments']:.4f} | "
              f"{e['D_over_linear']:.3f} | {100 * e['area_change']:+.3f} % | "
              f"{100 * e['reference_area_change']:+.3f} % | "
              + (f"{e['chi']:.2f}" if e["chi"] is not None else "-")
              + f" | {p['D']:.4f} ({p['t']:.2f}) |")


def main():
    if sys.argv[1:] == ["--table"]:
        table()
        return
    out = {}
    for spec in sys.argv[1:]:
        spec, _, until = spec.partition("@")
        path, _, label = spec.partition(":")
        m = measure(Path(path), float(until) if until else None)
        out[label or Path(path).name] = {"source": spec + (f"@{until}" if until else ""), **m}
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
