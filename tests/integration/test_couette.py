"""Plane Couette flow from rest reaches the exact linear profile u = U y / H to round-off:
the second-order stencils are exact for a linear profile, so nothing but time limits the
error. Backward Euler with a large fixed dt damps every transient mode fast."""
import os

import numpy as np

from efsi_harness import check, datasets, parse_args, run

args = parse_args()
out = os.path.join(args.output, "couette")
run(args, "couette", out, sets=["fluid.viscosity=1.0", "time.viscous=backward_euler",
                                "time.dt=0.05", "time.end_time=3.0", "output.fields=false"])
d = datasets(os.path.join(out, "checkpoint.h5"))
u = d["velocity_u"]  # [nz][ny][nx], faces normal to x
v = d["velocity_v"]
ny = u.shape[1]
y = (np.arange(ny) + 0.5) / ny  # H = 1, U = 1
err = np.abs(u - y[None, :, None]).max()
check(u.shape == (1, 32, 8), f"velocity_u has shape [nz][ny][nx] = {u.shape}")
check(err < 1e-8, f"|u - U y/H| = {err:.2e} < 1e-8")
check(np.abs(v).max() < 1e-10, f"|v| = {np.abs(v).max():.2e} < 1e-10")
