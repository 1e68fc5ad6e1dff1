"""Bad input stops before anything is allocated, with exit code 2 and the key named:
`efsi check` of a case with an unknown key, and a 64 x 64 case on 3 ranks."""
import os

from efsi_harness import check, parse_args, run

args = parse_args()
case = os.path.join(args.output, "typo")
os.makedirs(case)
with open(os.path.join(args.cases, "lid_cavity", "case.toml")) as f:
    text = f.read()
with open(os.path.join(case, "case.toml"), "w") as f:
    f.write(text.replace("viscosity = 0.01", "viscosity = 0.01\nviscossity = 0.01"))
proc = run(args, case, command="check", expect=2)
check("fluid.viscossity" in proc.stderr, f"unknown key named: {proc.stderr.strip()}")

proc = run(args, "lid_cavity", command="check")
check("is valid" in proc.stdout, "a good case passes efsi check")

out = os.path.join(args.output, "three_ranks")
proc = run(args, "lid_cavity", out, ranks=3, expect=None)
check(proc.returncode != 0, f"3 ranks on 64x64 exits {proc.returncode}")
check("cannot be divided" in proc.stderr, f"message: {proc.stderr.strip()[:200]}")
check(not os.path.exists(out), "nothing was written (checked before allocating)")
