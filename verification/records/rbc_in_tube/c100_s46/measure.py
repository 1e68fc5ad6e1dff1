"""The red cell of cases/rbc_in_tube with a stiff-area Skalak membrane (C = 100, the case's
C = 10 otherwise; issue 20: "C = 100 must run") against the case's own run over the same
time: per run the time reached and status, the largest area change |A / A(0) - 1|, the
largest stored-strain drift |A_ref / A - 1|, max tr Gs, the volume drift, the steps and the
cell's velocity (its centroid's, least squares over the second half). Writes result.md here
(the row A_ref / A_ref(0) - 1, the reference area's own change, was added in session 47, after
this record's result.md was made).

    /usr/bin/python3 verification/records/rbc_in_tube/c100_s46/measure.py C100_RUN C10_RUN
"""
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2] / "studies"))
from _flowio import body_series  # noqa: E402 (the studies' reader of bodies.csv)
TUBE_LENGTH = 24.0  # um (cases/rbc_in_tube)


def measure(out: Path, t_max: float) -> dict:
    keys = ("centroid_x", "volume", "area", "reference_area", "tensor_trace_max")
    t, *values = body_series(out, "rbc", keys)
    keep = t <= t_max + 1e-9
    t = t[keep]
    c = {k: v[keep] for k, v in zip(keys, values)}
    x = np.unwrap(c["centroid_x"], period=TUBE_LENGTH)
    half = t >= 0.5 * t[-1]
    s = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else {}
    return {"t reached [ms]": float(t[-1]), "status of the whole run": f"{s.get('status', '-')} at {s.get('time', '-')} ms",
            "area change max": float(np.max(np.abs(c["area"] / c["area"][0] - 1))),
            "A_ref / A - 1, max": float(np.max(np.abs(c["reference_area"] / c["area"] - 1))),
            "A_ref / A_ref(0) - 1, max": float(np.max(np.abs(c["reference_area"]
                                                           / c["reference_area"][0] - 1))),
            "max tr Gs": float(c["tensor_trace_max"].max()),
            "volume drift": float(abs(c["volume"][-1] / c["volume"][0] - 1)),
            "cell velocity [um/ms]": float(np.polyfit(t[half], x[half], 1)[0])}


def report(c100: Path, c10: Path, t_max: float, out: Path, title: str) -> str:
    """The table of both runs up to t_max (the C = 100 run's time reached), into out."""
    a = measure(c100, t_max)
    b = measure(c10, a["t reached [ms]"])
    lines = [f"# {title}", "",
             "Made by `measure.py` (this folder); the C = 10 column is the blood_capillary study's",
             "full-tier tube run (the case as it is) up to the same time.", "",
             "| quantity | C = 100 | C = 10 (the case) |", "|---|---|---|"]
    for k in a:
        fa, fb = a[k], b[k]
        f = (lambda v: f"{v:.4g}") if not isinstance(fa, str) else str
        lines.append(f"| {k} | {f(fa)} | {f(fb) if not isinstance(fb, str) else fb} |")
    text = "\n".join(lines) + "\n"
    (out / "result.md").write_text(text)
    return text


if __name__ == "__main__":
    print(report(Path(sys.argv[1]), Path(sys.argv[2]), 1.0, HERE,
                 "A red cell with C = 100 in the 10 um tube (session 46)"), end="")
