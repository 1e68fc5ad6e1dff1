"""Faults lose nothing (issue 23, item 5), on a 32 x 32 Taylor-Green run:
(a) kill -9 while checkpoints are written (seeded, several times, many of them inside a
    checkpoint write): the previous checkpoint stays readable, and a restart from it ends bit
    for bit where the uninterrupted run ends;
(b) a restart on another rank count (2 -> 1, 1 -> 2) ends equal to 1e-12;
(c) a full disk (a file-size limit, ulimit -f, with SIGXFSZ ignored so writes fail with
    EFBIG) while checkpointing and while writing snapshots, on 1 and 2 ranks: exit 3, a
    message naming the last good checkpoint, status "io_error", no tmp or partial file, the
    last good checkpoint unchanged and still a good restart;
(d) a flipped bit, a zeroed dataset, a changed attribute, a truncated file, a file that is
    not a checkpoint, a checkpoint of another case on the same grid (lid cavity into
    Taylor-Green), and bodies into a case without them (and back) are each refused with a
    message, exit 2, nothing written."""
import hashlib
import json
import os
import random
import resource
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np

from efsi_harness import check, datasets, parse_args, run, tg_grid

args = parse_args()
rng = random.Random(23)
CASE = "taylor_green"
BASE = tg_grid(32) + ["time.end_time=1.0", "output.fields=false"]
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_mpi_yield_when_idle="1")


