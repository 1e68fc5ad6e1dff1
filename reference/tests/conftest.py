"""Shared helpers for the reference tests: paths and an MPI launcher that works as root."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

REF = Path(__file__).resolve().parent.parent
PY = "/usr/bin/python3"
sys.path.insert(0, str(REF))


def mpi_env():
    env = dict(os.environ)
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    return env


def run_script(args, ranks=1, timeout=900, cwd=None):
    """Run a reference script (path relative to reference/) serially or under mpirun."""
    cmd = [PY, str(REF / args[0])] + [str(a) for a in args[1:]]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] + cmd
    res = subprocess.run(cmd, env=mpi_env(), capture_output=True, text=True, timeout=timeout,
                         cwd=cwd or REF.parent)
    assert res.returncode == 0, f"{' '.join(cmd)} failed:\n{res.stdout[-2000:]}\n{res.stderr[-3000:]}"
    return res


@pytest.fixture
def outdir(tmp_path):
    return tmp_path
