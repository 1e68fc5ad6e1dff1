#!/bin/bash
# Session 58, after the change (the log is survey_6_2d.txt): the stability study's 2D capsule at
# Ca 0.002 (d/16 to t = 2, its capsule_sets keys) at k x the NEW automatic step (factor 10,
# the binary of build/), k = 1, 2, 3, 4: the stored stability result predates the change.
set -u
D=$(dirname "$0")
S=(--set 'grid.cells=[64,64,1]' --set 'grid.length=[8.0,8.0,0.125]' --set 'grid.origin=[-4.0,-4.0,-0.0625]'
   --set 'body[0].elastic_modulus=500.0' --set output.checkpoint_every=0)
EFSI_BIN=$(cd "$D/../../../.." && pwd)/build/bin/efsi /usr/bin/python3 $D/survey_case.py capsule_shear_2d --end 2 --tag ca0.002_factor10 "${S[@]}" 1 2 3 4
