"""The output folder: meshio reads fields/fields.xdmf as a time series with cell data of
the right shape (2D on 2 ranks, 3D), the snapshots fall on multiples of fields_interval
(an interval that no adaptive step divides: the step is shortened to land on them),
diagnostics.csv has its header and rows, and summary.json holds the documented keys."""
import csv
import json
import os

import meshio

from efsi_harness import check, datasets, parse_args, run, tg_grid

args = parse_args()
setups = {
    "tg2d": ("taylor_green", 2, tg_grid(16) + ["time.end_time=0.4", "output.fields_interval=0.13"],
             16 * 16),
    "box3d": ("lid_cavity", 1, ["grid.cells=[6, 5, 4]", "grid.length=[1.2, 1.0, 0.8]",
                                "boundary.z_low=wall", "boundary.z_high=wall", "time.max_steps=3"],
              6 * 5 * 4),
}
for name, (case, ranks, sets, ncells) in setups.items():
    out = os.path.join(args.output, name)
    run(args, case, out, ranks=ranks, sets=sets)
    with meshio.xdmf.TimeSeriesReader(os.path.join(out, "fields", "fields.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        check(sum(len(c.data) for c in cells) == ncells, f"{name}: mesh has {ncells} cells")
        check(reader.num_steps >= 2, f"{name}: {reader.num_steps} snapshots")
        if name == "tg2d":
            times = [reader.read_data(k)[0] for k in range(reader.num_steps)]
            want = [0.0, 0.13, 0.26, 0.39, 0.4]
            check(len(times) == len(want) and all(abs(a - b) < 1e-12 for a, b in zip(times, want)),
                  f"{name}: snapshot times {times} are {want}")
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            p, vel = cell_data["pressure"][0], cell_data["velocity"][0]
            check(p.shape in [(ncells,), (ncells, 1)] and vel.shape == (ncells, 3),
                  f"{name} t = {t:.3g}: pressure {p.shape}, velocity {vel.shape}")
    with open(os.path.join(out, "diagnostics.csv")) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) >= 2 and "max_divergence" in rows[0], f"{name}: {len(rows)} diagnostics rows")
    check(max(float(r["max_divergence"]) for r in rows) < 1e-8, f"{name}: divergence-free")
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    for key in ("ranks", "cells", "steps", "wall_seconds", "cell_updates_per_second", "stages",
                "final"):
        check(key in s, f"{name}: summary.json has {key}")
    # box3d ends on time.max_steps before time.end_time, which its status says.
    want = "max_steps" if name == "box3d" else "completed"
    check(s["ranks"] == ranks and s["cells"] == ncells and s["status"] == want,
          f"{name}: summary ranks {s['ranks']}, cells {s['cells']}, {s['status']}")
    # On more than one rank, each stage's least and largest time over the ranks.
    if ranks > 1:
        lo, hi = s.get("stages_rank_min", {}), s.get("stages_rank_max", {})
        check(sorted(lo) == sorted(s["stages"]) == sorted(hi)
              and all(0 <= lo[k] <= s["stages"][k] <= hi[k] for k in lo),
              f"{name}: stages_rank_min <= stages <= stages_rank_max for {len(lo)} stages")
    else:
        check("stages_rank_min" not in s, f"{name}: no rank spread on one rank")
    check(os.path.exists(os.path.join(out, "case.toml")), f"{name}: resolved case echoed")

# A body's fields in a snapshot: stored in deflated chunks (io/hdf5_file.cpp), so the file
# holds the patch and not the grid, with the same values as the checkpoint's (contiguous)
# copy and zeros outside the patch; the flow's fields stay contiguous.
import h5py  # noqa: E402
import numpy as np  # noqa: E402

out = os.path.join(args.output, "capsule3d")
run(args, "capsule_shear", out, ranks=2,
    sets=["grid.cells=[32, 32, 32]", "grid.length=[8.0, 8.0, 8.0]", "grid.origin=[-4.0, -4.0, -4.0]",
          "time.end_time=0.05", "output.fields_interval=0.05"])
snaps = sorted(f for f in os.listdir(os.path.join(out, "fields")) if f.startswith("fields_0"))
last = os.path.join(out, "fields", snaps[-1])
with h5py.File(last, "r") as f, h5py.File(os.path.join(out, "checkpoint.h5"), "r") as c:
    check(abs(float(f.attrs["time"]) - float(c.attrs["time"])) < 1e-12,
          f"capsule3d: the last snapshot ({snaps[-1]}) is at the checkpoint's time")
    phi = f["phi_capsule"]
    check(phi.chunks is not None and phi.compression == "gzip",
          f"capsule3d: phi_capsule stored in deflated chunks ({phi.chunks}, {phi.compression})")
    check(f["pressure"].chunks is None and f["velocity"].chunks is None,
          "capsule3d: the flow's fields are contiguous")
    box = c["body_capsule_phi"]
    check("box_lo" in box.attrs and box.size < c["pressure"].size,
          f"capsule3d: the checkpoint holds the body's patch box only ({box.shape} from "
          f"{list(box.attrs.get('box_lo', []))}, grid {c['pressure'].shape})")
    stored = datasets(os.path.join(out, "checkpoint.h5"))["body_capsule_phi"]
    check(np.array_equal(phi[...].reshape(stored.shape), stored),
          "capsule3d: the snapshot's phi equals the checkpoint's, zeros outside the patch "
          "included")
    inside = int(np.count_nonzero(stored))
    check(0 < inside < stored.size // 2, f"capsule3d: the patch holds {inside} of "
          f"{stored.size} cells (a test of the zeros around it)")
    body = [k for k in f.keys() if k.startswith("phi_") or k.startswith("capsule_")]
    grid_bytes = sum(f[k].size * 8 for k in f.keys())
    size = os.path.getsize(last)
    check(len(body) >= 7 and size < 0.75 * grid_bytes,
          f"capsule3d: snapshot of {size} bytes against {grid_bytes} for {len(f.keys())} "
          f"datasets on the grid ({len(body)} of the body)")
