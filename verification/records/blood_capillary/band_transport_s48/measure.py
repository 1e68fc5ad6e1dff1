"""Gs transported on the band only (body.band_transport, default on) against the whole patch
(off), in cases/capillary_coarse: 10 steps from a checkpoint at step 10, the two settings
alternated twice, on 1 rank and on 2 (split along z); the largest relative difference of every
dataset of the two checkpoints and the stage times. Writes result.md beside this script.

    /usr/bin/python3 verification/records/blood_capillary/band_transport_s48/measure.py \
        build/bin/efsi WORKDIR        (from the repository root)
"""
import os
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from capillary_ab import largest_difference, run_capillary  # noqa: E402

exe, work = sys.argv[1], pathlib.Path(sys.argv[2])
work.mkdir(parents=True, exist_ok=True)
COMMON = ["output.fields=false", "output.diagnostics_every=5"]


def run(out, ranks, sets, restart=None):
    return run_capillary(exe, out, COMMON + sets, restart=restart, ranks=ranks)


start = work / "start"
run(start, 1, ["time.max_steps=10"])
rows = []
for ranks, layout in ((1, None), (2, "[1,1,2]")):
    legs = {}
    for rep in range(2):
        for band in ("true", "false"):
            out = work / f"np{ranks}_{band}_{rep}"
            sets = ["time.max_steps=20", f"seeding.kind[1].body.band_transport={band}"]
            if layout:
                sets.append(f"parallel.ranks={layout}")
            s = run(out, ranks, sets, restart=start / "checkpoint.h5")
            st = s["stages"]
            stepping = s["wall_seconds"] - st.get("checkpoint", 0) - st.get("output", 0)
            legs.setdefault(band, []).append((st["bodies_tensor"] / s["steps"],
                                              stepping / s["steps"], out))
    diff = largest_difference(legs["true"][0][2] / "checkpoint.h5",
                              legs["false"][0][2] / "checkpoint.h5")
    for band in ("true", "false"):
        rows.append((ranks, band, min(x[0] for x in legs[band]), min(x[1] for x in legs[band]),
                     diff))
load = os.getloadavg()
here = pathlib.Path(__file__).parent
with open(here / "result.md", "w") as f:
    f.write("# Gs transported on the band only (session 48)\n\nMade by `measure.py` (this "
            "folder): cases/capillary_coarse (C = 10), 10 steps from its step-10 checkpoint, "
            "band_transport on and off alternated twice, the faster leg of each kept. "
            f"1-minute load after the runs: {load[0]:.2f}.\n\n")
    f.write("| ranks | band_transport | bodies_tensor [s/step] | step without checkpoint "
            "[s/step] | largest relative difference, on vs off (dataset) |\n|---|---|---|---|---|\n")
    for r, band, t, w, d in rows:
        f.write(f"| {r} | {band} | {t:.3f} | {w:.3f} | {d[0]:.1e} ({d[1]}) |\n")
print(open(here / "result.md").read())
