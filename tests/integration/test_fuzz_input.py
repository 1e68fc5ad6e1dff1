"""Bad input, fuzzed (issue 23, item 3). A seeded generator mutates the case files of cases/
and the --set and command-line arguments: wrong types, missing and unknown keys, non-finite,
negative, huge and out-of-range numbers, integers beyond their type, grids that do not divide
among the ranks or cannot be allocated, bodies outside the box, truncated and garbage TOML,
folders and devices instead of files, names and paths that escape the output folder, and
wrong mask files. For every input efsi must: exit 2, print one message (one line starting
with "efsi:") that names the key (or the file / word), write nothing, not crash, not hang
(timeout) and stay within bounded memory (ulimit -v). Most inputs go through `efsi check`
(validation only, milliseconds); one in eight through `efsi run --output DIR`, which must not
create DIR. Prints the number of inputs tried and failed; any failure fails the test."""
import os
import random
import re
import resource
import subprocess
import sys
import tomllib
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

from efsi_harness import parse_args

args = parse_args()
args.efsi, args.cases = os.path.abspath(args.efsi), os.path.abspath(args.cases)
rng = random.Random(20231123)
# The debug preset's sanitizers (ASan reserves terabytes of address space, so no ulimit -v
# there, and no leak report: MPI's own allocations at exit are not ours) and fewer inputs.
SANITIZED = b"__asan_init" in open(args.efsi, "rb").read()
N_MUTATIONS = int(os.environ.get("EFSI_FUZZ_COUNT", "60" if SANITIZED else "240"))
MEMORY = 4 << 30  # ulimit -v per efsi process
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_mpi_yield_when_idle="1", OMPI_MCA_ess_singleton_isolated="1")
if SANITIZED:
    ENV["ASAN_OPTIONS"] = "detect_leaks=0"


def limits():
    if not SANITIZED:
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


# ---- the keys, their types and ranges, from `efsi keys` -------------------------------
table = subprocess.run([args.efsi, "keys"], capture_output=True, text=True, env=ENV,
                       timeout=60).stdout
KEYS = {}
for line in table.splitlines():
    m = re.match(r"\| `([^`]+)` \| ([^|]+) \| [^|]+ \| ([^|]+) \| ([^|]+) \|", line)
    if m and not m.group(2).strip().startswith("array"):
        KEYS[m.group(1)] = (m.group(2).strip(), m.group(3).strip(), m.group(4).strip())

CASES = sorted(d for d in os.listdir(args.cases)
               if os.path.exists(os.path.join(args.cases, d, "case.toml")))
TEXT = {c: open(os.path.join(args.cases, c, "case.toml")).read() for c in CASES}
PARSED = {c: tomllib.loads(TEXT[c]) for c in CASES}
BODY_CASES = [c for c in CASES if PARSED[c].get("body")]


def out_of_range(rng_text, integer):
    """Values outside a documented range such as '> 0', '>= 0', '[1, 64]', '(0, 1]'."""
    vals = []
    m = re.match(r"([\[(])(-?[\d.e+]+), (-?[\d.e+]+)\]", rng_text)
    if m:
        lo, hi = float(m.group(2)), float(m.group(3))
        vals += [lo - 1, hi + 1, hi * 10 + 7]
        if m.group(1) == "(":
            vals.append(lo)
    m = re.match(r"(>=?) (-?[\d.e+]+)", rng_text)
    if m:
        lo = float(m.group(2))
        vals += [lo - 1, -1e30] + ([lo] if m.group(1) == ">" else [])
    if integer:
        vals = [int(v) for v in vals if abs(v) < 1e18 and float(int(v)) == v]
    return vals


def bad_values(key, kind, rng_text):
    """(value, why) that must be refused for a key of this type and range."""
    v = []
    if kind == "float":
        v += [("nan", "nan"), ("inf", "inf"), ("-inf", "-inf"), ('"1.0"', "string"),
              ("true", "bool"), ("[1.0, 2.0]", "array"), ("{a = 1}", "table")]
        v += [(repr(x), "out of range") for x in out_of_range(rng_text, False)]
    elif kind == "integer":
        v += [("1.5", "float"), ('"3"', "string"), ("true", "bool"), ("nan", "nan"),
              ("2147483648", "beyond int"), ("9223372036854775807", "beyond int"),
              ("99999999999999999999", "beyond int64"), ("[1]", "array")]
        v += [(str(x), "out of range") for x in out_of_range(rng_text, True)]
    elif kind == "bool":
        v += [("1", "integer"), ('"yes"', "string"), ("0.0", "float")]
    elif kind == "string":
        v += [("3", "integer"), ("true", "bool"), ("[\"a\"]", "array")]
        if rng_text != "any":
            v += [('"nonsense"', "unknown choice"), ('""', "empty choice")]
    elif kind == "float[3]":
        v += [("[1.0, 2.0]", "2 elements"), ("[nan, 0.0, 0.0]", "nan"),
              ("[0.0, inf, 0.0]", "inf"), ('["a", 1.0, 2.0]', "string"), ("5.0", "scalar"),
              ("[1.0, 2.0, 3.0, 4.0]", "4 elements")]
        v += [(f"[{x!r}, {x!r}, {x!r}]", "out of range") for x in out_of_range(rng_text, False)]
    elif kind == "integer[3]":
        v += [("[1.5, 2, 1]", "float"), ("[4294967298, 4, 1]", "beyond int"),
              ("[4, 4]", "2 elements"), ('["4", 4, 1]', "string"), ("8", "scalar")]
        v += [(f"[{x}, {x}, 1]", "out of range") for x in out_of_range(rng_text, True)]
    return v


