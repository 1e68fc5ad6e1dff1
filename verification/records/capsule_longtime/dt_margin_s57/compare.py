"""D(t), the largest tr Gs and the area of continue.sh's runs (/tmp/dtprobe_F<F>) beside the
same times of capsule_longtime's own C = 100 run (its bodies.csv, automatic step).

    /usr/bin/python3 verification/records/capsule_longtime/dt_margin_s57/compare.py 2 3 4 6 10"""
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


tm, m = load(MAIN)
print("| F | from t | to t | status | max abs(D - D_auto) | D at the end (automatic step) "
      "| max tr Gs (automatic step) |")
print("|---|---|---|---|---|---|---|")
for f in sys.argv[1:]:
    out = Path(f"/tmp/dtprobe_F{f}")
    t, c = load(out / "bodies.csv")
    log = (Path(f"/tmp/dtprobe_F{f}.log")).read_text()
    if len(t) == 0:  # stopped before its first diagnostics row
        print(f"| {f} | - | - | UNSTABLE before a row of bodies.csv | - | - | - |")
        continue
    d_main = np.interp(t, tm, m["taylor_deformation"])
    window = (tm >= t[0]) & (tm <= t[-1])
    status = "UNSTABLE" if "UNSTABLE" in log else "completed"
    print(f"| {f} | {t[0]:.3f} | {t[-1]:.3f} | {status} | "
          f"{np.abs(c['taylor_deformation'] - d_main).max():.2e} | "
          f"{c['taylor_deformation'][-1]:.6f} ({d_main[-1]:.6f}) | "
          f"{c['tensor_trace_max'].max():.4f} ({m['tensor_trace_max'][window].max():.4f}) |")
