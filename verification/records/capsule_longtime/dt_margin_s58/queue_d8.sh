#!/bin/bash
# Session 58's d/8 survey, t = 0 to 2 (one rank; the log is survey_d8.txt).
set -u
export EFSI_BIN=${EFSI_BIN:-/tmp/efsi_base}  # the binary of commit 4e40ab1
S="/usr/bin/python3 $(dirname "$0")/survey.py"
$S --cells 8 --ca 0.025 --law skalak --c 100 --end 2 1 2 4 8 12
$S --cells 8 --ca 0.025 --law skalak --c 10 --end 2 1 2 4 6 8
$S --cells 8 --ca 0.025 --end 2 1 2 4 8
$S --cells 8 --ca 0.0125 --end 2 1 2 4 8
$S --cells 8 --ca 0.05 --eb 0.01 --end 2 1 2 4 8
