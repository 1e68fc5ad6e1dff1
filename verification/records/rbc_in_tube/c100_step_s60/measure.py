"""Does the membrane step make the C = 100 red cell lose its strain consistency (issue 20,
"C = 100 must run")? The lone C = 100 cell of rbc_in_tube on the case's grid (96 x 48 x 48,
h = 0.25 um) to 3 ms at three fixed steps, F times the automatic step of the former limit
factor 4 (F = 1: dt = 2 mu h / K = 0.000498 ms; today's automatic step is F = 2.5):

- F = 1: made in session 60 (folder F1 here);
- F = 2.5: session 59's run at the automatic step (../c100_h034_s59/h025);
- F = 4: session 58's step survey (folder F4 here; dt = 0.001992 ms, binary of fa99686 plus
  the factor change, before the bound on kappa_R of 687f8bf, which leaves this grid's run
  unchanged: docs/method.md "Membrane bending").

Per run: when the largest tr Gs first passes 2.1, 2.2, 2.5 and 3.0 (bodies.csv every 10
steps; an unstrained membrane has 2), the largest speed in the tube and tr Gs per half
millisecond (the flow's own speed is about 2 um/ms), and the measures of ../c100_s46 at 3 ms.
Writes result.md here.

    /usr/bin/python3 verification/records/rbc_in_tube/c100_step_s60/measure.py

The F = 1 run (one rank, 6025 steps, 2037 s, the machine running one other job):

    efsi run cases/rbc_in_tube -o F1 -q --set 'body[1].area_dilation=100' \\
        --set time.end_time=3 --set time.dt=0.000498 \\
        --set output.checkpoint_every=500 --set output.fields_interval=1.0

(F = 4: the same with time.dt=0.001992; F = 2.5: without time.dt.)

A fourth run (folder profile2): the automatic step with the profile restoration that the
red cells have off (`--set 'body[1].profile_iterations=2'`, no time.dt), stopped by hand at
0.61 ms (step 490; no summary.json), the machine running the d/32 capsule on two ranks beside
it. It is in the first two tables only.
"""
import importlib.util
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2] / "studies"))
from _flowio import body_series  # noqa: E402


def load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


s46 = load("c100_s46", HERE.parent / "c100_s46" / "measure.py")
s59 = load("c100_h034_s59", HERE.parent / "c100_h034_s59" / "measure.py")
RUNS = (("F = 1 (dt 0.000498 ms)", HERE / "F1"),
        ("F = 2.5 (automatic, 0.001244 ms)", HERE.parent / "c100_h034_s59" / "h025"),
        ("F = 4 (dt 0.001992 ms)", HERE / "F4"))
PROFILE = ("F = 2.5 with the profile restoration (2 pseudo-steps), to 0.61 ms", HERE / "profile2")
THRESHOLDS = (2.1, 2.2, 2.5, 3.0)


def first_passage(run: Path) -> list[str]:
    t, trace = body_series(run, "rbc", ("tensor_trace_max",))
    cells = []
    for level in THRESHOLDS:
        above = np.nonzero(trace > level)[0]
        cells.append(f"{t[above[0]]:.3f}" if above.size else "-")
    return cells


def main() -> str:
    lines = ["# The C = 100 red cell at three membrane steps, h = 0.25 um (session 60)", "",
             "Made by `measure.py` (this folder; its docstring has the commands).", "",
             "Time [ms] at which max tr Gs first exceeds a level:", "",
             "| run | " + " | ".join(f"> {v:g}" for v in THRESHOLDS) + " |",
             "|---|" + "---|" * len(THRESHOLDS)]
    for name, run in RUNS + (PROFILE,):
        lines.append(f"| {name} | " + " | ".join(first_passage(run)) + " |")
    lines += ["", "Largest speed in the tube [um/ms] / largest tr Gs, per interval of t [ms]:", "",
              "| run | " + " | ".join(f"({lo:g}, {hi:g}]" for lo, hi in s59.INTERVALS) + " |",
              "|---|" + "---|" * len(s59.INTERVALS)]
    for name, run in RUNS + (PROFILE,):
        lines.append(f"| {name} | " + " | ".join(s59.per_interval(run)) + " |")
    measures = [s46.measure(run, 3.0) for _, run in RUNS]
    lines += ["", "At 3 ms (the measures of ../c100_s46/measure.py):", "",
              "| quantity | " + " | ".join(name for name, _ in RUNS) + " |",
              "|---|" + "---|" * len(RUNS)]
    for key in measures[0]:
        cells = [m[key] if isinstance(m[key], str) else f"{m[key]:.4g}" for m in measures]
        lines.append(f"| {key} | " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n"
    (HERE / "result.md").write_text(text)
    return text


if __name__ == "__main__":
    print(main(), end="")
