"""Medians per binary of the A/B lines in this folder's *.txt (ab.sh / capsule_ab.sh output):
python3 summarise.py > summary.txt"""
import statistics
import sys
from pathlib import Path

here = Path(__file__).resolve().parent
KEYS = ("step", "viscous_solve", "bodies_extension", "bodies_tensor", "bodies_vof",
        "body_stress", "bodies_surface_velocity")


def read_runs(path):
    """{binary label: [{key: value} per run]} of one A/B file."""
    runs = {}
    for line in path.read_text().split("\n"):
        words = line.split()
        if len(words) < 6:
            continue
        runs.setdefault(words[0], []).append(dict(zip(words[1::2], words[2::2])))
    return runs


for path in sorted(here.glob("ab_*.txt")):
    runs = read_runs(path)
    np_ = next(iter(runs.values()))[0]["np"]
    keys = [k for k in KEYS if all(k in v for r in runs.values() for v in r)]
    print(f"{path.name} ({np_} rank(s)), seconds per step, median of {min(map(len, runs.values()))} runs each:")
    print("| binary | " + " | ".join(keys) + " |")
    print("|---" * (len(keys) + 1) + "|")
    med = {}
    for label, rs in runs.items():
        med[label] = [statistics.median(float(r[k]) for r in rs) for k in keys]
        print(f"| {label} | " + " | ".join(f"{m:.4f}" for m in med[label]) + " |")
    labels = list(med)
    if len(labels) == 2:
        a, b = labels
        print(f"| {a} / {b} | " + " | ".join(f"{x / y:.3f}" for x, y in zip(med[a], med[b])) + " |")
    print()

# The machine's speed drifted by up to 1.5x between runs minutes apart (the advection stage,
# which no change touched, took 0.0109 and 0.0208 s per step in two runs of the same binary).
# So each stage is also given relative to the same run's flow stages that the changes do not
# touch (viscous_solve + pressure_solve + predictor), which drift with it.
print("Relative to the same run's viscous_solve + pressure_solve + predictor (medians):")
print()
for path in sorted(here.glob("ab_*.txt")):
    runs = read_runs(path)
    keys = [k for k in KEYS if all(k in v for r in runs.values() for v in r)]
    ref = ("viscous_solve", "pressure_solve", "predictor")
    print(f"{path.name}:")
    print("| binary | " + " | ".join(keys) + " |")
    print("|---" * (len(keys) + 1) + "|")
    med = {}
    for label, rs in runs.items():
        med[label] = [statistics.median(float(r[k]) / sum(float(r[q]) for q in ref) for r in rs)
                      for k in keys]
        print(f"| {label} | " + " | ".join(f"{m:.3f}" for m in med[label]) + " |")
    labels = list(med)
    if len(labels) == 2:
        a, b = labels
        print(f"| {a} / {b} | " + " | ".join(f"{x / y:.3f}" for x, y in zip(med[a], med[b])) + " |")
    print()
