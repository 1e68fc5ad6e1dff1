"""Results on 1, 2 and 4 ranks agree to 1e-10 relative: 2D Taylor-Green (periodic) and a
small 3D walled box with a lid sliding in x and z on an anisotropic 12 x 10 x 8 grid.
Every dataset of checkpoint.h5 is compared."""
import os

import numpy as np

from efsi_harness import check, datasets, parse_args, run, tg_grid

args = parse_args()
setups = {
    "taylor_green": ("taylor_green", tg_grid(32) + ["time.max_steps=15", "output.fields=false"]),
    "walled_3d": ("lid_cavity", ["grid.cells=[12, 10, 8]", "grid.length=[1.2, 1.0, 0.8]",
                                 "boundary.z_low=wall", "boundary.z_high=free_slip",
                                 "boundary.y_high={type=\"wall\", velocity=[1.0, 0.0, 0.5]}",
                                 "fluid.viscosity=0.05", "time.max_steps=10",
                                 "output.fields=false"]),
}
for name, (case, sets) in setups.items():
    results = {}
    for ranks in (1, 2, 4):
        out = os.path.join(args.output, f"{name}_np{ranks}")
        run(args, case, out, ranks=ranks, sets=sets)
        results[ranks] = datasets(os.path.join(out, "checkpoint.h5"))
    ref = results[1]
    check(ref["@step"] > 0, f"{name}: {int(ref['@step'])} steps")
    for ranks in (2, 4):
        for key, a in ref.items():
            b = results[ranks][key]
            scale = max(np.abs(a).max(), 1e-300)
            rel = np.abs(a - b).max() / scale
            if rel > 1e-10:
                check(False, f"{name}: {key} on {ranks} ranks differs by {rel:.2e} relative")
        check(True, f"{name}: {len(ref)} datasets on {ranks} ranks agree with 1 rank to 1e-10")
