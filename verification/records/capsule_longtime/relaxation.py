#!/usr/bin/python3
"""Relaxation of a sheared capsule (docs/method.md, "The membrane's stiffness, measured by
relaxation"): the effective stiffness of the discrete membrane, without tank-treading.

    /usr/bin/python3 verification/records/capsule_longtime/relaxation.py OUT N[:BOX[:W]] ... > relaxation.json
    /usr/bin/python3 verification/records/capsule_longtime/relaxation.py --table  (docs/method.md)

N cells per diameter (then, comma-separated, extra case keys for both runs, key=value as
for --set: "16,body[0].strain_model=\"tensor\"" or "16,time.cfl=0.25"; "ca=0.025" sets the
capillary number instead of 0.0125, and a Skalak law with "body[0].law=\"skalak\"" and
"body[0].area_dilation=C" takes the small-deformation D = 5/4 (2 + 3C)/(1 + 2C) x 1.5 Ca
of capsule_shear.py in place of 25/4 Ca); BOX the box in radii (8, the cases' box, unless given: 16 doubles it,
with its walls at +-8 moving at +-8 while sheared); W the smoothing width in cells (the
case's 0.75 unless given).

For each N (cells per diameter): cases/capsule_shear at Ca 0.0125 (small deformation), Re
1e-4 (fluid.density = 1e-4, so the flow follows the walls within ~1e-3), sheared to t = 0.6
(D near its steady 25/4 Ca); then the walls stop and the capsule relaxes for 0.6 more. The
solver refuses a restart whose case differs from the checkpoint's (the walls' velocity is in
its fingerprint), so this script rewrites the checkpoint copy's fingerprint (and the checksum
over it, FNV-1a as solver/io/checkpoint.cpp) to the stopped walls: a diagnostic, not a
feature. The fit: D(t) of the phi = 1/2 body (bodies.csv taylor_deformation_sharp) over the
window 0.6 D0 >= D >= 0.15 D0, log-linear, gives the relaxation time tau.

Small-deformation theory for a neo-Hookean capsule with equal viscosities: a sphere starts
deforming at dD/dt = E (E = shear rate / 2; the runs show 0.49-0.50 at t -> 0) and settles at
D = 25/4 Ca (Barthes-Biesel & Rallison 1981), so a single-mode relaxation has
tau = 2 x 25/4 Ca / shear rate = 12.5 Ca (= 0.156 here). tau / 12.5 Ca > 1 means the discrete
membrane is that much softer than the continuous one (the walls at 4 a also slow the
relaxation by a few per cent: not removed here). Output: JSON on stdout.
"""
import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

REPO = Path(__file__).resolve().parents[3]
EFSI = REPO / "build" / "bin" / "efsi"
CA, T_SHEAR, T_RELAX = 0.0125, 0.6, 0.6


