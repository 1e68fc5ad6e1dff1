"""How evenly capillary_coarse's stages are shared by 2 ranks: summary.json's
stages_rank_min / stages_rank_max (session 48) after 10 steps from one checkpoint at step 10,
for the three ways of splitting the grid in two. Writes result.md beside this script.

    /usr/bin/python3 verification/records/blood_capillary/rank_spread_s48/measure.py \
        EFSI START_CHECKPOINT WORKDIR      (from the repository root)

START_CHECKPOINT: a checkpoint of cases/capillary_coarse at step 10 with output.fields=false
(band_transport_s48/measure.py makes one, WORKDIR/start).
"""
import os
import pathlib
import sys

import h5py

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from capillary_ab import run_capillary  # noqa: E402

exe, start, work = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3])
work.mkdir(parents=True, exist_ok=True)
STAGES = ["bodies_tensor", "bodies_vof", "bodies_extension", "body_stress", "viscous_solve",
          "predictor", "diagnostics"]
load = os.getloadavg()[0]
rows = []
for layout in ("[2,1,1]", "[1,2,1]", "[1,1,2]"):
    s = run_capillary(exe, work / layout.strip("[]").replace(",", ""),
                      ["output.fields=false", "output.diagnostics_every=10", "time.max_steps=20",
                       f"parallel.ranks={layout}"], restart=start, ranks=2)
    lo, hi, n = s["stages_rank_min"], s["stages_rank_max"], s["steps"]
    rows.append((layout, {k: (lo[k] / n, hi[k] / n) for k in STAGES},
                 (s["wall_seconds"] - s["stages"].get("checkpoint", 0)) / n))
here = pathlib.Path(__file__).parent
with open(here / "result.md", "w") as f:
    f.write("# capillary_coarse's stages on 2 ranks: least and largest rank (session 48)\n\n"
            "Made by `measure.py` (this folder): 10 steps from the step-10 checkpoint (C = 10), "
            "each stage's seconds per step on the rank that spent least and on the one that "
            f"spent most (summary.json stages_rank_min / _max). 1-minute load before: {load:.2f}."
            "\n\n| stage [s/step] | " + " | ".join(f"ranks {r[0]}" for r in rows) + " |\n|---|"
            + "---|" * len(rows) + "\n")
    for k in STAGES:
        f.write(f"| {k} | " + " | ".join(f"{r[1][k][0]:.3f} - {r[1][k][1]:.3f}" for r in rows)
                + " |\n")
    f.write("| step without checkpoint | " + " | ".join(f"{r[2]:.3f}" for r in rows) + " |\n")
    # The stages time the waits at the patches' halo exchanges too, so the ranks' times agree
    # whatever their shares; the shares themselves, from the start checkpoint's patch boxes:
    # each layout's two halves, and the cells of the moving bodies' patches in each.
    with h5py.File(start) as c:
        a = c.attrs
        n = [int(x) for x in c["velocity_u"].shape[::-1]]
        names = sorted({k[5:-4] for k in a if k.startswith("body_") and k.endswith("_lo0")
                        and not k.startswith("body_wall")})
        boxes = [[(int(a[f"body_{b}_lo{d}"]), int(a[f"body_{b}_hi{d}"])) for d in range(3)]
                 for b in names]
    f.write("\nThe moving bodies' patch cells in each half (the start checkpoint's boxes):\n\n"
            "| ranks | first half | second half | larger / mean |\n|---|---|---|---|\n")
    for layout, d in (("[2,1,1]", 0), ("[1,2,1]", 1), ("[1,1,2]", 2)):
        half = [0, 0]
        for box in boxes:
            cells = 1
            for e in range(3):
                if e != d:
                    cells *= box[e][1] - box[e][0]
            lo, hi = box[d]
            half[0] += cells * max(0, min(hi, n[d] // 2) - lo)
            half[1] += cells * max(0, hi - max(lo, n[d] // 2))
        f.write(f"| {layout} | {half[0]} | {half[1]} | {max(half) / (sum(half) / 2):.3f} |\n")
print(open(here / "result.md").read())
