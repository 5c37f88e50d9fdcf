#!/bin/bash
# The 270 truth-pose missions (the simulator's truth joints + the scenario's noise, the default pose source): the nine
# built-ins, seeds 0-9, and session 18's variant files (seed 9, seed 10, seed 12 small targets), seeds 0-2.
#   bash docs/issue11/session33/scripts/run_truth.sh WORKTREE OUTDIR [built-ins|variants|all]
#   SETS="--set KEY=VALUE ..." adds parameter overrides to every run. Copy this script out of the tree before running it.
set -u
tree=$(cd "$1" && pwd); out=$2; which=${3:-all}
cd "$tree"
if [ "$which" != variants ]; then
  mkdir -p "$out/builtin"
  for s in paper_pool far_diver clutter5 distractor_behind far_placards left_arm murky near_miss nothing_there; do
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$s" --seeds 0-9 --jobs 2 \
      ${SETS:-} > "$out/builtin/$s.txt" 2>&1
  done
fi
if [ "$which" != built-ins ]; then
  for set in variants_seed9 variants_seed10 variants_seed12_small; do
    mkdir -p "$out/$set"
    for f in docs/issue11/session18/$set/variant_*.yaml; do
      PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-2 --jobs 2 \
        ${SETS:-} > "$out/$set/default_$(basename "$f" .yaml).txt" 2>&1
    done
  done
fi
