"""Patches across the periodic x seam in the blood scene (session 55).

Since session 55 a moving body's patch may cross the periodic x seam as one box whose x
indices run past [0, n) (bodies/patch.hpp, docs/method.md "The periodic seam"). This reads
a checkpoint (the patch boxes are its attributes body_<name>_lo<d> / _hi<d>), counts the
moving bodies' patch cells, and the cells the same patches would hold over the whole of x
(what a patch across the seam was until then). Writes result.md beside this file (or prints
it with --print).

    mpirun -np 2 build/bin/efsi run cases/capillary_coarse -o /tmp/capseam \\
        --set time.max_steps=5 --set output.fields=false --set output.checkpoint_every=5
    /usr/bin/python3 verification/records/blood_capillary/seam_cross_s55/measure.py \\
        /tmp/capseam/checkpoint.h5
"""
import sys
from pathlib import Path

import h5py

HERE = Path(__file__).resolve().parent
HELD = {"wall"}  # cases/capillary_coarse: the vessel wall is held in place (never crosses)


def measure(path: str) -> dict:
    with h5py.File(path, "r") as f:
        a = f.attrs
        n = int(f["pressure"].shape[2])
        step, time = int(a["step"]), float(a["time"])
        names = sorted({k[len("body_"):-len("_lo0")] for k in a
                        if k.startswith("body_") and k.endswith("_lo0") and "fitted" not in k})
        moving = [b for b in names if b not in HELD]
        cells = whole = crossing = 0
        for b in moving:
            lo = [int(a[f"body_{b}_lo{d}"]) for d in range(3)]
            hi = [int(a[f"body_{b}_hi{d}"]) for d in range(3)]
            yz = (hi[1] - lo[1]) * (hi[2] - lo[2])
            cells += (hi[0] - lo[0]) * yz
            if lo[0] < 0 or hi[0] > n:
                crossing += 1
                whole += n * yz
            else:
                whole += (hi[0] - lo[0]) * yz
    return {"checkpoint": path, "step": step, "time": time, "moving": len(moving),
            "crossing": crossing, "cells": cells, "whole": whole}


def main(argv: list[str]) -> int:
    paths = [p for p in argv if not p.startswith("--")]
    if not paths:
        print(__doc__)
        return 2
    rows = ["| checkpoint | step | t | moving bodies | patches across the seam | patch cells "
            "(moving bodies) | the same over the whole of x | fewer cells |",
            "|---|---|---|---|---|---|---|---|"]
    for p in paths:
        m = measure(p)
        rows.append(f"| `{m['checkpoint']}` | {m['step']} | {m['time']:g} | {m['moving']} | "
                    f"{m['crossing']} | {m['cells']} | {m['whole']} | "
                    f"{1 - m['cells'] / m['whole']:.3f} |")
    text = "\n".join(["# Patches across the periodic x seam in capillary_coarse", "",
                      "Made by `measure.py` (this folder; its docstring has the run). 'The same "
                      "over the whole of x': each patch that crosses the seam counted with all "
                      "n x cells, as before session 55.", "", *rows, ""])
    if "--print" in argv:
        print(text)
    else:
        (HERE / "result.md").write_text(text)
        print(f"wrote {HERE / 'result.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
