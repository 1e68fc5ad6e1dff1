#!/usr/bin/python3
"""D(t) of the d/16 and d/32 capsule_longtime records minus each published curve at a few
times (verification/data/capsule_shear): where along the run the d/32 runs part from the
boundary-element results. Run: /usr/bin/python3 verification/records/capsule_longtime/reference_gap.py
[suffix], suffix appended to the record names (e.g. _proj); docs/method.md quotes it."""
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE.parents[1] / "data" / "capsule_shear"
sys.path.insert(0, str(HERE.parents[1] / "studies"))
from _flowio import body_series  # noqa: E402

SOURCES = ("pozrikidis1995", "ramanujan_pozrikidis1998", "eggleton_popel1998")
TIMES = (0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 7.5)


def main() -> int:
    suffix = sys.argv[1] if len(sys.argv) > 1 else ""
    print("| Ca | reference | t | published D | d/16 - published | d/32 - published |")
    print("|---|---|---|---|---|---|")
    for ca in ("0.2", "0.1", "0.05"):
        runs = {}
        for label, name in (("d16", f"ca{ca}_n64_t20{suffix}"), ("d32", f"ca{ca}_n128_t10{suffix}")):
            if (HERE / name / "bodies.csv").exists():
                t, D = body_series(HERE / name)[:2]
                runs[label] = (t, D)
        for src in SOURCES:
            f = DATA / f"{src}_ca{ca}.csv"
            if not f.exists():
                continue
            a = np.loadtxt(f, delimiter=",")
            a = a[np.argsort(a[:, 0])]
            for tt in TIMES:
                if tt > a[-1, 0]:
                    continue
                ref = np.interp(tt, a[:, 0], a[:, 1])
                gaps = [f"{np.interp(tt, *runs[k]) - ref:+.3f}" if k in runs else "-"
                        for k in ("d16", "d32")]
                print(f"| {ca} | {src} | {tt:g} | {ref:.3f} | {gaps[0]} | {gaps[1]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
