#!/bin/bash
# Session 62's fault missions in GUIDED from a frozen tree: link_cut_guided seeds 0-39 (the "before" tree, aebd3f5,
# gets the plan file copied in), then link_cut seeds 0-9 (manual_control, a regression check); skips files written:
#   bash docs/issue11/session62/scripts/guided_runs.sh TREE OUT LABEL
set -u
tree=$1; out=$2; label=$3
mkdir -p "$out"; cd "$tree"
run() {  # plan first_seed count
  o="$out/$1_${label}_s$2.json"; [ -s "$o" ] && return
  nice -n 5 python -m sitl.fault_campaign missions --plan "sitl/faults/$1.yaml" --seeds "$3" --first-seed "$2" --jobs 2 \
    --json "$o" > "${o%.json}.txt" 2>&1
}
for s in 0 10 20 30; do run link_cut_guided $s 10; done
run link_cut 0 10
