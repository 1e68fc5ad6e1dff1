#!/bin/bash
# capsule_ab.sh np steps label:binary ... ; alternates runs of capsule_longtime's d/32 Skalak
# capsule (C = 10, Ca 0.025, 128^3; run_sets(32, 0.025, 10, "skalak", 10, 0) of
# verification/studies/capsule_longtime.py) from t = 0 (run from the repository root;
# binaries in /tmp/bin; no field output, no checkpoint). Prints one line per run: seconds
# per step of each stage (diagnostics, output and checkpoint left out) and the wall time.
np=$1; shift; steps=$1; shift
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
args=$(cd verification/studies && /usr/bin/python3 -c "
from capsule_longtime import run_sets
s = run_sets(32, 0.025, 10.0, 'skalak', 10.0, 0.0)
s.update({'time.max_steps': '$steps', 'output.fields': 'false', 'output.checkpoint_every': '0'})
print(' '.join(f'--set {k}={v}' for k, v in s.items() if k != 'case.description'))")
for spec in "$@"; do
  IFS=: read label bin <<< "$spec"
  rm -rf /tmp/cab_$label
  load=$(cut -d' ' -f1 /proc/loadavg)
  mpirun -np $np /tmp/bin/$bin run cases/capsule_shear -o /tmp/cab_$label -q $args >/dev/null 2>&1
  /usr/bin/python3 - "$label" "$np" "$load" <<'PY'
import json, sys
label, np, load = sys.argv[1:]
s = json.load(open(f'/tmp/cab_{label}/summary.json'))
n, st = s['steps'], s['stages']
skip = ('checkpoint', 'output', 'diagnostics')
tot = sum(v for k, v in st.items() if k not in skip)
parts = ' '.join(f'{k} {v / n:.4f}' for k, v in sorted(st.items())
                 if k not in skip and v / n >= 0.002)
print(f'{label} np {np} load {load} step {tot / n:.4f} {parts} wall {s["wall_seconds"]:.1f}')
PY
done
