#!/bin/bash
# Session 58's survey, fourth part (the log is survey_4.txt): the d/16 neo-Hookean capsule at
# Ca 0.0125 between its stable 4 and unstable 8, and at 3.
set -u
export EFSI_BIN=${EFSI_BIN:-/tmp/efsi_base}  # the binary of commit 4e40ab1
D=$(dirname "$0")
/usr/bin/python3 $D/survey.py --cells 16 --ca 0.0125 --end 0.5 3 5 6