def run(out: Path, n: int, t_end: float, restart: Path = None, stopped=False, box=8, width=None,
        extra=(), ca=CA):
    cells = n * box // 2
    cmd = [str(EFSI), "run", str(REPO / "cases" / "capsule_shear"), "-o", str(out),
           "--set", f"grid.cells=[{cells},{cells},{cells}]",
           "--set", f"body[0].elastic_modulus={1 / ca!r}", "--set", "fluid.density=0.0001",
           "--set", f"time.end_time={t_end!r}", "--set", "output.checkpoint_every=100000",
           "--set", "output.fields_interval=1000.0", "--set", "output.diagnostics_every=1"]
    if width is not None:
        cmd += ["--set", f"body[0].smoothing_width={width!r}"]
    for kv in extra:
        cmd += ["--set", kv]
    if box != 8:
        half = box / 2
        cmd += ["--set", f"grid.length=[{box:.1f},{box:.1f},{box:.1f}]",
                "--set", f"grid.origin=[{-half:.1f},{-half:.1f},{-half:.1f}]",
                "--set", f"initial.amplitude={half!r}"]
        if not stopped:
            cmd += ["--set", f'boundary.y_low={{type="wall",velocity=[{-half!r},0.0,0.0]}}',
                    "--set", f'boundary.y_high={{type="wall",velocity=[{half!r},0.0,0.0]}}']
    if stopped:
        cmd += ["--set", 'boundary.y_low={type="wall",velocity=[0.0,0.0,0.0]}',
                "--set", 'boundary.y_high={type="wall",velocity=[0.0,0.0,0.0]}']
    if restart:
        cmd += ["--restart", str(restart)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def stop_walls(checkpoint: Path):
    """The checkpoint's fingerprint with the walls at rest, and its attribute checksum."""
    with h5py.File(checkpoint, "r+") as f:
        g = f["integrity"]

        def put(name, text):
            b = text.encode()
            old = h5py.h5a.open(g.id, name.encode()).get_type()
            del g.attrs[name]
            t = h5py.h5t.C_S1.copy()
            t.set_size(len(b))
            t.set_strpad(old.get_strpad())
            t.set_cset(old.get_cset())
            a = h5py.h5a.create(g.id, name.encode(), t, h5py.h5s.create(h5py.h5s.SCALAR))
            a.write(np.array(b, dtype=f"S{len(b)}"), mtype=t)

        fp = re.sub(r"wall velocity \[-?[0-9.]+, 0, 0\] frequency 0",
                    "wall velocity [0, 0, 0] frequency 0",
                    bytes(g.attrs["case_fingerprint"]).decode())
        keys = ["time", "step", "dt_prev", "dim", "next_fields_time", "format"]
        keys += [f"body_capsule_{s}{d}" for d in range(3) for s in ("lo", "hi")]
        h, mask = 0xCBF29CE484222325, (1 << 64) - 1
        for chunk in [x for k in keys for x in (k.encode(), np.float64(f.attrs[k]).tobytes())]:
            for c in chunk:
                h = ((h ^ c) * 0x100000001B3) & mask
        for c in fp.encode():
            h = ((h ^ c) * 0x100000001B3) & mask
        put("case_fingerprint", fp)
        put("attributes_checksum", f"{h:016x}")


def steady_small_deformation(ca: float, extra) -> float:
    if any(kv.replace(" ", "") == 'body[0].law="skalak"' for kv in extra):
        c = float(next(kv.split("=", 1)[1] for kv in extra if kv.startswith("body[0].area_dilation=")))
        return 1.25 * (2 + 3 * c) / (1 + 2 * c) * 1.5 * ca
    return 25.0 / 4.0 * ca


def fit(relax: Path, t0: float, ca: float = CA, extra=()) -> dict:
    rows = list(csv.DictReader(open(relax / "bodies.csv")))
    t = np.array([float(r["time"]) for r in rows])
    D = np.array([float(r["taylor_deformation_sharp"]) for r in rows])
    keep = t >= t0 - 1e-9
    t, D = t[keep] - t0, D[keep]
    w = (D <= 0.6 * D[0]) & (D >= 0.15 * D[0])
    slope = np.polyfit(t[w], np.log(D[w]), 1)[0]
    tau = -1.0 / slope
    theory = 2 * steady_small_deformation(ca, extra)
    return {"Ca": ca, "D0": float(D[0]), "tau": float(tau), "tau_theory": theory,
            "tau_over_theory": float(tau / theory), "fit_points": int(w.sum()),
            "fit_window": [float(t[w][0]), float(t[w][-1])]}


def table():
    """docs/method.md's table from relaxation.json (beside this script)."""
    d = json.loads((Path(__file__).parent / "relaxation.json").read_text())
    print("| run | box [a] | smoothing width [cells] | other keys | D0 | tau | theory | tau / theory |")
    print("|---|---|---|---|---|---|---|---|")
    for name, m in d["runs"].items():
        box = name.split("_box")[1].split("_")[0] if "_box" in name else "8"
        w = name.split("_w")[1].split("_")[0] if "_w" in name else "0.75"
        keys = ", ".join(p for p in name.split("_", 1)[-1:] if "=" in p) or "-"
        print(f"| {name} | {box} | {w} | {keys} | {m['D0']:.4f} | {m['tau']:.4f} | "
              f"{m.get('tau_theory', 12.5 * CA):.4f} | "
              f"{m['tau_over_theory']:.3f} |")


def main():
    if sys.argv[1:] == ["--table"]:
        table()
        return
    root, out = Path(sys.argv[1]), {}
    for spec in sys.argv[2:]:
        spec, *extra = spec.split(",")
        ca = float(next((kv[3:] for kv in extra if kv.startswith("ca=")), CA))
        extra = [kv for kv in extra if not kv.startswith("ca=")]
        parts = spec.split(":")
        n, box = int(parts[0]), int(parts[1]) if len(parts) > 1 else 8
        width = float(parts[2]) if len(parts) > 2 else None
        name = f"d{n}" + (f"_box{box}" if box != 8 else "") + (f"_w{width:g}" if width else "")
        name += (f"_ca{ca:g}" if ca != CA else "") + "".join(
            "_" + kv.split("=")[0].split(".")[-1] + "=" + kv.split("=", 1)[1].replace('"', "")
            for kv in extra)
        d = root / name
        run(d / "shear", n, T_SHEAR, box=box, width=width, extra=extra, ca=ca)
        ck = d / "checkpoint_stopped.h5"
        ck.write_bytes((d / "shear" / "checkpoint.h5").read_bytes())
        stop_walls(ck)
        run(d / "relax", n, T_SHEAR + T_RELAX, restart=ck, stopped=True, box=box, width=width,
            extra=extra, ca=ca)
        out[name] = fit(d / "relax", T_SHEAR, ca, extra)
    json.dump({"Ca": CA, "shear_until": T_SHEAR, "runs": out}, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
