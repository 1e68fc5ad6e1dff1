"""Tables of ab_*.txt (the output of ../body_rounds_s51/ab.sh): per run, s/step of the time
stepping and of the body stages, and the medians of each binary. Prints Markdown."""
import ast
import os
import statistics
import sys

here = os.path.dirname(os.path.abspath(__file__))
for name in sorted(f for f in os.listdir(here) if f.startswith("ab_") and f.endswith(".txt")):
    rows = []
    with open(os.path.join(here, name)) as f:
        for line in f:
            head, _, rest = line.partition("{")
            words = head.split()
            if len(words) < 5 or not rest:
                continue
            stages_text, _, load = rest.rpartition("}")
            rows.append((words[0], int(words[1]), float(words[4]),
                         ast.literal_eval("{" + stages_text + "}"), float(load)))
    if not rows:
        sys.exit(f"{name}: no runs")
    stages = sorted({k for r in rows for k in r[3]})
    print(f"\n{name} ({rows[0][1]} rank(s), runs in the order made):\n")
    print("| binary | step [s] | " + " | ".join(stages) + " | 1-min load before |")
    print("|---" * (len(stages) + 3) + "|")
    for label, _, step, st, load in rows:
        print(f"| {label} | {step:.3f} | " + " | ".join(f"{st.get(k, 0):.3f}" for k in stages)
              + f" | {load:.2f} |")
    for label in dict.fromkeys(r[0] for r in rows):
        sel = [r for r in rows if r[0] == label]
        print(f"| median {label} | {statistics.median(r[2] for r in sel):.3f} | "
              + " | ".join(f"{statistics.median(r[3].get(k, 0) for r in sel):.3f}" for k in stages)
              + " | |")
