#!/bin/bash
# BlazePose-pose missions from a frozen tree, one output file per scenario (skipped when complete):
#   bash docs/issue11/session68/scripts/pixels.sh TREE OUT "KEY=VALUE ..." SCENARIO:SEEDS ...
# (session 71's rerun.sh with sitl.pose_source=blazepose before the given settings, two processes per scenario)
JOBS=2 exec bash "$(dirname "$0")/../../session71/scripts/rerun.sh" "$1" "$2" "sitl.pose_source=blazepose $3" "${@:4}"
