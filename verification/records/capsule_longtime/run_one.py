"""Make one of capsule_longtime's runs alone, on N ranks, into the study's own cache folder
(build/verification/capsule_longtime/runs/<tag>_t<end>), resuming from its checkpoint when
it has one; the study (run.py capsule_longtime --tier full) then takes it as made. For the
runs too long to make with the rest of the tier in one session, e.g. d/32 Skalak C = 10
(44 800 steps: about 2-2.5 h on 2 ranks here, session 54):

    /usr/bin/python3 verification/records/capsule_longtime/run_one.py --cells 32 --ca 0.025 \\
        --law skalak --c 10 --end 10 --ranks 2

then record it (verification/record.py, as <tag>_t<end>_foot) and assemble the study with
EFSI_VERIFY_RECORDS=only. The keys are the study's run_sets, nothing added."""
import argparse
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "verification" / "studies"))
from capsule_longtime import run_sets, tag  # noqa: E402

p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
p.add_argument("--cells", type=int, required=True, help="cells per diameter (8, 16, 32)")
p.add_argument("--ca", type=float, required=True)
p.add_argument("--law", default="neo_hookean", help='"neo_hookean" or "skalak"')
p.add_argument("--c", type=float, default=None, help="Skalak area dilation C")
p.add_argument("--eb", type=float, default=0.0, help="bending Eb / (a^2 Es)")
p.add_argument("--end", type=float, required=True, help="shear-rate x t to reach")
p.add_argument("--ranks", type=int, default=1)
a = p.parse_args()
out = REPO / "build" / "verification" / "capsule_longtime" / "runs" / \
    f"{tag(a.ca, a.cells, a.law, a.c, a.eb)}_t{a.end:g}"
out.mkdir(parents=True, exist_ok=True)
cmd = ["mpirun", "-np", str(a.ranks), str(REPO / "build" / "bin" / "efsi"), "run",
       str(REPO / "cases" / "capsule_shear"), "--output", str(out)]
for k, v in run_sets(a.cells, a.ca, a.end, a.law, a.c, a.eb).items():
    cmd += ["--set", f"{k}={v}"]
if (out / "checkpoint.h5").exists():
    cmd += ["--restart", str(out / "checkpoint.h5")]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
if a.ranks > 2:
    cmd.insert(1, "--oversubscribe")
print(" ".join(cmd), flush=True)
sys.exit(subprocess.run(cmd, env=env).returncode)
