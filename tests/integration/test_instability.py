"""A run far beyond its stability limit stops with exit code 3 and a message naming the
step and the place (UNSTABLE ... step ... x = (...)), and writes no NaN into the fields:
(1) a fixed dt = 1 with an explicit viscous term (caught by the CFL check at once);
(2) an explicit viscous step 5x over its limit, which grows from round-off for a while
    before the velocity check catches it."""
import glob
import os

import numpy as np

from efsi_harness import check, datasets, parse_args, run, tg_grid

args = parse_args()
runs = {
    "cfl": tg_grid(32) + ["time.dt=1.0", "time.viscous=explicit"],
    "viscous": tg_grid(32) + ["time.dt=0.05", "time.viscous=explicit", "fluid.viscosity=1.0",
                              "stability.max_velocity=100", "time.end_time=5.0",
                              "output.fields_interval=0.05"],
}
for name, sets in runs.items():
    out = os.path.join(args.output, name)
    proc = run(args, "taylor_green", out, sets=sets, expect=3)
    msg = proc.stderr
    check("UNSTABLE" in msg and "step" in msg and "x = (" in msg,
          f"{name}: message names the step and place: {msg.strip()[:200]}")
    snaps = sorted(glob.glob(os.path.join(out, "fields", "fields_*.h5")))
    for f in snaps + glob.glob(os.path.join(out, "checkpoint.h5")):
        for k, v in datasets(f).items():
            if np.issubdtype(np.asarray(v).dtype, np.floating) and not np.all(np.isfinite(v)):
                check(False, f"{name}: {os.path.basename(f)}:{k} holds non-finite values")
    check(True, f"{name}: {len(snaps)} snapshot(s), all finite")
    if name == "viscous":
        step = int(msg.split("UNSTABLE at step ")[1].split(",")[0])
        check(step > 1, f"{name}: caught at step {step}, after growing")
