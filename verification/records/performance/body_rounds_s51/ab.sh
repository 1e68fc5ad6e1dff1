#!/bin/bash
# ab.sh np steps label:binary:env ... ; alternates (run from the repository root; the binaries
# in /tmp/bin, the step-10 checkpoint in /tmp/cap10: result.md)
np=$1; shift; steps=$1; shift
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for spec in "$@"; do
  IFS=: read label bin envv <<< "$spec"
  rm -rf /tmp/ab_$label
  env $envv mpirun -np $np /tmp/bin/$bin run cases/capillary_coarse -o /tmp/ab_$label -q --restart /tmp/cap10/checkpoint.h5 --set time.max_steps=$((10+steps)) --set output.fields=false --set output.checkpoint_every=0 >/dev/null 2>&1
  /usr/bin/python3 -c "
import json; s=json.load(open('/tmp/ab_$label/summary.json')); n=s['steps']; st=s['stages']
tot=sum(v for k,v in st.items() if k not in ('checkpoint','output'))
print('$label', $np, 'step s', round(tot/n,3), {k[:10]: round(v/n,3) for k,v in st.items() if k.startswith('bod') and v/n>0.005}, s['load_before'][0])"
done
