#!/bin/bash
# Session 58's survey, third part (the log is survey_3.txt): the red cell of rbc_in_tube at the
# factors between the stable 4 and the unstable 8 of queue_2, and at 3, the factor adopted.
set -u
export EFSI_BIN=${EFSI_BIN:-/tmp/efsi_base}  # the binary of commit 4e40ab1
D=$(dirname "$0")
/usr/bin/python3 $D/survey_case.py rbc_in_tube --end 1 3 5 6
/usr/bin/python3 $D/survey_case.py rbc_in_tube --end 1 --tag C100 --set 'body[1].area_dilation=100.0' 3 6
