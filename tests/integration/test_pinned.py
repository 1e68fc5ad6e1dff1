"""Pinned solids (body.pinned = true): a solid slab held on the bottom wall of a channel
driven by a pressure gradient (forcing.body_force), and a pinned cylinder in the same
channel. The penalisation -(phi / tau) v holds the velocity inside the solid at
|v| < 1e-6 x the channel velocity, the fluid above the slab sees a wall at its surface
(Poiseuille profile of the narrowed channel), and a pinned body neither moves nor changes
volume. Run with the implicit (Crank-Nicolson) and the explicit viscous scheme."""
import csv
import glob
import os

import h5py
import numpy as np

from efsi_harness import check, parse_args, run

CASE = """
[case]
name = "pinned_channel"
[grid]
cells = [8, 32, 1]
length = [0.25, 1.0, 0.03125]
[fluid]
density = 1.0
viscosity = 0.1
[boundary]
y_low = "wall"
y_high = "wall"
[forcing]
body_force = [0.8, 0.0, 0.0]
[time]
end_time = 15.0
viscous = "{scheme}"
dt_max = 0.05
[[body]]
name = "wall_layer"
kind = "solid"
shape = "slab"
centre = [0.0, 0.125, 0.0]
normal = [0.0, 1.0, 0.0]
thickness = 0.25
shear_modulus = 1.0
pinned = true
[output]
diagnostics_every = 50
progress_every = 1000
fields_interval = 0
"""

args = parse_args()
for scheme in ("crank_nicolson", "explicit"):
    path = os.path.join(args.output, f"{scheme}.toml")
    with open(path, "w") as f:
        f.write(CASE.format(scheme=scheme))
    out = os.path.join(args.output, scheme)
    run(args, path, out)
    last = sorted(glob.glob(os.path.join(out, "fields", "fields_*.h5")))[-1]
    with h5py.File(last, "r") as f:
        u = f["faces_u"][0].mean(axis=1)      # u(y), cell rows
        v = np.abs(f["faces_v"][0]).max()
        phi = f["phi_wall_layer"][...].reshape(u.size, -1).mean(axis=1)
    y = (np.arange(u.size) + 0.5) / u.size
    # Narrowed channel 1/4 < y < 1: U = G H^2 / (8 mu) with H = 3/4.
    U = 0.8 * 0.75 ** 2 / (8 * 0.1)
    inside = np.abs(u[phi > 0.999]).max()
    check(inside < 1e-6 * U, f"{scheme}: max |u| inside the pinned slab {inside:.2e} "
          f"< 1e-6 x channel velocity {U:.3f}")
    check(v < 1e-6 * U, f"{scheme}: max |v| {v:.2e} (1D flow)")
    # The last fully penalised u row (chi = 1) is the one centred h/2 below the surface:
    # the fluid sees its wall there (the first-order offset of a cell-wise penalisation).
    fluid, yw = y > 0.25, 0.25 - 0.5 / u.size
    exact = 0.8 / (2 * 0.1) * (y[fluid] - yw) * (1 - y[fluid])
    err = np.abs(u[fluid] - exact).max() / U
    check(err < 0.01, f"{scheme}: Poiseuille profile above the slab (wall at the centre of "
          f"the last solid row), max error {err:.4f} U")
    with open(os.path.join(out, "bodies.csv")) as f:
        rows = list(csv.DictReader(f))
    vol = [float(r["volume"]) for r in rows]
    cy = [float(r["centroid_y"]) for r in rows]
    check(max(vol) == min(vol), f"{scheme}: pinned volume unchanged ({vol[0]:.6e} m^3)")
    check(max(cy) == min(cy), f"{scheme}: pinned centroid unchanged (y = {cy[0]:.6f} m)")
