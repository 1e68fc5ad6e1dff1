"""A C = 100 red cell in the 10 um tube at capillary_coarse's spacing (session 59): is the
C = 100 capillary scene's loss of soundness after ~1.5 ms (docs/method.md, "The blood scene
with C = 100") the crowding of the scene or the red cells' resolution? The same single cell as
rbc_in_tube (C = 100) on 70 x 35 x 35 cells (h = 0.343 um, capillary_coarse's 0.344) and on the
case's 96 x 48 x 48 (h = 0.25 um), both to 3 ms at today's membrane step. Per run the measures of
../c100_s46/measure.py, and per interval the largest speed in the tube (diagnostics.csv; the
flow's own is about 2 um/ms) and the largest tr Gs (bodies.csv). Writes result.md here.

    /usr/bin/python3 verification/records/rbc_in_tube/c100_h034_s59/measure.py RUN_H034 RUN_H025

where the runs were made, one rank each, by

    efsi run cases/rbc_in_tube -o RUN_H034 -q --set 'grid.cells=[70,35,35]' \\
        --set 'body[1].area_dilation=100' --set time.end_time=3 \\
        --set output.checkpoint_every=500 --set output.fields_interval=1.0
    efsi run cases/rbc_in_tube -o RUN_H025 -q --set 'body[1].area_dilation=100' \\
        --set time.end_time=3 --set output.checkpoint_every=500 --set output.fields_interval=1.0

(70 x 35 x 35 needs the bound on kappa_R of commit 687f8bf: before it the run stopped UNSTABLE
at step 4). The runs' bodies.csv, diagnostics.csv, summary.json and case.toml are kept in the
folders h034/ and h025/ here, so `measure.py h034 h025` (from this folder) remakes result.md.
"""
import csv
import importlib.util
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
spec = importlib.util.spec_from_file_location("c100_s46", HERE.parent / "c100_s46" / "measure.py")
c100_s46 = importlib.util.module_from_spec(spec)
spec.loader.exec_module(c100_s46)
sys.path.insert(0, str(HERE.parents[2] / "studies"))
from _flowio import body_series  # noqa: E402

INTERVALS = [(0.0, 0.5), (0.5, 1.0), (1.0, 1.5), (1.5, 2.0), (2.0, 2.5), (2.5, 3.0)]


def per_interval(run: Path) -> list[str]:
    with open(run / "diagnostics.csv") as f:
        rows = [(float(r["time"]), float(r["max_speed"])) for r in csv.DictReader(f)]
    t_d = np.array([r[0] for r in rows])
    speed = np.array([r[1] for r in rows])
    t_b, trace = body_series(run, "rbc", ("tensor_trace_max",))
    cells = []
    for lo, hi in INTERVALS:
        s = speed[(t_d > lo) & (t_d <= hi + 1e-9)]
        g = trace[(t_b > lo) & (t_b <= hi + 1e-9)]
        cells.append(f"{s.max():.1f} / {g.max():.2f}" if s.size and g.size else "-")
    return cells


def main(h034: Path, h025: Path) -> str:
    a = c100_s46.measure(h034, 3.0)
    b = c100_s46.measure(h025, 3.0)
    lines = ["# A C = 100 red cell in the 10 um tube at capillary_coarse's spacing (session 59)", "",
             "Made by `measure.py` (this folder; its docstring has the commands).", "",
             "| quantity | h = 0.343 um (70 x 35 x 35) | h = 0.25 um (96 x 48 x 48, the case's) |",
             "|---|---|---|"]
    for k in a:
        f = (lambda v: v if isinstance(v, str) else f"{v:.4g}")
        lines.append(f"| {k} | {f(a[k])} | {f(b[k])} |")
    lines += ["", "Largest speed in the tube [um/ms] / largest tr Gs, per interval of t [ms]:", "",
              "| run | " + " | ".join(f"({lo:g}, {hi:g}]" for lo, hi in INTERVALS) + " |",
              "|---|" + "---|" * len(INTERVALS)]
    for name, run in (("h = 0.343 um", h034), ("h = 0.25 um", h025)):
        lines.append(f"| {name} | " + " | ".join(per_interval(run)) + " |")
    text = "\n".join(lines) + "\n"
    (HERE / "result.md").write_text(text)
    return text


if __name__ == "__main__":
    print(main(Path(sys.argv[1]), Path(sys.argv[2])), end="")
