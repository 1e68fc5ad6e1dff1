"""The overlap of the bodies' sharp equivalents (blood_capillary's max_body_overlap) per
snapshot of a capillary_coarse run, with the pair that sets it. The snapshots (fields/, 1.3
GB for this run) are not kept; rerun the case to regenerate them (README.md):

    /usr/bin/python3 verification/records/blood_capillary/contact_k20_t3/overlap.py RUN_DIR
"""
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "studies"))
import blood_capillary as bc  # noqa: E402


def main(run: Path):
    widths = bc.smoothing_widths(run)
    print("| t [ms] | max_body_overlap | pair |")
    print("|---|---|---|")
    for p in bc.snapshots(run):
        with h5py.File(p, "r") as f:
            phis = {k[4:]: f[k][...] for k in f.keys() if k.startswith("phi_")}
        sharp = {k: bc.sharp_fraction(v, widths[k]) if k in widths else v
                 for k, v in phis.items()}
        names = sorted(sharp)
        vols = {k: sharp[k].sum() for k in names}
        best, pair = 0.0, "-"
        for a in range(len(names)):
            for b in range(a + 1, len(names)):
                small = min(vols[names[a]], vols[names[b]])
                o = float(np.maximum(sharp[names[a]] + sharp[names[b]] - 1, 0).sum() / small)
                if o > best:
                    best, pair = o, f"{names[a]}, {names[b]}"
        print(f"| {bc.snapshot_time(p):.2f} | {best:.4f} | {pair} |")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
