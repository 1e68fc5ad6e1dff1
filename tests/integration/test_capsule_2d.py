"""The 2D (z-invariant) neo-Hookean capsule in shear (cases/capsule_shear_2d, d/16, Ca = 0.05)
against the independent 2D references of reference/ (README there): at shear-rate x t = 1
the Eulerian finite-element solution gives D = 0.3471 (d/16) and the boundary-integral
Lagrangian capsule D = 0.3395, inclination 0.1799 pi (FE) and 0.1828 pi (BI).
Checks: (1) D(1) within 3% of both; (2) inclination within 0.005 pi of both; (3) early
time D ~ t/2 (D(0.1) / 0.05 in [0.9, 1.1]); (4) volume conserved to 1e-10; (5) area
increases (the membrane is stretched)."""
import csv
import os

import numpy as np

from efsi_harness import check, parse_args, run

args = parse_args()
out = os.path.join(args.output, "capsule")
run(args, "capsule_shear_2d", out, sets=["time.end_time=1.0", "output.diagnostics_every=2"])
with open(os.path.join(out, "bodies.csv")) as f:
    rows = [r for r in csv.DictReader(f) if r["body"] == "capsule"]
t = np.array([float(r["time"]) for r in rows])
col = {k: np.array([float(r[k]) for r in rows]) for k in
       ("taylor_deformation", "inclination_over_pi", "volume", "area")}
d1 = float(np.interp(1.0, t, col["taylor_deformation"]))
th1 = float(np.interp(1.0, t, col["inclination_over_pi"]))
for name, d_ref, th_ref in (("FE", 0.3471, 0.1799), ("BI", 0.3395, 0.1828)):
    check(abs(d1 / d_ref - 1) < 0.03, f"D(1) = {d1:.4f} vs {name} {d_ref} ({100 * (d1 / d_ref - 1):+.1f}%)")
    check(abs(th1 - th_ref) < 0.005, f"inclination(1) = {th1:.4f} pi vs {name} {th_ref} pi")
early = float(np.interp(0.1, t, col["taylor_deformation"])) / 0.05
check(0.9 <= early <= 1.1, f"early time: D(0.1) / (0.1 / 2) = {early:.3f}")
drift = abs(col["volume"][-1] - col["volume"][0]) / col["volume"][0]
check(drift < 1e-10, f"volume drift {drift:.1e}")
check(col["area"][-1] > col["area"][0], f"area {col['area'][0]:.4f} -> {col['area'][-1]:.4f}")
