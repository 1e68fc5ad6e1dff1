"""Shared driver for the end-to-end tests: run bin/efsi (serially or under mpiexec) on a
case with --set overrides, read its HDF5 outputs, and fail with a readable message.

Every script takes --efsi, --mpiexec, --cases and --output (a folder of its own, so the
scripts can run concurrently under ctest -j)."""
import argparse
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

TWO_PI = 6.283185307179586


def parse_args():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--efsi", required=True)
    p.add_argument("--mpiexec", default="mpiexec")
    p.add_argument("--cases", required=True)
    p.add_argument("--output", required=True)
    a = p.parse_args()
    shutil.rmtree(a.output, ignore_errors=True)
    os.makedirs(a.output)
    return a


def run(args, case, out=None, ranks=1, sets=(), extra=(), command="run", expect=0):
    """Run efsi; returns the CompletedProcess. `expect` is the required exit code (None: any)."""
    cmd = [] if ranks == 1 else [args.mpiexec, "-np", str(ranks), "--oversubscribe"]
    case_path = case if os.path.isabs(case) else os.path.join(args.cases, case)
    cmd += [args.efsi, command, case_path]
    if out is not None:
        cmd += ["--output", out]
    if command == "run":
        cmd += ["--quiet"]
    for s in sets:
        cmd += ["--set", s]
    cmd += list(extra)
    # Yield instead of busy-waiting: with more ranks than cores (4 ranks on the 2-core CI
    # machine) busy-polling ranks starve the one with work; body_translation on 4 ranks took
    # 284 s polling, 3.8 s yielding.
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_mpi_yield_when_idle="1")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=800)
    if expect is not None and proc.returncode != expect:
        fail(f"{' '.join(cmd)}\nexited {proc.returncode}, expected {expect}\n"
             f"stdout:\n{proc.stdout[-3000:]}\nstderr:\n{proc.stderr[-3000:]}")
    return proc


def datasets(path):
    """Every dataset of an HDF5 file as {name: array}. A checkpoint's body dataset holds only
    its patch box (attribute box_lo: where the box starts, x, y, z): it is placed on the whole
    grid (the shape of "pressure"), zero outside the box, so that checkpoints written on any
    rank layout (whose patch boxes may differ) compare point by point. A box across the
    periodic x seam (x indices below 0 or past the grid) is placed at its indices modulo the
    grid's x cells."""
    out, boxes = {}, {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
                if "box_lo" in obj.attrs:
                    boxes[name] = [int(v) for v in obj.attrs["box_lo"]]
        f.visititems(visit)
        for name, (x0, y0, z0) in boxes.items():
            box = out[name]
            full = np.zeros(out["pressure"].shape, dtype=box.dtype)
            nz, ny, nx = box.shape
            columns = np.arange(x0, x0 + nx) % full.shape[2]
            full[z0:z0 + nz, y0:y0 + ny, columns] = box
            out[name] = full
        for k, v in f.attrs.items():
            # numeric attributes only (a checkpoint also holds its case fingerprint and
            # the checksum of its attributes as strings)
            if np.asarray(v).dtype.kind in "biuf":
                out["@" + k] = np.asarray(v)
    return out


def dataset_coverage(path):
    """For each body dataset of a checkpoint (a patch box, attribute box_lo), the grid cells its
    box covers, as a boolean array of the shape datasets() places it on: where two layouts'
    patches both hold a body's values (a tensor's value off the body, e.g. B = I, exists only
    where a patch stores it)."""
    out = {}
    with h5py.File(path, "r") as f:
        shape = f["pressure"].shape
        for name, obj in f.items():
            if isinstance(obj, h5py.Dataset) and "box_lo" in obj.attrs:
                x0, y0, z0 = (int(v) for v in obj.attrs["box_lo"])
                nz, ny, nx = obj.shape
                mask = np.zeros(shape, dtype=bool)
                mask[z0:z0 + nz, y0:y0 + ny, np.arange(x0, x0 + nx) % shape[2]] = True
                out[name] = mask
    return out


def tg_grid(n):
    """--set overrides for an n x n 2D Taylor-Green grid (cubic cells)."""
    return [f"grid.cells=[{n}, {n}, 1]",
            f"grid.length=[{TWO_PI!r}, {TWO_PI!r}, {TWO_PI / n!r}]"]



def csv_rows(out, name):
    """The rows of the run's CSV file `name` (adhesion.csv, bodies.csv, ...) as dicts."""
    import csv
    with open(os.path.join(out, name)) as f:
        return list(csv.DictReader(f))


def run_summary(out):
    """The run's summary.json."""
    import json
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)

def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def check(cond, msg):
    if not cond:
        fail(msg)
    print("ok:", msg)
