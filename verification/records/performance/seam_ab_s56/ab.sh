#!/bin/bash
# ab.sh np steps label:binary ... ; alternates runs of capillary_coarse from its step-10
# checkpoint (run from the repository root; binaries in /tmp/bin; the checkpoint and the
# expanded case in /tmp/cap10, made by the base binary:
#   efsi run cases/capillary_coarse -o /tmp/cap10 --set time.max_steps=10 \
#       --set output.fields=false --set output.checkpoint_every=10
# whose case.toml holds the seeded bodies, so no run seeds again). Prints one line per run:
# seconds per step of each stage (the final step's diagnostics and checkpoint left out).
# Each run's end state stays in /tmp/ab_<label>_np<np> for compare_states.py.
np=$1; shift; steps=$1; shift
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for spec in "$@"; do
  IFS=: read label bin <<< "$spec"
  out=/tmp/ab_${label}_np$np
  rm -rf $out
  load=$(cut -d' ' -f1 /proc/loadavg)
  mpirun -np $np /tmp/bin/$bin run /tmp/cap10/case.toml -o $out -q \
      --restart /tmp/cap10/checkpoint.h5 --set time.max_steps=$((10+steps)) \
      --set output.fields=false --set output.checkpoint_every=0 \
      --set output.diagnostics_every=1000 >/dev/null 2>&1
  /usr/bin/python3 - "$label" "$np" "$load" "$out" <<'PY'
import json, sys
label, np, load, out = sys.argv[1:]
s = json.load(open(f'{out}/summary.json'))
n, st = s['steps'], s['stages']
skip = ('checkpoint', 'output', 'diagnostics')
tot = sum(v for k, v in st.items() if k not in skip)
parts = ' '.join(f'{k} {v / n:.3f}' for k, v in sorted(st.items())
                 if k not in skip and v / n >= 0.005)
print(f'{label} np {np} load {load} step {tot / n:.3f} {parts}')
PY
done
