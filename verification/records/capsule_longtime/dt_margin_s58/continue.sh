#!/bin/bash
# The d/16 Skalak C = 100 capsule (Ca 0.025) continued from a checkpoint of capsule_longtime's
# own run with a fixed time.dt = F x its automatic step of the time (4.664179e-5), for SPAN
# shear times: session 57's continue.sh with the runs in /tmp/dtprobe58_F<F>.
# The checkpoint used in session 58: that run's checkpoint.h5 at step 101 700, t = 4.7435
# (copied from build/verification/capsule_longtime/runs/ca0.025_n64_skalak_C100_t20; not kept).
#
#   SPAN=2.0 bash verification/records/capsule_longtime/dt_margin_s58/continue.sh CKPT 4
PREFIX=/tmp/dtprobe58_F exec bash "$(dirname "$0")/../dt_margin_s57/continue.sh" "$@"
