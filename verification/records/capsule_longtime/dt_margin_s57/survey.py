"""How far the automatic step of a membrane capsule is from the explicit membrane force's
stability limit: capsule_longtime's d/16 capsule at Ca 0.025 with a fixed time.dt = F x the
automatic step (the membrane limit times time.cfl), from t = 0 to shear-rate x t = END, one run
per F, one rank. Prints, per run, the exit code, the time reached, D and the largest tr Gs.

    /usr/bin/python3 verification/records/capsule_longtime/dt_margin_s57/survey.py 0.5 \\
        sk_C10_ca0.025 1 4 6 8 16 32

(configurations: nh_ca0.025, sk_C10_ca0.025, sk_C100_ca0.025; runs go to /tmp/dts_<name>_F<F>)."""
import csv
import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[4]
sys.path.insert(0, str(REPO / "verification" / "studies"))
from capsule_longtime import run_sets  # noqa: E402

EFSI = str(REPO / "build" / "bin" / "efsi")
CASE = str(REPO / "cases" / "capsule_shear")
CONFIGS = {"nh_ca0.025": ("neo_hookean", None), "sk_C10_ca0.025": ("skalak", 10.0),
           "sk_C100_ca0.025": ("skalak", 100.0)}

end, name, factors = float(sys.argv[1]), sys.argv[2], [float(x) for x in sys.argv[3:]]
law, c = CONFIGS[name]
args = []
for k, v in run_sets(16, 0.025, end, law, c, 0.0).items():
    args += ["--set", f"{k}={v}"]
check = subprocess.run([EFSI, "check", CASE, *args, "--ranks", "1"], capture_output=True,
                       text=True, check=True).stdout
dt_auto = float(re.search(r"#   step ([0-9.e+-]+) \(", check).group(1))
print(name, "dt_auto", dt_auto, flush=True)
for f in factors:
    out = Path(f"/tmp/dts_{name}_F{f:g}")
    subprocess.run(["rm", "-rf", str(out)], check=True)
    r = subprocess.run([EFSI, "run", CASE, "-o", str(out), "-q", *args,
                        "--set", f"time.dt={f * dt_auto!r}",
                        "--set", "output.checkpoint_every=100000",
                        "--set", "output.diagnostics_every=10"], capture_output=True, text=True)
    rows = list(csv.DictReader(open(out / "bodies.csv"))) if (out / "bodies.csv").exists() else []
    d = float(rows[-1]["taylor_deformation"]) if rows else float("nan")
    tr = max(float(x["tensor_trace_max"]) for x in rows) if rows else float("nan")
    t = float(rows[-1]["time"]) if rows else 0.0
    print(f"{name} F={f:g} rc={r.returncode} t={t:.4f} D={d:.6f} max_trGs={tr:.4f} "
          f"{r.stderr.strip()[:140]}", flush=True)
