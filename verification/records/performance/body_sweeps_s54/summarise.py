"""Medians per binary of the A/B lines in this folder's *.txt (ab.sh / capsule_ab.sh output):
python3 summarise.py > summary.txt"""
import statistics
from pathlib import Path

here = Path(__file__).resolve().parent
KEYS = ("step", "viscous_solve", "bodies_extension", "bodies_tensor", "bodies_vof",
        "body_stress", "bodies_surface_velocity")
# Flow stages no change of the session touched: they drift with the machine's speed.
REFERENCE = ("viscous_solve", "pressure_solve", "predictor")


def read_runs(path):
    """{binary label: [{key: value} per run]} of one A/B file."""
    runs = {}
    for line in path.read_text().split("\n"):
        words = line.split()
        if len(words) < 6:
            continue
        runs.setdefault(words[0], []).append(dict(zip(words[1::2], words[2::2])))
    return runs


def table(title, runs, value, digits):
    """Median of value(run, key) per binary and stage, and the ratio of two binaries."""
    keys = [k for k in KEYS if all(k in v for r in runs.values() for v in r)]
    print(title)
    print("| binary | " + " | ".join(keys) + " |")
    print("|---" * (len(keys) + 1) + "|")
    med = {}
    for label, rs in runs.items():
        med[label] = [statistics.median(value(r, k) for r in rs) for k in keys]
        print(f"| {label} | " + " | ".join(f"{m:.{digits}f}" for m in med[label]) + " |")
    if len(med) == 2:
        a, b = list(med)
        print(f"| {a} / {b} | " + " | ".join(f"{x / y:.3f}" for x, y in zip(med[a], med[b])) + " |")
    print()


files = sorted(here.glob("ab_*.txt"))
for path in files:
    runs = read_runs(path)
    np_ = next(iter(runs.values()))[0]["np"]
    table(f"{path.name} ({np_} rank(s)), seconds per step, median of "
          f"{min(map(len, runs.values()))} runs each:", runs, lambda r, k: float(r[k]), 4)

# The machine's speed drifted by up to 1.5x between runs minutes apart (the advection stage,
# which no change touched, took 0.0109 and 0.0208 s per step in two runs of the same binary).
# So each stage is also given relative to the same run's REFERENCE stages, which drift with it.
print("Relative to the same run's viscous_solve + pressure_solve + predictor (medians):")
print()
for path in files:
    table(f"{path.name}:", read_runs(path),
          lambda r, k: float(r[k]) / sum(float(r[q]) for q in REFERENCE), 3)
