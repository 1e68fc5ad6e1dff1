"""capillary_coarse's step before and after session 48 (band transport, the pinned-wall
predictor sweep, the bending force's psi, the diagnostics' empty rows): the efsi of the
session's start (f6eec7e) against the session's, 10 steps from one checkpoint at step 10
(diagnostics every 10 steps, the case's), alternated twice, on 1 rank and on 2 (split along z);
the time of each stage per step (the faster leg of each) and the largest relative difference
of the two binaries' checkpoints. Writes result.md beside this script.

    /usr/bin/python3 verification/records/blood_capillary/step_s48/measure.py \
        OLD_EFSI NEW_EFSI START_CHECKPOINT WORKDIR      (from the repository root)

OLD_EFSI: built from f6eec7e (git worktree add /tmp/wt_old f6eec7e; cmake -S /tmp/wt_old -B
/tmp/wt_old/build -DCMAKE_BUILD_TYPE=Release; cmake --build /tmp/wt_old/build --target efsi).
START_CHECKPOINT: a checkpoint of cases/capillary_coarse at step 10 with output.fields=false
(band_transport_s48/measure.py makes one, WORKDIR/start).
"""
import os
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from capillary_ab import largest_difference, run_capillary  # noqa: E402

old, new, start, work = sys.argv[1], sys.argv[2], sys.argv[3], pathlib.Path(sys.argv[4])
work.mkdir(parents=True, exist_ok=True)
SETS = ["output.fields=false", "output.diagnostics_every=10", "time.max_steps=20"]


def run(exe, out, ranks):
    return run_capillary(exe, out, SETS + (["parallel.ranks=[1,1,2]"] if ranks == 2 else []),
                         restart=start, ranks=ranks)


load_before = os.getloadavg()[0]
tables = []
for ranks in (1, 2):
    legs = {"start (f6eec7e)": [], "session 48": []}
    for rep in range(2):
        for label, exe in (("start (f6eec7e)", old), ("session 48", new)):
            out = work / f"np{ranks}_{'old' if exe == old else 'new'}_{rep}"
            s = run(exe, out, ranks)
            per = {k: v / s["steps"] for k, v in s["stages"].items()}
            per["step without checkpoint"] = (s["wall_seconds"]
                                              - s["stages"].get("checkpoint", 0)) / s["steps"]
            legs[label].append((per, out))
    best = {label: min(rows, key=lambda r: r[0]["step without checkpoint"])
            for label, rows in legs.items()}
    diff = largest_difference(best["start (f6eec7e)"][1] / "checkpoint.h5",
                              best["session 48"][1] / "checkpoint.h5")
    tables.append((ranks, best, diff))
here = pathlib.Path(__file__).parent
with open(here / "result.md", "w") as f:
    f.write("# capillary_coarse's step before and after session 48\n\nMade by `measure.py` "
            "(this folder): 10 steps from the step-10 checkpoint (C = 10, diagnostics every 10 "
            "steps), the two binaries alternated twice, the faster leg of each kept. 1-minute "
            f"load before / after the runs: {load_before:.2f} / {os.getloadavg()[0]:.2f}.\n")
    for ranks, best, diff in tables:
        a, b = best["start (f6eec7e)"][0], best["session 48"][0]
        f.write(f"\n## {ranks} rank{'s' if ranks > 1 else ''}\n\n| stage [s/step] | start "
                "(f6eec7e) | session 48 |\n|---|---|---|\n")
        keys = sorted(k for k in a if k != "step without checkpoint" and k != "checkpoint")
        for k in keys + ["step without checkpoint"]:
            f.write(f"| {k} | {a[k]:.4f} | {b.get(k, 0):.4f} |\n")
        f.write(f"\nLargest relative difference of the two checkpoints' datasets: "
                f"{diff[0]:.1e} ({diff[1]}).\n")
print(open(here / "result.md").read())
