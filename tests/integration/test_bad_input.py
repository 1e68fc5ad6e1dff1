"""Bad input stops before anything is allocated, with exit code 2 and the key named:
`efsi check` of a case with an unknown key, a 64 x 64 case on 3 ranks, and a membrane case
whose blocks are too thin for the surface velocity of its Gs."""
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

# A membrane whose Gs is carried by the surface velocity reads u up to 8 cells away, so
# every rank's block must be at least 8 cells wide: 16 cells over 4 ranks along y is not.
out = os.path.join(args.output, "thin_blocks")
proc = run(args, "body_translation", out, ranks=4, expect=None,
           sets=["grid.cells=[32,16,1]", "grid.length=[2.0,1.0,0.0625]", "parallel.ranks=[1,4,1]"])
check(proc.returncode == 2, f"thin blocks exit {proc.returncode}")
check("strain_extension" in proc.stderr and "10 cells wide" in proc.stderr,
      f"message: {proc.stderr.strip()[:200]}")
check(not os.path.exists(out), "nothing was written (checked before the run)")

# With the layered extension, the surface velocity's halo decides: ceil(reach) + 3 layers,
# 8 for the default reach and 5 for 1.5, still more than 4-cell blocks.
out = os.path.join(args.output, "thin_blocks_layers")
proc = run(args, "body_translation", out, ranks=4, expect=None,
           sets=["grid.cells=[32,16,1]", "grid.length=[2.0,1.0,0.0625]", "parallel.ranks=[1,4,1]",
                 "body[2].strain_model=\"tensor\"", "body[2].strain_extension=\"layers\""])
check(proc.returncode == 2 and "strain_velocity" in proc.stderr and "8 cells wide" in proc.stderr,
      f"layers: exit {proc.returncode}, message: {proc.stderr.strip()[:200]}")
out = os.path.join(args.output, "thin_blocks_short_reach")
proc = run(args, "body_translation", out, ranks=4, expect=None,
           sets=["grid.cells=[32,16,1]", "grid.length=[2.0,1.0,0.0625]", "parallel.ranks=[1,4,1]",
                 "body[2].surface_velocity_reach=1.5", "body[2].strain_model=\"tensor\"", "body[2].strain_extension=\"layers\""])
check(proc.returncode == 2 and "5 cells wide" in proc.stderr,
      f"short reach: exit {proc.returncode}, message: {proc.stderr.strip()[:200]}")

# Out of its range [1, 8] the reach is refused by name.
proc = run(args, "body_translation", command="check", expect=2,
           sets=["body[2].surface_velocity_reach=0.5"])
check("surface_velocity_reach" in proc.stderr, f"reach 0.5: {proc.stderr.strip()[:200]}")