# ---- the inputs ------------------------------------------------------------------------
work = os.path.join(args.output, "inputs")
os.makedirs(work)
inputs = []  # (label, case path, sets, extra args, words the message must contain, ranks)


def add(label, case, sets=(), words=(), extra=(), ranks=1, command=None):
    inputs.append(dict(label=label, case=case, sets=list(sets), words=list(words),
                       extra=list(extra), ranks=ranks, command=command))


def write_case(name, text, binary=False):
    d = os.path.join(work, name)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "case.toml"), "wb" if binary else "w") as f:
        f.write(text)
    return d


# 1. --set of every key of a case (body keys on a case with bodies) to a bad value
candidates = []
for key, (kind, deflt, rng_text) in KEYS.items():
    if key.startswith("body[]."):
        case = rng.choice(BODY_CASES)
        k = key.replace("body[]", "body[0]")
    else:
        case, k = rng.choice(CASES), key
    leaf = k.split(".")[-1]
    for value, why in bad_values(k, kind, rng_text):
        candidates.append((f"--set {k}={value} ({why})", case, k, value, leaf))
rng.shuffle(candidates)
for label, case, k, value, leaf in candidates[:N_MUTATIONS]:
    add(label, os.path.join(args.cases, case), [f"{k}={value}"], [leaf])

# 2. unknown keys and sections, malformed --set
for case in rng.sample(CASES, 6):
    p = os.path.join(args.cases, case)
    add(f"{case}: unknown key", p, ["fluid.viscossity=0.1"], ["fluid.viscossity"])
    add(f"{case}: unknown section", p, ["solverr.x=1"], ["solverr"])
    add(f"{case}: --set without value", p, ["grid.cells"], ["grid.cells"])
    add(f"{case}: --set body[x]", p, ["body[x].radius=1"], ["body[x]"])
    add(f"{case}: --set body[99]", p, ["body[99].radius=1"], ["body"])
    add(f"{case}: --set into a value", p, ["fluid.density.x=1"], ["density"])
    add(f"{case}: --set empty key", p, ["=3"], ["--set"])

# 3. grids: not cubes, cannot be allocated, not divisible by the ranks, PFMG non power of 2
tg = os.path.join(args.cases, "taylor_green")
add("grid cells not cubes", tg, ["grid.cells=[64, 32, 1]"], ["grid"])
add("grid too large to allocate", tg,
    ["grid.cells=[1048576, 1048576, 1048576]", "grid.length=[1.0, 1.0, 1.0]"], ["grid.cells"])
add("grid too large (run)", tg, ["grid.cells=[65536, 65536, 65536]",
                                 "grid.length=[1.0, 1.0, 1.0]"], ["grid.cells"],
    command="run")
# PFMG needs a power of two along periodic directions (the FFT pressure solve does not).
add("periodic grid not a power of two for PFMG", tg,
    ["grid.cells=[48, 48, 1]", "grid.length=[1.0, 1.0, 0.0208333333333333333]",
     'solver.pressure.method="pcg_pfmg"'], ["grid.cells"])
add("grid of 1 cell", tg, ["grid.cells=[1, 64, 1]"], ["grid.cells"])
add("2D with walls in z", os.path.join(args.cases, "lid_cavity"), ["boundary.z_low=wall",
                                                                 "boundary.z_high=wall"],
    ["z_low"])
add("half periodic", os.path.join(args.cases, "lid_cavity"), ["boundary.x_low=periodic"],
    ["x_low"])
add("wall moving along its normal", os.path.join(args.cases, "lid_cavity"),
    ['boundary.y_high={type="wall", velocity=[0.0, 1.0, 0.0]}'], ["y_high"])
