#!/bin/bash
# Session 58's survey, second part (one rank; the log is survey_2.txt): the red cell of
# rbc_in_tube (strain carried as a tensor, no area filter; C = 10 as the case and C = 100) to
# 1 ms, and the d/16 capsules the session-57 survey left out (Ca 0.0125 neo-Hookean; Ca 0.05
# with bending 0.01) to shear-rate x t = 0.5.
set -u
export EFSI_BIN=${EFSI_BIN:-/tmp/efsi_base}  # the binary of commit 4e40ab1, copied before the session rebuilt build/
D=$(dirname "$0")
/usr/bin/python3 $D/survey_case.py rbc_in_tube --end 1 1 2 4 8
/usr/bin/python3 $D/survey_case.py rbc_in_tube --end 1 --tag C100 --set 'body[1].area_dilation=100.0' 1 2 4 8
/usr/bin/python3 $D/survey.py --cells 16 --ca 0.0125 --end 0.5 1 2 4 8
/usr/bin/python3 $D/survey.py --cells 16 --ca 0.05 --eb 0.01 --end 0.5 1 2 4 8