def command(out, sets, extra=(), ranks=1):
    cmd = [] if ranks == 1 else [args.mpiexec, "-np", str(ranks), "--oversubscribe"]
    cmd += [args.efsi, "run", os.path.join(args.cases, CASE), "--output", out, "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    return cmd + list(extra)


def same(a, b, what, rel=0.0):
    check(sorted(a) == sorted(b), f"{what}: same datasets and attributes")
    for k in a:
        x, y = np.asarray(a[k]), np.asarray(b[k])
        if x.dtype.kind in "fiu":
            x, y = x.astype(float), y.astype(float)
            err = np.abs(x - y).max() / max(np.abs(x).max(), 1e-300) if x.size else 0.0
            if (rel == 0.0 and not np.array_equal(x, y)) or err > rel:
                check(False, f"{what}: {k} differs ({err:.3e} relative)")
        elif rel == 0.0 and not np.array_equal(x, y):
            check(False, f"{what}: {k} differs")
    check(True, f"{what}: {len(a)} datasets and attributes agree"
          + (" bit for bit" if rel == 0.0 else f" to {rel:g}"))


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def leftovers(folder):
    return [os.path.join(r, n) for r, _, names in os.walk(folder) for n in names
            if n.endswith(".tmp")]


# The uninterrupted runs (checkpoints at every step: most of the run is checkpoint writing).
ref = os.path.join(args.output, "reference")
sets_every = BASE + ["output.checkpoint_every=1"]
t0 = time.time()
run(args, CASE, ref, sets=sets_every)
wall = time.time() - t0
reference = datasets(os.path.join(ref, "checkpoint.h5"))
nsteps = int(reference["@step"])
check(nsteps >= 8, f"reference: {nsteps} steps in {wall:.2f} s")

# (a) kill -9 at random moments, several times (seeded); half of them the moment a
# checkpoint's tmp file appears (plus a random delay of up to 2 ms): inside a write.
kills, inside = 0, 0
for trial in range(6):
    out = os.path.join(args.output, f"kill_{trial}")
    tmp = os.path.join(out, "checkpoint.h5.tmp")
    proc = subprocess.Popen(command(out, sets_every), env=ENV, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    if trial % 2 == 0:
        # wait for the k-th checkpoint write to begin
        k, seen, deadline = rng.randint(2, max(2, nsteps - 3)), 0, time.time() + 60
        was = False
        while proc.poll() is None and time.time() < deadline:
            now = os.path.exists(tmp)
            if now and not was:
                seen += 1
                if seen >= k:
                    break
            was = now
            time.sleep(0.0002)
        time.sleep(rng.uniform(0, 0.002))
    else:
        time.sleep(rng.uniform(0.5, 0.95) * wall)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    if proc.returncode != -signal.SIGKILL:
        # a machine faster than at the reference run: it finished first, as it should
        check(proc.returncode == 0, f"kill {trial}: the run ended before the kill (exit "
              f"{proc.returncode})")
        same(reference, datasets(os.path.join(out, "checkpoint.h5")),
             f"kill {trial}: finished before the kill")
        continue
    kills += 1
    inside += os.path.exists(tmp)
    good = os.path.join(out, "checkpoint.h5")
    if not os.path.exists(good):
        check(True, f"kill {trial}: killed before the first checkpoint; nothing to check")
        continue
    got = datasets(good)  # readable, every dataset
    check(0 < int(got["@step"]) <= nsteps,
          f"kill {trial}: the last checkpoint (step {int(got['@step'])}) is readable"
          f"{' (killed inside a checkpoint write)' if os.path.exists(tmp) else ''}")
    if int(got["@step"]) == nsteps:
        # killed after the last checkpoint was published: nothing left to run (a restart
        # would be refused as at end_time); the checkpoint itself must be the final state
        same(reference, got, f"kill {trial}: killed after the final checkpoint")
        continue
    run(args, CASE, out, sets=sets_every, extra=["--restart", good])
    same(reference, datasets(good), f"kill {trial}: restart from step {int(got['@step'])}")
check(inside >= 1, f"{inside} of {kills} kills hit a checkpoint write in progress")

# (b) restart on another rank count: 2 -> 1 and 1 -> 2, equal to 1e-12.
ref1 = os.path.join(args.output, "reference_plain")
run(args, CASE, ref1, sets=BASE)
plain = datasets(os.path.join(ref1, "checkpoint.h5"))
for first, second in ((2, 1), (1, 2)):
    out = os.path.join(args.output, f"ranks_{first}_{second}")
    run(args, CASE, out, ranks=first, sets=BASE + ["time.max_steps=4"])
    run(args, CASE, out, ranks=second, sets=BASE,
        extra=["--restart", os.path.join(out, "checkpoint.h5")])
    same(plain, datasets(os.path.join(out, "checkpoint.h5")),
         f"checkpoint of {first} rank(s) continued on {second}", rel=1e-12)


# (c) a full disk: a file-size limit below one checkpoint (or one snapshot).
# PMIx keeps its data store in files, which the limit would break: its hash store instead.
LIMITED_ENV = dict(ENV, PMIX_MCA_gds="hash")


def limited(limit):
    def pre():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return pre


first = os.path.join(args.output, "disk_first_part")
run(args, CASE, first, sets=BASE + ["time.max_steps=4"])
size = os.path.getsize(os.path.join(first, "checkpoint.h5"))
for ranks in (1, 2):
    out = os.path.join(args.output, f"disk_full_np{ranks}")
    shutil.copytree(first, out)
    good = os.path.join(out, "checkpoint.h5")
    before = digest(good)
    proc = subprocess.run(command(out, BASE + ["output.checkpoint_every=2"],
                                  ["--restart", good], ranks), env=LIMITED_ENV, capture_output=True,
                          text=True, timeout=300, preexec_fn=limited(size // 2),
                          restore_signals=False)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    check(proc.returncode == 3, f"np{ranks} disk full while checkpointing: exit {proc.returncode}"
          f" ({proc.stderr.strip()[:300]})")
    check(summary["status"] == "io_error" and good in proc.stderr and "last good" in proc.stderr,
          f"np{ranks}: status {summary['status']}, message names the last good checkpoint")
    ours = [line for line in proc.stderr.splitlines() if line.startswith("efsi:")]
    check(len(ours) == 1 and "HDF5-DIAG" not in proc.stderr,
          f"np{ranks}: one message, no HDF5 error stacks")
    check(digest(good) == before and not leftovers(out),
          f"np{ranks}: the last good checkpoint is unchanged, no tmp file left")
    run(args, CASE, out, ranks=ranks, sets=BASE, extra=["--restart", good])
    same(plain, datasets(good), f"np{ranks}: restart from the kept checkpoint after the full disk",
         rel=1e-12)

    # snapshots: the first write already fails (limit below a snapshot's size)
    out = os.path.join(args.output, f"disk_full_fields_np{ranks}")
    proc = subprocess.run(command(out, tg_grid(32) + ["time.end_time=0.5"], ranks=ranks),
                          env=LIMITED_ENV, capture_output=True, text=True, timeout=300,
                          preexec_fn=limited(16 * 1024), restore_signals=False)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    published = [n for n in os.listdir(os.path.join(out, "fields")) if n.endswith(".h5")]
    check(proc.returncode == 3 and summary["status"] == "io_error" and "snapshot" in proc.stderr,
          f"np{ranks} disk full while writing snapshots: exit {proc.returncode}, status "
          f"{summary['status']}: {proc.stderr.strip()[:200]}")
    check(not leftovers(out) and not published,
          f"np{ranks}: no tmp and no partial snapshot left ({published})")

# (c') a really full disk, when a small tmpfs can be mounted (root, and a kernel that lets
# this container mount): snapshots and checkpoints fill 300 kB until one does not fit.
mnt = os.path.join(args.output, "tmpfs")
os.makedirs(mnt)
mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=300k", "tmpfs", mnt],
                         capture_output=True).returncode == 0
if not mounted:
    print("skipped: a full tmpfs (cannot mount one here); the file-size limit stands in")
else:
    try:
        out = os.path.join(mnt, "run")
        proc = subprocess.run(command(out, tg_grid(32) + ["time.end_time=1.0",
                                                         "output.fields_interval=0.05",
                                                         "output.checkpoint_every=2"]),
                              env=ENV, capture_output=True, text=True, timeout=300)
        with open(os.path.join(out, "summary.json")) as f:
            status = json.load(f)["status"]
        check(proc.returncode == 3 and status == "io_error" and "No space left" in proc.stderr
              and not leftovers(out),
              f"full tmpfs: exit {proc.returncode}, status {status}, no tmp file: "
              f"{proc.stderr.strip()[:200]}")
    finally:
        subprocess.run(["umount", mnt])

# (d) corrupted and foreign checkpoints are refused with a message; nothing is written.
src = os.path.join(first, "checkpoint.h5")
bad_dir = os.path.join(args.output, "bad")
os.makedirs(bad_dir)


def corrupt(name, change):
    path = os.path.join(bad_dir, name + ".h5")
    shutil.copy(src, path)
    change(path)
    return path


def flip_bit(path):
    with h5py.File(path, "r+") as f:
        a = f["pressure"][()]
        bits = a.view(np.uint64)
        bits[0, 7, 11] ^= np.uint64(1 << 17)
        f["pressure"][...] = a


def zero(path):
    with h5py.File(path, "r+") as f:
        f["velocity_u"][...] = 0.0


def nudge_time(path):
    with h5py.File(path, "r+") as f:
        f.attrs["time"] = np.nextafter(f.attrs["time"], 1.0)


def truncate(path):
    with open(path, "r+b") as f:
        f.truncate(os.path.getsize(path) * 6 // 10)


bad = {"flipped bit": (corrupt("flip", flip_bit), "checksum"),
       "zeroed dataset": (corrupt("zero", zero), "checksum"),
       "changed time attribute": (corrupt("time", nudge_time), "checksum"),
       "truncated file": (corrupt("trunc", truncate), "--restart"),
       "not a checkpoint": (os.path.join(ref, "diagnostics.csv"), "--restart"),
       "a folder": (bad_dir, "not a regular file")}

# another case on the same grid: the lid cavity into Taylor-Green
lid = os.path.join(args.output, "lid")
run(args, "lid_cavity", lid, sets=BASE + ["time.max_steps=2"])
bad["lid cavity into Taylor-Green"] = (os.path.join(lid, "checkpoint.h5"), "boundary")

# bodies into a case without them: Taylor-Green with a passive disc
with open(os.path.join(args.cases, CASE, "case.toml")) as f:
    text = f.read()
body_case = os.path.join(args.output, "tg_with_body")
os.makedirs(body_case)
with open(os.path.join(body_case, "case.toml"), "w") as f:
    f.write(text + '\n[[body]]\nname = "disc"\nshape = "cylinder"\ncentre = [3.0, 3.0, 0.0]\n'
            'radius = 0.8\n')
body_out = os.path.join(args.output, "with_body")
run(args, body_case, body_out, sets=BASE + ["time.max_steps=2"])
bad["bodies into a bodyless case"] = (os.path.join(body_out, "checkpoint.h5"), "body")

for what, (path, word) in bad.items():
    out = os.path.join(args.output, "refused_" + what.replace(" ", "_"))
    p = run(args, CASE, out, sets=BASE, extra=["--restart", path], expect=None)
    check(p.returncode == 2 and word in p.stderr and not os.path.exists(out),
          f"{what}: exit {p.returncode}, nothing written: {p.stderr.strip()[:220]}")

out = os.path.join(args.output, "refused_bodyless_into_bodies")
p = run(args, body_case, out, sets=BASE, extra=["--restart", src], expect=None)
check(p.returncode == 2 and "body" in p.stderr and not os.path.exists(out),
      f"a bodyless checkpoint into a case with bodies: exit {p.returncode}: "
      f"{p.stderr.strip()[:220]}")
