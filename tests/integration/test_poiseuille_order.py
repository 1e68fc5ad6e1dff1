"""Plane Poiseuille flow: the steady profile converges to u = G/(2 mu) y (H - y) at second
order in h (the wall mirror rule is exact for a line, O(h^2) for the parabola): the
error at 16 and 32 cells across gives an observed order in [1.8, 2.2]."""
import os

import numpy as np

from efsi_harness import check, datasets, parse_args, run

args = parse_args()
mu, G = 1.0, 8.0  # centreline speed G H^2 / (8 mu) = 1
errors = {}
for ny in (16, 32):
    out = os.path.join(args.output, f"ny{ny}")
    h = 1.0 / ny
    run(args, "poiseuille", out,
        sets=[f"grid.cells=[4, {ny}, 1]", f"grid.length=[{4 * h!r}, 1.0, {h!r}]",
              f"fluid.viscosity={mu}", f"forcing.body_force=[{G}, 0.0, 0.0]",
              "time.viscous=backward_euler", "time.dt=0.05", "time.end_time=4.0",
              "output.fields=false"])
    u = datasets(os.path.join(out, "checkpoint.h5"))["velocity_u"]
    y = (np.arange(ny) + 0.5) * h
    exact = G / (2 * mu) * y * (1 - y)
    errors[ny] = np.abs(u - exact[None, :, None]).max()
    print(f"ny = {ny}: max |u - exact| = {errors[ny]:.3e}")
order = np.log2(errors[16] / errors[32])
check(errors[32] < 1e-2, f"error at 32 cells {errors[32]:.2e} < 1e-2")
check(1.8 <= order <= 2.2, f"observed order {order:.3f} in [1.8, 2.2]")
