"""Shared by the session-48 records of capillary_coarse's step (band_transport_s48,
pinned_predictor_s48, bending_psi_s48, step_s48): a run continued from one checkpoint, two
checkpoints compared dataset by dataset, and a table of one stage for two binaries."""
import json
import os
import pathlib
import subprocess

import h5py
import numpy as np

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def run_capillary(exe, out, sets, restart=None, ranks=1):
    """cases/capillary_coarse with `sets` (--set k=v), from `restart` if given; its summary."""
    cmd = ([] if ranks == 1 else ["mpirun", "-np", str(ranks)])
    cmd += [exe, "run", "cases/capillary_coarse", "-o", str(out), "-q"]
    if restart:
        cmd += ["--restart", str(restart)]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, env=ENV, capture_output=True)
    return json.load(open(pathlib.Path(out) / "summary.json"))


def largest_difference(a, b):
    """(max |x - y| / max |x|, dataset) over the real datasets of two HDF5 files."""
    worst = (0.0, "")
    with h5py.File(a) as fa, h5py.File(b) as fb:
        for k in fa.keys():
            if isinstance(fa[k], h5py.Dataset) and fa[k].dtype.kind == "f":
                x, y = fa[k][...], fb[k][...]
                d = float(np.max(np.abs(x - y))) / max(1e-300, float(np.max(np.abs(x))))
                worst = max(worst, (d, k))
    return worst


def stage_table(old, new, start, work, stage, labels, title, column, result):
    """10 steps from `start` with each binary, alternated twice on 1 rank: `stage`'s time per
    step and the step's (without the checkpoint), the faster leg of each; written to `result`
    under `title`, the first column headed `column`, the rows named `labels` (old, new)."""
    work = pathlib.Path(work)
    work.mkdir(parents=True, exist_ok=True)
    sets = ["output.fields=false", "output.diagnostics_every=5", "time.max_steps=20"]
    legs = {labels[0]: [], labels[1]: []}
    for rep in range(2):
        for label, exe, tag in ((labels[0], old, "old"), (labels[1], new, "new")):
            out = work / f"{tag}_{rep}"
            s = run_capillary(exe, out, sets, restart=start)
            st = s["stages"]
            legs[label].append((st[stage] / s["steps"],
                                (s["wall_seconds"] - st.get("checkpoint", 0)) / s["steps"], out))
    worst = largest_difference(legs[labels[0]][0][2] / "checkpoint.h5",
                               legs[labels[1]][0][2] / "checkpoint.h5")
    with open(result, "w") as f:
        f.write(f"# {title} (session 48)\n\nMade by `measure.py` (this folder): "
                "cases/capillary_coarse (C = 10), 10 steps from its step-10 checkpoint on 1 "
                "rank, the two binaries alternated twice, the faster leg of each kept. 1-minute "
                f"load after the runs: {os.getloadavg()[0]:.2f}.\n\n")
        f.write(f"| {column} | {stage} [s/step] | step without checkpoint [s/step] |\n"
                "|---|---|---|\n")
        for label, rows in legs.items():
            f.write(f"| {label} | {min(r[0] for r in rows):.4f} | "
                    f"{min(r[1] for r in rows):.3f} |\n")
        f.write(f"\nLargest relative difference of the two checkpoints' datasets: "
                f"{worst[0]:.1e} ({worst[1]}).\n")
    print(open(result).read())
