"""The survey of survey.py on any case (the red cells of rbc_in_tube, say): a fixed time.dt =
F x the case's automatic step (as `efsi check` prints it) from t = 0 to END, one run per F,
one rank. Prints per run the exit code, the time reached and, per membrane body, D, the
largest tr Gs and the largest relative area change.

    /usr/bin/python3 verification/records/capsule_longtime/dt_margin_s58/survey_case.py \\
        rbc_in_tube --end 1 --set body[1].area_dilation=100.0 -- 1 2 4 8

Runs go to /tmp/dts58_<case>[_<tag>]_F<F>."""
import argparse
import csv
import os
import re
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[4]
# EFSI_BIN: a copy of the binary, so that a rebuild during a survey leaves it alone.
EFSI = os.environ.get("EFSI_BIN", str(REPO / "build" / "bin" / "efsi"))


def automatic_step(case: str, args: list[str]) -> tuple[float, str]:
    """The case's automatic step as `efsi check` prints it, and what binds it."""
    check = subprocess.run([EFSI, "check", case, *args, "--ranks", "1"], capture_output=True,
                           text=True, check=True).stdout
    m = re.search(r"#   step ([0-9.e+-]+) \(([^)]*)\)", check)
    return float(m.group(1)), m.group(2)


def run_fixed(case: str, out: Path, args: list[str], dt: float, extra: list[str]):
    """One run at the fixed step dt into out (emptied first): its exit code, its bodies.csv
    rows and the last line it wrote to stderr."""
    subprocess.run(["rm", "-rf", str(out)], check=True)
    r = subprocess.run([EFSI, "run", case, "-o", str(out), "-q", *args,
                        "--set", f"time.dt={dt!r}", *extra,
                        "--set", "output.checkpoint_every=100000",
                        "--set", "output.diagnostics_every=10"], capture_output=True, text=True)
    rows = list(csv.DictReader(open(out / "bodies.csv"))) if (out / "bodies.csv").exists() else []
    err = r.stderr.strip().splitlines()
    return r.returncode, rows, err[-1] if err else ""


def main():
    p = argparse.ArgumentParser()
    p.add_argument("case")
    p.add_argument("--end", type=float, required=True)
    p.add_argument("--tag", default="")
    p.add_argument("--set", action="append", default=[])
    p.add_argument("factors", type=float, nargs="+")
    a = p.parse_args()

    case = str(REPO / "cases" / a.case)
    name = a.case + (f"_{a.tag}" if a.tag else "")
    args = ["--set", f"time.end_time={a.end!r}"]
    for s in a.set:
        args += ["--set", s]
    dt_auto, binding = automatic_step(case, args)
    print(f"{name} dt_auto {dt_auto!r} (binding: {binding})", flush=True)
    for f in a.factors:
        out = Path(f"/tmp/dts58_{name}_F{f:g}")
        rc, rows, err = run_fixed(case, out, args, f * dt_auto, ["--set", "output.fields=false"])
        t = max((float(x["time"]) for x in rows), default=0.0)
        line = f"{name} F={f:g} rc={rc} t={t:.4f}"
        for body in dict.fromkeys(x["body"] for x in rows):
            b = [x for x in rows if x["body"] == body]
            if b[0].get("taylor_deformation", "") in ("", "nan") or "tensor_trace_max" not in b[0]:
                continue
            tr = max(float(x["tensor_trace_max"]) for x in b)
            area = max(abs(float(x["area"]) / float(b[0]["area"]) - 1) for x in b)
            line += (f" | {body}: D={float(b[-1]['taylor_deformation']):.6f} max_trGs={tr:.4f}"
                     f" max_area_change={area:.5f}")
        print(line + (f" | {err[:160]}" if err else ""), flush=True)


if __name__ == "__main__":
    main()
