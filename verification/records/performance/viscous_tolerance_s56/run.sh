#!/bin/bash
# run.sh tol ... : capillary_coarse, 10 steps from the step-10 checkpoint in /tmp/cap10 (as in
# ../seam_ab_s56/ab.sh), one rank, with solver.viscous.tolerance = tol, diagnostics every
# step; prints the stages per step and the viscous iterations of each step. End states in
# /tmp/vt_<tol>_<n> (n counts the runs of a tolerance) for compare.py.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for tol in "$@"; do
  n=1; while [ -d /tmp/vt_${tol}_$n ]; do n=$((n+1)); done
  out=/tmp/vt_${tol}_$n
  load=$(cut -d' ' -f1 /proc/loadavg)
  build/bin/efsi run /tmp/cap10/case.toml -o $out -q --restart /tmp/cap10/checkpoint.h5 \
      --set time.max_steps=20 --set output.fields=false --set output.checkpoint_every=0 \
      --set output.diagnostics_every=1 --set solver.viscous.tolerance=$tol >/dev/null 2>&1
  /usr/bin/python3 - "$tol" "$load" "$out" <<'PY'
import csv, json, sys
tol, load, out = sys.argv[1:]
s = json.load(open(f'{out}/summary.json'))
n, st = s['steps'], s['stages']
its = [r['viscous_iterations'] for r in csv.DictReader(open(f'{out}/diagnostics.csv'))][-n:]
skip = ('checkpoint', 'output', 'diagnostics')
tot = sum(v for k, v in st.items() if k not in skip)
print(f'tol {tol} load {load} step {tot / n:.3f} viscous_solve {st["viscous_solve"] / n:.3f} '
      f'pressure_solve {st["pressure_solve"] / n:.3f} iterations {",".join(its)} out {out}')
PY
done
