"""The paper's Fig. 5 scene (cases/platelet_adhesion_rbc): a platelet 100 nm above a vWF
patch in channel flow, with red cells seeded to Ht 20 % and without. A short run checks
(1) the seeding: 4 red cells, the haematocrit reached between 18 % and 20 %, the same scene
    (every body's centroid at every row to 1e-10 relative) on 1 and 2 ranks;
(2) the adhesion is live near the patch: receptors within reach of a ligand plus the
    skip test's margin are counted from the first rows, but no bond forms while the
    platelet stays 100 nm from the wall (30 nm beyond the reactive distance);
(3) without red cells (target 0): no red cell, no membrane field in the snapshot, and the
    platelet's rows match the run with red cells' at step 0."""
import glob
import os

import h5py

from efsi_harness import check, csv_rows, parse_args, run, run_summary

args = parse_args()
case = os.path.join(args.cases, "platelet_adhesion_rbc")
SHORT = ["time.end_time=3.0e-5"]


rows, summary = csv_rows, run_summary
out = {}
for ranks in (1, 2):
    out[ranks] = os.path.join(args.output, f"rbc_np{ranks}")
    run(args, case, out[ranks], ranks=ranks, sets=SHORT)

# (1) the seeding
seeding = summary(out[1])["seeding"]
check(seeding["placed"] == {"rbc": 4}, f"4 red cells placed ({seeding['placed']})")
ht = seeding["achieved_haematocrit"]
check(0.18 <= ht <= 0.2, f"haematocrit reached {ht:.4f} in [0.18, 0.2]")
b1, b2 = rows(out[1], "bodies.csv"), rows(out[2], "bodies.csv")
check(len(b1) == len(b2) and len(b1) > 5, f"bodies.csv has the same {len(b1)} rows on 1 and 2 ranks")
worst = 0.0
for r1, r2 in zip(b1, b2):
    assert r1["body"] == r2["body"] and r1["step"] == r2["step"]
    for k in ("centroid_x", "centroid_y", "centroid_z"):
        a, b = float(r1[k]), float(r2[k])
        worst = max(worst, abs(a - b) / max(abs(a), 1e-12))
check(worst <= 1e-10, f"every body's centroid the same on 1 and 2 ranks ({worst:.2e} relative)")
names = sorted({r["body"] for r in b1})
check(names == ["platelet", "rbc_0", "rbc_1", "rbc_2", "rbc_3"], f"bodies {names}")

# (2) adhesion near the patch, no bond yet
adh = rows(out[1], "adhesion.csv")
near = [int(r["free_near"]) for r in adh[1:]]
check(min(near) > 0, f"receptors near the patch counted from the first rows ({min(near)}-{max(near)})")
check(all(int(r["bonds"]) == 0 for r in adh), "no bond while the platelet stays 100 nm above")

# (3) without red cells
free = os.path.join(args.output, "free")
run(args, case, free, sets=SHORT + ["seeding.target_haematocrit=0"])
s = summary(free)["seeding"]
check(s["placed"] == {"rbc": 0} and s["achieved_haematocrit"] == 0, f"no red cell ({s['placed']})")
bf = rows(free, "bodies.csv")
check({r["body"] for r in bf} == {"platelet"}, "bodies.csv holds the platelet only")
snap = sorted(glob.glob(os.path.join(free, "fields", "fields_*.h5")))[0]
with h5py.File(snap, "r") as f:
    keys = list(f.keys())
check(not any(k.startswith("rbc") or k.startswith("phi_rbc") for k in keys),
      "no red-cell field in the snapshot")
p0 = next(r for r in b1 if r["body"] == "platelet" and r["step"] == "0")
f0 = next(r for r in bf if r["body"] == "platelet" and r["step"] == "0")
check(all(p0[k] == f0[k] for k in ("volume", "centroid_x", "centroid_y", "centroid_z")),
      "the platelet starts the same with and without red cells")
print("PASS")
