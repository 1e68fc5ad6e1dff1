"""The red cell of rbc_in_tube (the tens250 record's case: h = 0.25 um, carried Gs, one rank)
rerun with the session-38 patches (residues dropped, moves decided on the fitted box), its
patch size against the tens250 record's at the same steps. The x-periodic box is 96 cells
long and the cell about 32 with its margin, so the patch covers the whole box while the cell
straddles the seam (221 184 cells); the rows below are those where it does not.
    efsi run verification/records/rbc_in_tube/tens250/case.toml -o OUT -q --set output.fields=false
    /usr/bin/python3 compare.py verification/records/rbc_in_tube/tens250 OUT > result.md"""
import csv
import sys

old, new = sys.argv[1], sys.argv[2]


def rows(out):
    return {int(r["step"]): r for r in csv.DictReader(open(f"{out}/bodies.csv"))}


a, b = rows(old), rows(new)
steps = sorted(set(a) & set(b))
full = 96 * 48 * 48
print("| step | t [ms] | patch cells, tens250 (before) | patch cells, after | centroid x before / after [um] |")
print("|---|---|---|---|---|")
shown = 0
for s in steps:
    pa, pb = int(a[s]["patch_cells"]), int(b[s]["patch_cells"])
    if pa == full or pb == full or s % 50:
        continue
    print(f"| {s} | {float(a[s]['time']):.3f} | {pa} | {pb} | "
          f"{float(a[s]['centroid_x']):.3f} / {float(b[s]['centroid_x']):.3f} |")
last = steps[-1]
print()
print(f"last common step {last}: volume before {float(a[last]['volume']):.12e}, after "
      f"{float(b[last]['volume']):.12e}; after, relative to its start "
      f"{float(b[last]['volume']) / float(b[0]['volume']) - 1:.1e}")