for ranks, sets in ((3, []), (3, ["parallel.ranks=[3, 1, 1]"]),
                    (2, ["parallel.ranks=[3, 1, 1]"])):
    add(f"{ranks} ranks on 64 x 64 {sets}", tg, sets, ["rank"], ranks=ranks, command="run")

# 4. bodies outside the box, through a wall, names that escape or clash
for case in BODY_CASES:
    p = os.path.join(args.cases, case)
    add(f"{case}: body far outside", p, ["body[0].centre=[100.0, 100.0, 0.0]"], ["centre"])
    add(f"{case}: body name escapes", p, ['body[0].name="../../etc"'], ["name"])
    add(f"{case}: body name with a slash", p, ['body[0].name="a/b"'], ["name"])
    add(f"{case}: body name empty", p, ['body[0].name=""'], ["name"])
    add(f"{case}: slab normal zero", p, ['body[0].shape="slab"', "body[0].thickness=0.1",
                                         "body[0].normal=[0.0, 0.0, 0.0]"], ["normal"])
    if PARSED[case]["body"][0].get("interface", "sharp") != "sharp":
        continue  # a mask needs a sharp interface, which is refused first
    add(f"{case}: mask without file", p, ['body[0].shape="mask"'], ["mask_file"])
    add(f"{case}: mask file missing", p, ['body[0].shape="mask"', 'body[0].mask_file="nope.h5"'],
        ["mask_file"])
    add(f"{case}: mask file is a folder", p, ['body[0].shape="mask"',
                                              f'body[0].mask_file="{work}"'], ["mask_file"])
lid = os.path.join(args.cases, "lid_cavity")
add("body through a wall", lid, ['body=[{name="b", shape="sphere", radius=0.2, '
                                 'centre=[0.05, 0.5, 0.0]}]'], ["wall"])
bt = os.path.join(args.cases, "body_translation")
add("two bodies with one name", bt, ['body[1].name="disc"'], ["twice"])

# 5. names and paths that escape the output folder
for name in ("../../escaped", "/tmp/abs", ".hidden", "a/b"):
    add(f"case.name {name!r} (run, default output)", tg, [f'case.name="{name}"'], ["case.name"],
        command="run-default")
add("--output is a file", tg, [], ["--output"],
    extra=["--output", os.path.join(args.cases, "taylor_green", "case.toml")], command="run-raw")

# 6. case files: truncated, garbage, duplicate tables, missing required keys, not files
for case in rng.sample(CASES, 8):
    text = TEXT[case]
    lines = text.splitlines()
    eq = [i for i, line in enumerate(lines) if "=" in line and not line.startswith("#")]
    i = rng.choice(eq)
    cut = "\n".join(lines[:i] + [lines[i].split("=")[0] + "= "])
    add(f"{case}: truncated mid-value", write_case(f"trunc_{case}", cut), words=["case.toml"])
    add(f"{case}: garbage bytes", write_case(f"garbage_{case}", bytes(
        rng.randrange(256) for _ in range(300)), binary=True), words=["case.toml"])
    add(f"{case}: duplicate table", write_case(f"dup_{case}", text + "\n[fluid]\ndensity = 2.0\n"),
        words=["case.toml"])
    add(f"{case}: unknown key in the file",
        write_case(f"unknown_{case}", text.replace("[fluid]", "[fluid]\ndensty = 1.0", 1)),
        words=["fluid.densty"])
    for key in ("end_time", "density", "cells"):
        kept = [line for line in lines if not re.match(rf"\s*{key}\s*=", line)]
        if len(kept) < len(lines):
            add(f"{case}: {key} removed", write_case(f"missing_{key}_{case}", "\n".join(kept)),
                words=[key])
add("empty case file", write_case("empty", ""), words=["grid.cells"])
os.makedirs(os.path.join(work, "folder_case", "case.toml"), exist_ok=True)
add("case.toml is a folder", os.path.join(work, "folder_case"), words=["regular file"])
add("case is a folder without case.toml", work, words=["no such case"])
add("case is /dev/zero", "/dev/zero", words=["/dev/zero"])
add("case is missing", os.path.join(work, "nothing_here"), words=["nothing_here"])
add("case file over 1 MB", write_case("huge", "# x\n" * 300000), words=["1 MB"])

# 7. wrong mask files (run: masks are read when the bodies are built)
mask_case = write_case("mask_case", TEXT["taylor_green"] + '\n[[body]]\nname = "m"\nshape = "mask"\n'
                       'mask_file = "mask.h5"\nmask_dataset = "cells"\n')
with h5py.File(os.path.join(mask_case, "mask.h5"), "w") as f:
    f["cells"] = np.zeros((1, 64, 32))
    f["nan"] = np.full((1, 64, 64), np.nan)
