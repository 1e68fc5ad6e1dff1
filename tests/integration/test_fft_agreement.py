"""The direct FFT solves (solver.*.method = "auto", the default where they apply) give the
same run as hypre converged to 1e-13: 2D Taylor-Green (periodic), a 3D walled box with a
sliding lid and a free-slip face (walls, mixed closures) and a 3D channel (periodic x and
z, walls in y), Crank-Nicolson, on 1 rank and (FFT) on 2 ranks. Every dataset of
checkpoint.h5 is compared to 1e-10 relative."""
import os

import numpy as np

from efsi_harness import check, datasets, parse_args, run, tg_grid

args = parse_args()
hypre = ["solver.pressure.method=pcg_pfmg", "solver.pressure.tolerance=1e-13",
         "solver.viscous.method=pcg_pfmg", "solver.viscous.tolerance=1e-13"]
setups = {
    "taylor_green": ("taylor_green", tg_grid(32) + ["time.max_steps=15", "output.fields=false"]),
    "walled_3d": ("lid_cavity", ["grid.cells=[12, 10, 8]", "grid.length=[1.2, 1.0, 0.8]",
                                 "boundary.z_low=wall", "boundary.z_high=free_slip",
                                 "boundary.x_high=free_slip",
                                 "boundary.y_high={type=\"wall\", velocity=[1.0, 0.0, 0.5]}",
                                 "fluid.viscosity=0.05", "time.max_steps=10",
                                 "output.fields=false"]),
    "channel_3d": ("poiseuille", ["grid.cells=[8, 12, 4]", "grid.length=[0.6666666666666666, 1.0, 0.3333333333333333]",
                                  "boundary.z_low=periodic", "boundary.z_high=periodic",
                                  "initial.type=taylor_green", "fluid.viscosity=0.002",
                                  "time.max_steps=10",
                                  "output.fields=false"]),
}
worst = 0.0
for name, (case, sets) in setups.items():
    runs = {"fft_np1": (1, []), "fft_np2": (2, []), "hypre_np1": (1, hypre)}
    results = {}
    for label, (ranks, extra) in runs.items():
        out = os.path.join(args.output, f"{name}_{label}")
        proc = run(args, case, out, ranks=ranks, sets=list(sets) + extra)
        results[label] = datasets(os.path.join(out, "checkpoint.h5"))
    ref = results["hypre_np1"]
    check(ref["@step"] > 0, f"{name}: {int(ref['@step'])} steps")
    for label in ("fft_np1", "fft_np2"):
        for key, a in ref.items():
            b = results[label][key]
            scale = max(np.abs(a).max(), 1e-300)
            diff = float(np.abs(a - b).max())
            rel = diff / scale
            if diff <= 1e-15:
                continue  # a field that is zero up to round-off (e.g. no advection yet)
            worst = max(worst, rel)
            if rel > 1e-10:
                check(False, f"{name}: {key} with the FFT solves ({label}) differs from hypre "
                             f"by {rel:.2e} relative")
        check(True, f"{name}: {len(ref)} datasets agree with hypre to 1e-10 ({label})")
print(f"largest relative difference FFT vs hypre: {worst:.2e}")
