"""A run stopped at step N and continued with --restart matches the uninterrupted run bit
for bit (every checkpoint dataset and attribute), serially and on 2 ranks."""
import os

import numpy as np

from efsi_harness import check, datasets, parse_args, run, tg_grid

args = parse_args()
sets = tg_grid(32) + ["time.end_time=0.5", "output.fields_interval=0.1"]
for ranks in (1, 2):
    full = os.path.join(args.output, f"full_np{ranks}")
    part = os.path.join(args.output, f"part_np{ranks}")
    run(args, "taylor_green", full, ranks=ranks, sets=sets)
    run(args, "taylor_green", part, ranks=ranks, sets=sets + ["time.max_steps=4"])
    half = datasets(os.path.join(part, "checkpoint.h5"))
    check(int(half["@step"]) == 4, f"np{ranks}: first part stopped at step 4")
    run(args, "taylor_green", part, ranks=ranks, sets=sets,
        extra=["--restart", os.path.join(part, "checkpoint.h5")])
    a = datasets(os.path.join(full, "checkpoint.h5"))
    b = datasets(os.path.join(part, "checkpoint.h5"))
    check(int(a["@step"]) > 4, f"np{ranks}: uninterrupted run took {int(a['@step'])} steps")
    check(sorted(a) == sorted(b), f"np{ranks}: same datasets {sorted(a)}")
    for k in a:
        if not np.array_equal(a[k], b[k]):
            diff = np.abs(np.asarray(a[k], float) - np.asarray(b[k], float)).max()
            check(False, f"np{ranks}: {k} differs after restart (max {diff:.3e})")
    check(True, f"np{ranks}: restarted checkpoint identical bit for bit")
