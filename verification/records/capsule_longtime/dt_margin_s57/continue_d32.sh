#!/bin/bash
# The d/32 Skalak C = 10 capsule (Ca 0.025) continued from capsule_longtime's run at t = 10
# (its final checkpoint, build/verification/capsule_longtime/runs/ca0.025_n128_skalak_C10_t10)
# with a fixed time.dt = F x its automatic step (2.232143e-4) to t = 10.3; runs in
# /tmp/d32probe_F<F>.
#   bash verification/records/capsule_longtime/dt_margin_s57/continue_d32.sh 8 6 4
set -u
REPO=$(cd "$(dirname "$0")/../../../.." && pwd)
CK=$REPO/build/verification/capsule_longtime/runs/ca0.025_n128_skalak_C10_t10/checkpoint.h5
for F in "$@"; do
    OUT=/tmp/d32probe_F$F
    rm -rf "$OUT"
    DT=$(/usr/bin/python3 -c "print(2.232142857142857e-04 * $F)")
    "$REPO/build/bin/efsi" run "$REPO/cases/capsule_shear" -o "$OUT" -q \
        --set 'grid.cells=[128,128,128]' --set 'grid.length=[8.0,8.0,8.0]' \
        --set 'grid.origin=[-4.0,-4.0,-4.0]' --set body[0].elastic_modulus=40.0 \
        --set time.end_time=10.3 --set output.fields_interval=10.0 \
        --set output.checkpoint_every=100000 --set output.progress_every=100000 \
        --set body[0].law=\"skalak\" --set body[0].area_dilation=10.0 \
        --set output.diagnostics_every=10 --set time.dt=$DT --restart "$CK" > "$OUT.log" 2>&1
    echo "F=$F rc=$? $(tail -1 "$OUT.log" | cut -c1-200)"
done
