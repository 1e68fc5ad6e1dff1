"""D(t), the largest tr Gs and the area of continue.sh's runs (/tmp/dtprobe58_F<F>) beside the
same times of capsule_longtime's own C = 100 run (its bodies.csv, automatic step), over the
span both hold (the study's run may not have reached the probe's end yet: the table says how
far it was compared).

    /usr/bin/python3 verification/records/capsule_longtime/dt_margin_s58/compare.py [MAIN_CSV] 4"""
import csv
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[4]
MAIN = REPO / "build/verification/capsule_longtime/runs/ca0.025_n64_skalak_C100_t20/bodies.csv"


def load(path):
    rows = list(csv.DictReader(open(path)))
    t = np.array([float(r["time"]) for r in rows])
    order = np.argsort(t, kind="stable")
    return t[order], {k: np.array([float(r[k]) for r in rows])[order]
                      for k in ("taylor_deformation", "tensor_trace_max", "area")}


args = sys.argv[1:]
main = Path(args.pop(0)) if args and args[0].endswith(".csv") else MAIN
tm, m = load(main)
print("| F | probe from t | probe to t | status | compared to t | max abs(D - D_auto) "
      "| D at the compared end, probe (automatic step) | max tr Gs, probe (automatic step) "
      "| max abs(area / area_auto - 1) |")
print("|---|---|---|---|---|---|---|---|---|")
for f in args:
    out = Path(f"/tmp/dtprobe58_F{f}")
    t, c = load(out / "bodies.csv")
    log = (Path(f"/tmp/dtprobe58_F{f}.log")).read_text()
    status = "UNSTABLE" if "UNSTABLE" in log else "completed"
    if len(t) == 0:
        print(f"| {f} | - | - | UNSTABLE before a row of bodies.csv | - | - | - | - | - |")
        continue
    both = t <= tm[-1]
    tb = t[both]
    d_main = np.interp(tb, tm, m["taylor_deformation"])
    a_main = np.interp(tb, tm, m["area"])
    window = (tm >= tb[0]) & (tm <= tb[-1])
    print(f"| {f} | {t[0]:.3f} | {t[-1]:.3f} | {status} | {tb[-1]:.3f} | "
          f"{np.abs(c['taylor_deformation'][both] - d_main).max():.2e} | "
          f"{c['taylor_deformation'][both][-1]:.6f} ({d_main[-1]:.6f}) | "
          f"{c['tensor_trace_max'][both].max():.4f} ({m['tensor_trace_max'][window].max():.4f}) | "
          f"{np.abs(c['area'][both] / a_main - 1).max():.2e} |")
