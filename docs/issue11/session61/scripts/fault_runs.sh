#!/bin/bash
# Session 61's fault-mission campaigns from a frozen tree: link_cut seeds 0-39 and gcs_loss 0-19 (new only: session
# 60 ran them on the code before), then every other bundled plan seeds 0-9, skipping files already written:
#   bash docs/issue11/session61/scripts/fault_runs.sh TREE OUT LABEL [full]
set -u
tree=$1; out=$2; label=$3; full=${4:-}
mkdir -p "$out"; cd "$tree"
run() {  # plan first_seed count
  o="$out/$1_${label}_s$2.json"; [ -s "$o" ] && return
  nice -n 5 python -m sitl.fault_campaign missions --plan "sitl/faults/$1.yaml" --seeds "$3" --first-seed "$2" --jobs 2 \
    --json "$o" > "${o%.json}.txt" 2>&1
}
if [ -n "$full" ]; then
  for s in 0 10 20 30; do run link_cut $s 10; done
  for s in 0 10; do run gcs_loss $s 10; done
fi
for p in autopilot_reboot camera_black camera_one_eye camera_out_of_order camera_stall camera_time_backwards \
         camera_wrong_size link_loss link_mess pilot_disarm pilot_mode_change; do run $p 0 10; done
