"""Command line and run status (issue 23): usage errors exit 2 naming the bad word or key;
`efsi --version` prints the build commit; a run stopped by time.max_steps says so
("max_steps", exit 0); summary.json stores the commit, the rank count and the machine load;
a restart from a checkpoint at or after end_time is refused (exit 2) and writes nothing."""
import json
import os
import re
import subprocess

from efsi_harness import check, parse_args, run, tg_grid

args = parse_args()


def efsi(*words):
    return subprocess.run([args.efsi, *words], capture_output=True, text=True, timeout=60)


# Usage errors: exit 2, one message naming what is wrong.
for words, named in ((["frobnicate"], "frobnicate"),
                     (["run"], "case"),
                     (["check", os.path.join(args.cases, "couette"), "--bogus"], "--bogus"),
                     (["check", os.path.join(args.cases, "couette"), "--set", "body[x].radius=1"],
                      "body[x]"),
                     (["check", os.path.join(args.cases, "couette"), "--set", "grid.cells"],
                      "grid.cells"),
                     (["check", os.path.join(args.cases, "couette"), "--set", "body[0].radius=1"],
                      "body"),
                     (["check", os.path.join(args.cases, "couette"), "--set",
                       "body[99999999999999999999].radius=1"], "body[99999999999999999999]")):
    p = efsi(*words)
    check(p.returncode == 2 and named in p.stderr and "stoul" not in p.stderr,
          f"efsi {' '.join(words[:1] + words[2:])}: exit {p.returncode}, {p.stderr.strip()[:160]}")
p = efsi("--help")
check(p.returncode == 0 and "run" in p.stdout, "efsi --help exits 0")

# --version: the commit the build was made from (40 hex digits, maybe -dirty).
p = efsi("--version")
m = re.search(r"commit ([0-9a-f]{40}(-dirty)?|unknown)", p.stdout)
check(p.returncode == 0 and m is not None, f"efsi --version: {p.stdout.strip()}")
commit = m.group(1)

# A run stopped by time.max_steps: status max_steps, exit 0, the log says so.
sets = tg_grid(16) + ["time.end_time=1.0", "output.fields=false"]
out = os.path.join(args.output, "capped")
cmd = [args.efsi, "run", os.path.join(args.cases, "taylor_green"), "--output", out]
for s in sets + ["time.max_steps=3"]:
    cmd += ["--set", s]
p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
with open(os.path.join(out, "summary.json")) as f:
    s = json.load(f)
check(p.returncode == 0 and s["status"] == "max_steps" and s["final_step"] == 3,
      f"max_steps run: exit {p.returncode}, status {s['status']}, step {s['final_step']}")
check("time.max_steps" in p.stdout and "time.max_steps" in s["message"],
      f"max_steps named in the log and summary: {s['message']}")
check(s["efsi_commit"] == commit and s["ranks"] == 1, f"summary commit {s['efsi_commit']}")
check(len(s["load_before"]) == 3 and len(s["load_after"]) == 3,
      f"summary load before {s['load_before']} after {s['load_after']}")

# A run to its end is "completed".
out = os.path.join(args.output, "full")
run(args, "taylor_green", out, sets=tg_grid(16) + ["time.end_time=0.05", "output.fields=false"])
with open(os.path.join(out, "summary.json")) as f:
    check(json.load(f)["status"] == "completed", "a run to end_time is completed")

# A restart from a checkpoint at end_time: exit 2, nothing written, the summary kept.
with open(os.path.join(out, "summary.json")) as f:
    before = f.read()
listing = sorted(os.listdir(out))
p = run(args, "taylor_green", out, sets=tg_grid(16) + ["time.end_time=0.05",
                                                       "output.fields=false"],
        extra=["--restart", os.path.join(out, "checkpoint.h5")], expect=2)
check("end_time" in p.stderr, f"restart at end_time refused: {p.stderr.strip()[:200]}")
with open(os.path.join(out, "summary.json")) as f:
    check(f.read() == before and sorted(os.listdir(out)) == listing,
          "the refused restart wrote nothing (summary unchanged)")
other = os.path.join(args.output, "elsewhere")
p = run(args, "taylor_green", other, sets=tg_grid(16) + ["time.end_time=0.01",
                                                         "output.fields=false"],
        extra=["--restart", os.path.join(out, "checkpoint.h5")], expect=2)
check(not os.path.exists(other), "a restart past end_time into a new folder creates nothing")
