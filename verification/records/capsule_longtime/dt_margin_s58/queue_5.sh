#!/bin/bash
# Session 58's survey, fifth part (the log is survey_5.txt): the C = 100 red cell, which stopped
# at F = 6 (t = 0.6 ms), at F = 5 and, over three times as long, at F = 4.
set -u
export EFSI_BIN=${EFSI_BIN:-/tmp/efsi_base}  # the binary of commit 4e40ab1
D=$(dirname "$0")
/usr/bin/python3 $D/survey_case.py rbc_in_tube --end 1 --tag C100 --set 'body[1].area_dilation=100.0' 5
/usr/bin/python3 $D/survey_case.py rbc_in_tube --end 3 --tag C100_3ms --set 'body[1].area_dilation=100.0' 4
