"""How far the automatic step of a membrane capsule is from the explicit membrane force's
stability limit, at any resolution, Ca, law and bending (session 58; session 57's survey.py,
dt_margin_s57, covered d/16 at Ca 0.025 only). capsule_longtime's keys (run_sets) with a fixed
time.dt = F x the automatic step (the stiffest body limit times time.cfl, as `efsi check`
prints it), from t = 0 to shear-rate x t = END, one run per F, one rank. Prints, per run, the
exit code, the time reached, D, the largest tr Gs and the largest relative area change, and
D at the end of the F = 1 run's span for comparison.

    /usr/bin/python3 verification/records/capsule_longtime/dt_margin_s58/survey.py \\
        --cells 8 --ca 0.025 --law skalak --c 100 --end 2 1 2 4 8 12

Runs go to /tmp/dts58_<name>_F<F>. The binary: EFSI_BIN, else build/bin/efsi (survey_case.py)."""
import argparse
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[4]
sys.path.insert(0, str(REPO / "verification" / "studies"))
from capsule_longtime import run_sets  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from survey_case import automatic_step, run_fixed  # noqa: E402

CASE = str(REPO / "cases" / "capsule_shear")

p = argparse.ArgumentParser()
p.add_argument("--cells", type=int, required=True)
p.add_argument("--ca", type=float, required=True)
p.add_argument("--law", default="neo_hookean")
p.add_argument("--c", type=float, default=0.0)
p.add_argument("--eb", type=float, default=0.0, help="Eb / (a^2 Es)")
p.add_argument("--end", type=float, required=True)
p.add_argument("factors", type=float, nargs="+")
a = p.parse_args()

name = f"n{a.cells}_ca{a.ca:g}_{a.law}" + (f"_C{a.c:g}" if a.law == "skalak" else "") + \
    (f"_bend{a.eb:g}" if a.eb > 0 else "")
args = []
for k, v in run_sets(a.cells, a.ca, a.end, a.law, a.c, a.eb).items():
    args += ["--set", f"{k}={v}"]
dt_auto, binding = automatic_step(CASE, args)
print(f"{name} dt_auto {dt_auto!r} (binding: {binding})", flush=True)
for f in a.factors:
    out = Path(f"/tmp/dts58_{name}_F{f:g}")
    rc, rows, err = run_fixed(CASE, out, args, f * dt_auto, [])
    d = float(rows[-1]["taylor_deformation"]) if rows else float("nan")
    tr = max(float(x["tensor_trace_max"]) for x in rows) if rows else float("nan")
    area = max(abs(float(x["area"]) / float(rows[0]["area"]) - 1) for x in rows) if rows \
        else float("nan")
    t = float(rows[-1]["time"]) if rows else 0.0
    print(f"{name} F={f:g} rc={rc} t={t:.4f} D={d:.6f} max_trGs={tr:.4f} "
          f"max_area_change={area:.5f} {err[:160]}", flush=True)
