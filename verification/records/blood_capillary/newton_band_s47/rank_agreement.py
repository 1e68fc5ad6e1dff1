"""cases/body_translation with the Newton foot points on (body[2], the smoothed capsule with
the reference map) on 1 rank and on 2 (split along x, as tests/integration/test_bodies.py
checks the default keys): the four largest relative differences of the checkpoints' datasets.

    /usr/bin/python3 rank_agreement.py EFSI_BINARY TAG   (from the repository root)
"""
import os
import subprocess
import sys

import h5py
import numpy as np

SETS = ["grid.cells=[32,16,1]", "grid.length=[2.0,1.0,0.0625]",
        "body[2].newton_foot_points=true"]


def run(exe, out, ranks, extra=()):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = ([] if ranks == 1 else ["mpirun", "-np", str(ranks)])
    cmd += [exe, "run", "cases/body_translation", "-o", out, "-q"]
    for s in SETS + list(extra):
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, env=env, capture_output=True)


def datasets(path):
    with h5py.File(path) as f:
        return {k: f[k][...] for k in f.keys()
                if isinstance(f[k], h5py.Dataset) and f[k].dtype.kind == "f"}


if __name__ == "__main__":
    exe, tag = sys.argv[1], sys.argv[2]
    run(exe, f"/tmp/nr_{tag}_1", 1)
    run(exe, f"/tmp/nr_{tag}_2", 2, ["parallel.ranks=[2,1,1]"])
    a = datasets(f"/tmp/nr_{tag}_1/checkpoint.h5")
    b = datasets(f"/tmp/nr_{tag}_2/checkpoint.h5")
    worst = sorted(((float(np.max(np.abs(b[k] - v))) / max(1e-300, float(np.max(np.abs(v)))), k)
                    for k, v in a.items()), reverse=True)[:4]
    print(tag, worst)
