#!/bin/bash
# The d/16 Skalak C = 100 capsule (Ca 0.025) continued from a checkpoint of capsule_longtime's
# own run with a fixed time.dt = F x its automatic step (4.664179e-5), for SPAN shear times.
# The checkpoint used in session 57: that run's checkpoint.h5 at step 21 500, t = 1.0028
# (build/verification/capsule_longtime/runs/ca0.025_n64_skalak_C100_t20; not kept: 60 MB).
#
#   SPAN=1.0 bash verification/records/capsule_longtime/dt_margin_s57/continue.sh CKPT 6 10
#
# Runs go to /tmp/dtprobe_F<F> (PREFIX overrides /tmp/dtprobe_F); compare.py sets their bodies.csv beside the run's own.
set -u
REPO=$(cd "$(dirname "$0")/../../../.." && pwd)
CKPT=$1
shift
SPAN=${SPAN:-0.14}
T0=$(/usr/bin/python3 -c "import h5py; print(h5py.File('$CKPT')['/'].attrs['time'])")
for F in "$@"; do
    DT=$(/usr/bin/python3 -c "print(4.664179104477612e-05 * $F)")
    END=$(/usr/bin/python3 -c "print($T0 + $SPAN)")
    OUT=${PREFIX:-/tmp/dtprobe_F}$F
    rm -rf "$OUT"
    "$REPO/build/bin/efsi" run "$REPO/cases/capsule_shear" --output "$OUT" -q \
        --set 'grid.cells=[64,64,64]' --set 'grid.length=[8.0,8.0,8.0]' \
        --set 'grid.origin=[-4.0,-4.0,-4.0]' --set body[0].elastic_modulus=40.0 \
        --set output.fields_interval=20.0 --set output.checkpoint_every=100000 \
        --set output.progress_every=100000 --set body[0].law=\"skalak\" \
        --set body[0].area_dilation=100.0 --set output.diagnostics_every=20 \
        --set time.dt=$DT --set time.end_time=$END --restart "$CKPT" > "$OUT.log" 2>&1
    echo "F=$F rc=$? $(tail -1 "$OUT.log")"
done