with open(os.path.join(mask_case, "text.h5"), "w") as f:
    f.write("not hdf5\n")
add("mask of the wrong shape", mask_case, words=["mask"], command="run")
add("mask with NaN", mask_case, ['body[0].mask_dataset="nan"'], words=["mask"], command="run")
add("mask dataset missing", mask_case, ['body[0].mask_dataset="none"'], words=["mask"],
    command="run")
add("mask file not HDF5", mask_case, ['body[0].mask_file="text.h5"'], words=["mask"],
    command="run")

# 8. command line: unknown words and options, missing arguments, bad restart files
add("unknown command", None, words=["frobnicate"], extra=["frobnicate"], command="raw")
add("unknown option", tg, words=["--bogus"], extra=["--bogus"])
add("option without value", tg, words=["--set"], extra=["--set"])
add("no command", None, words=["subcommand"], extra=[], command="raw")
add("restart file missing", tg, words=["--restart"], extra=["--restart", "/nonexistent.h5"],
    command="run")
add("restart is a folder", tg, words=["--restart"], extra=["--restart", work], command="run")
add("restart is not HDF5", tg, words=["--restart"],
    extra=["--restart", os.path.join(mask_case, "text.h5")], command="run")

# One in eight --set mutations also goes through `run`, which must write nothing.
for k, inp in enumerate(inputs):
    if inp["command"] is None and k % 8 == 3:
        inp["command"] = "run"


# ---- run them --------------------------------------------------------------------------
def attempt(k_inp):
    k, inp = k_inp
    out = os.path.join(args.output, "out", f"{k:04d}")
    cmd = [] if inp["ranks"] == 1 else [args.mpiexec, "-np", str(inp["ranks"]), "--oversubscribe"]
    cmd.append(args.efsi)
    cwd = None
    command = inp["command"] or "check"
    if command == "raw":
        cmd += inp["extra"]
    elif command == "run-default":
        cwd = os.path.join(args.output, "cwd", f"{k:04d}", "a", "b")
        os.makedirs(cwd)
        cmd += ["run", inp["case"], "--quiet"]
    elif command == "run-raw":
        cmd += ["run", inp["case"], "--quiet"] + inp["extra"]
    else:
        cmd += [command, inp["case"]]
        if command == "run":
            cmd += ["--output", out, "--quiet"]
        cmd += inp["extra"]
    for s in inp["sets"]:
        cmd += ["--set", s]
    problems = []
    # A session folder of its own: concurrent MPI singletons can collide in /tmp/ompi.*.
    tmp = os.path.join(args.output, "tmp", f"{k:04d}")
    os.makedirs(tmp)
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=60,
                           env=dict(ENV, TMPDIR=tmp, OMPI_MCA_orte_tmpdir_base=tmp),
                           preexec_fn=limits, cwd=cwd, errors="replace")
    except subprocess.TimeoutExpired:
        return inp, ["hang (timeout 60 s)"], ""
    ours = [line for line in p.stderr.splitlines() if line.startswith("efsi:")]
    if p.returncode != 2:
        problems.append(f"exit {p.returncode}")
    if len(ours) != 1:
        problems.append(f"{len(ours)} efsi: lines")
    missing = [w for w in inp["words"] if w not in p.stderr]
    if missing:
        problems.append(f"message does not name {missing}")
    if "runtime error:" in p.stderr or "Sanitizer" in p.stderr:
        problems.append("sanitizer report")
    if os.path.exists(out):
        problems.append("wrote the output folder")
    if cwd is not None:
        written = [os.path.join(r, n) for r, ds, fs in os.walk(os.path.join(args.output, "cwd",
                                                                             f"{k:04d}"))
                   for n in ds + fs if n not in ("a", "b")]
        if written:
            problems.append(f"wrote {written}")
    return inp, problems, p.stderr.strip()


with ThreadPoolExecutor(max_workers=2) as pool:
    results = list(pool.map(attempt, enumerate(inputs)))
failed = [(inp, problems, err) for inp, problems, err in results if problems]
for inp, problems, err in failed:
    print(f"FAILED: {inp['label']}: {'; '.join(problems)}\n    {err[:300]}")
escaped = [p for p in ("/tmp/abs",) if os.path.exists(p)]
for inp, problems, err in random.Random(1).sample(results, 12):
    print(f"sample: {inp['label']}\n    {err.splitlines()[-1][:200] if err else ''}")
print(f"fuzz: {len(inputs)} inputs tried, {len(failed)} failed")
if failed or escaped:
    sys.exit(1)
print("ok: every input refused with exit 2, one message naming the key, nothing written")
