"""How much of the blood scene's body work the periodic seam costs (session 47).

A body's patch follows its occupied box (phi > 1e-8) plus a margin; along a periodic
direction a box that would cross the seam becomes the whole direction (bodies/patch.cpp,
make_patch). For each body whose stored patch covers the whole of a periodic direction, this
finds the shortest periodic interval holding its occupied cells, adds the margin on both
sides, and counts the cells a patch allowed to wrap would hold. Reads a checkpoint (the
patch boxes are its attributes, phi its body_<name>_phi datasets) and writes result.md
beside this file (or prints it with --print).

    /usr/bin/python3 verification/records/blood_capillary/seam_patches_s47/measure.py \
        build/verification/blood_capillary/runs/full/cells/checkpoint.h5 [more checkpoints]
"""
import sys
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
OCCUPIED = 1e-8   # VofOptions::epsilon: the patch follows phi above it
MARGIN = 4        # body.margin's default (config/body_config.cpp), what the cases use


def shortest_cover(occupied: np.ndarray) -> int:
    """Length of the shortest periodic interval holding every True entry."""
    n = occupied.size
    idx = np.flatnonzero(occupied)
    if idx.size == 0:
        return 0
    gaps = np.diff(np.concatenate([idx, [idx[0] + n]]))  # gap after each occupied index
    return n - (int(gaps.max()) - 1)


def measure(path: str) -> dict:
    f = h5py.File(path, "r")
    names = sorted({k[len("body_"):-len("_phi")] for k in f.keys()
                    if k.startswith("body_") and k.endswith("_phi")})
    rows = []
    for name in names:
        a = f.attrs
        lo = [int(a[f"body_{name}_lo{d}"]) for d in range(3)]
        hi = [int(a[f"body_{name}_hi{d}"]) for d in range(3)]
        phi = f[f"body_{name}_phi"]  # stored (z, y, x)
        nz, ny, nx = phi.shape
        cells = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])
        whole_x = lo[0] == 0 and hi[0] == nx
        wrapped_cells = cells
        if whole_x and name != "wall":
            occ_x = (phi[lo[2]:hi[2], lo[1]:hi[1], :] > OCCUPIED).any(axis=(0, 1))
            length = min(nx, shortest_cover(occ_x) + 2 * MARGIN)
            wrapped_cells = length * (hi[1] - lo[1]) * (hi[2] - lo[2])
        rows.append((name, cells, whole_x, wrapped_cells))
    t = float(f.attrs["time"]) if "time" in f.attrs else float("nan")
    return {"path": path, "time": t, "rows": rows}


def report(results: list) -> str:
    out = ["# The periodic seam's share of the blood scene's body patches", "",
           "Made by `measure.py` (this folder). A patch whose box would cross the periodic "
           "x seam covers the whole of x (bodies/patch.cpp); 'wrapped' is the patch it would "
           "have if it could cross the seam (the shortest periodic interval holding phi > "
           f"{OCCUPIED:g}, plus the margin of {MARGIN} cells on each side; y and z as stored).",
           "", "| checkpoint | t | moving bodies | patches over the whole of x | patch cells "
           "(moving bodies) | patch cells if wrapped | share the seam adds |",
           "|---|---|---|---|---|---|---|"]
    for r in results:
        moving = [x for x in r["rows"] if x[0] != "wall"]
        total = sum(x[1] for x in moving)
        wrapped = sum(x[3] for x in moving)
        whole = sum(1 for x in moving if x[2])
        out.append(f"| `{r['path']}` | {r['time']:.4g} | {len(moving)} | {whole} | {total} | "
                   f"{wrapped} | {1 - wrapped / total:.3f} |")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--print"]
    if not args:
        sys.exit(__doc__)
    text = report([measure(p) for p in args])
    if "--print" in sys.argv:
        print(text)
    else:
        (HERE / "result.md").write_text(text)
        print(text)
