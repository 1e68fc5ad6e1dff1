"""Paired stage timings of two efsi binaries on one case, run in turn (old, new, old, ...).

    /usr/bin/python3 verification/records/performance/ab_stages.py OLD_BIN NEW_BIN REPEATS CASE \
        [--set key=value ...]

Prints a markdown table: the median over the repeats of each stage's seconds (summary.json
`stages`) and of the wall time, per binary, with the 1-minute load average before and after.
The VM's speed drifts by up to ~30 % within an hour, so only binaries run in turn like this
are compared; stop other jobs first (a paused job: kill -STOP).
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def main():
    old, new, repeats, case = sys.argv[1:5]
    sets = sys.argv[5:]
    runs = {"old": [], "new": []}
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(int(repeats)):
            for tag, exe in (("old", old), ("new", new)):
                out = Path(tmp) / tag
                subprocess.run([exe, "run", case, "-o", str(out), "-q", *sets], check=True,
                               stdout=subprocess.DEVNULL)
                runs[tag].append(json.loads((out / "summary.json").read_text()))
    load_after = os.getloadavg()[0]
    stages = sorted({k for s in runs["old"] + runs["new"] for k in s["stages"]})

    def med(tag, key):
        vals = [s["wall_seconds"] if key == "wall" else s["stages"].get(key, 0.0)
                for s in runs[tag]]
        return statistics.median(vals)

    print(f"case `{case}` {' '.join(sets)}; {repeats} runs of each binary in turn, medians; "
          f"1-minute load {load_before:.2f} before, {load_after:.2f} after")
    print()
    print("| stage | old [s] | new [s] | new / old |")
    print("|---|---|---|---|")
    for key in stages + ["wall"]:
        o, n = med("old", key), med("new", key)
        if max(o, n) < 0.005:
            continue
        print(f"| {key} | {o:.3f} | {n:.3f} | {n / o:.2f} |")


if __name__ == "__main__":
    main()
