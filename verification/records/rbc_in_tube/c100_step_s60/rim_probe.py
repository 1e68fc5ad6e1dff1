"""Where the C = 100 red cell's strain grows (session 60): in a checkpoint of rbc_in_tube
(h = 0.25 um, tube axis at y = z = 6 um), the band cells (1e-3 < phi < 0.9, cells holding
the identity left out) with the largest tr Gs, and the profile through the first of them
along y: the wall's phi, the red cell's phi and u. The checkpoints are not kept (23 MB each);
this script's output is, in rim_probe_F1.txt and rim_probe_F4.txt.

    /usr/bin/python3 verification/records/rbc_in_tube/c100_step_s60/rim_probe.py F1/checkpoint.h5
"""
import sys
from pathlib import Path

import h5py
import numpy as np

H = 0.25  # um
AXIS = 6.0  # um


def probe(path: str) -> str:
    with h5py.File(path, "r") as f:
        lo = f["body_rbc_phi"].attrs["box_lo"]
        phi = f["body_rbc_phi"][...]  # (z, y, x) on the patch, x from lo[0]
        trace = sum(f[f"body_rbc_Gs_{c}"][...] for c in ("xx", "yy", "zz"))
        wall = f["body_wall_phi"][...]
        u = f["velocity_u"][...]
        t = float(f.attrs["time"])
    band = (phi > 1e-3) & (phi < 0.9) & (np.abs(trace - 3) > 1e-9)
    order = np.argsort(np.where(band, trace, 0).ravel())[::-1][:8]
    run = Path(path).resolve().parent.name  # the run's folder, not where it lay
    out = [f"{run}/{Path(path).name} at t = {t:g} ms: largest tr Gs in the band (1e-3 < phi < 0.9)"]
    for q in order:
        k, j, i = np.unravel_index(q, phi.shape)
        x, y, z = (i + lo[0] + 0.5) * H, (j + 0.5) * H, (k + 0.5) * H
        out.append(f"  tr Gs {trace.flat[q]:.3f}  phi {phi.flat[q]:.4f}  x {x:.3f}  y {y:.3f}  "
                   f"z {z:.3f}  r {np.hypot(y - AXIS, z - AXIS):.3f} um")
    k, j, i = np.unravel_index(order[0], phi.shape)
    out.append(f"profile along y at x = {(i + lo[0] + 0.5) * H:.3f}, z = {(k + 0.5) * H:.3f} um:")
    out.append("  y [um]  wall phi  cell phi  u [um/ms]")
    for jj in range(0, j + 6):
        out.append(f"  {(jj + 0.5) * H:6.3f}  {wall[k, jj, i + lo[0]]:8.4f}  {phi[k, jj, i]:8.4f}  "
                   f"{u[k, jj, i + lo[0]]:9.3f}")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    print(probe(sys.argv[1]), end="")
