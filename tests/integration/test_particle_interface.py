"""A neo-Hookean particle in channel flow (cases/particle_poiseuille at 8 cells per
diameter, to t = 2): the left Cauchy-Green tensor B stays bounded in the cells the solid
shares with the fluid (docs/method.md, Solids: extension of B).
(1) the run completes and tr B over every cell holding solid (bodies.csv
    tensor_trace_max) stays below 4 throughout: a plane-strain stretch lambda has
    tr B = lambda^2 + lambda^-2 + 1, so 4 means lambda = 1.62, while the particle's
    Taylor deformation D ~ 0.1 is a mean stretch of ~1.1;
(2) with the extension off (extension_threshold = 0: B carried with the mixed velocity
    gradient of the cut cells, the transport before the extension) the same run exceeds
    that bound, i.e. the check above can fail; tr B runs away and the run stops UNSTABLE
    on stability.max_tensor_trace (100) before t = 2, naming the particle;
(3) the particle's volume is kept to 1e-10 relative;
(4) 1, 2 and 4 ranks agree to 1e-10 relative at t = 1 (every checkpoint dataset, B where
    phi > 0), and a wider patch (margin 6) gives the same result bit for bit: without the
    extension, B of the sheared fluid near the patch edge reached the cut cells and the
    result depended on the patch, hence on the decomposition (5e-4 at t = 1);
(5) a restart from a mid-run checkpoint repeats the uninterrupted run bit for bit."""
import csv
import os

import numpy as np

from efsi_harness import check, datasets, parse_args, run

args = parse_args()
H = 0.25 / 8  # 8 cells per diameter: 64 x 32 cells
grid = ["grid.cells=[64, 32, 1]", f"grid.length=[2.0, 1.0, {H!r}]",
        f"body[0].centre=[0.5, 0.3, {H / 2!r}]", "output.fields=false"]


def bodies_csv(out):
    with open(os.path.join(out, "bodies.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows])
            for k in ("time", "volume", "tensor_trace_max", "centroid_y")}


on = os.path.join(args.output, "extension")
run(args, "particle_poiseuille", on, sets=grid + ["time.end_time=2.0"])
b = bodies_csv(on)
check(abs(b["time"][-1] - 2.0) < 1e-9, f"run reached t = {b['time'][-1]:.3f}")
check(b["tensor_trace_max"].max() < 4.0,
      f"with the extension: max tr B = {b['tensor_trace_max'].max():.3f} < 4")
drift = abs(b["volume"][-1] - b["volume"][0]) / b["volume"][0]
check(drift < 1e-10, f"volume drift {drift:.1e}")

off = os.path.join(args.output, "no_extension")
proc = run(args, "particle_poiseuille", off,
           sets=grid + ["time.end_time=2.0", "body[0].extension_threshold=0.0"], expect=3)
c = bodies_csv(off)
check(c["tensor_trace_max"].max() > 4.0,
      f"without the extension: max tr B = {c['tensor_trace_max'].max():.1f} > 4 (the bound "
      "can fail)")
check("'particle'" in proc.stderr and "stability.max_tensor_trace" in proc.stderr,
      f"without the extension: stopped on the tensor bound at t = {c['time'][-1]:.3f}")



def compare(a, b):
    """Largest relative difference over the datasets of two checkpoints: B only where both
    runs hold solid (phi > 0; elsewhere it depends on how far the patch reaches), the
    patch boxes (attributes, decomposition dependent) not at all."""
    solid = (a["body_particle_phi"] > 0) & (b["body_particle_phi"] > 0)
    worst = 0.0
    for k, v in a.items():
        if k.startswith("@body_"):
            continue
        d = np.abs(np.asarray(b[k], float) - np.asarray(v, float))
        if k.startswith("body_particle_B"):
            d = d[solid]
        worst = max(worst, float(d.max()) / max(1e-300, float(np.abs(v).max())))
    return worst


short = grid + ["time.end_time=1.0"]
reference = None
for ranks in (1, 2, 4):
    out = os.path.join(args.output, f"np{ranks}")
    run(args, "particle_poiseuille", out, ranks=ranks, sets=short)
    d = datasets(os.path.join(out, "checkpoint.h5"))
    if reference is None:
        reference = d
        continue
    worst = compare(reference, d)
    check(worst <= 1e-10, f"{ranks} ranks vs 1 at t = 1: max relative difference {worst:.1e}")
# The same on a wider patch: nothing outside the extended band reaches the solid.
wide = os.path.join(args.output, "margin6")
run(args, "particle_poiseuille", wide, sets=short + ["body[0].margin=6"])
worst = compare(reference, datasets(os.path.join(wide, "checkpoint.h5")))
check(worst == 0.0, f"patch margin 6 vs 4: max relative difference {worst:.1e}")

part = os.path.join(args.output, "part")
run(args, "particle_poiseuille", part, sets=short + ["time.max_steps=60"])
rest = os.path.join(args.output, "restart")
run(args, "particle_poiseuille", rest, sets=short,
    extra=["--restart", os.path.join(part, "checkpoint.h5")])
other = datasets(os.path.join(rest, "checkpoint.h5"))
worst = max(float(np.max(np.abs(other[k] - v))) for k, v in reference.items())
check(worst == 0.0, f"restart at step 60 vs uninterrupted: max difference {worst:.1e}")
