#!/bin/bash
# The 130 pixel missions (BlazePose on every frame): the nine built-ins, seeds 0-9, and session 18's seed-9 variant
# files, seeds 0-1; or (v10) the held-out seed-10 variant files, seeds 0-1.
#   bash docs/issue14/session32/scripts/run_pixels.sh WORKTREE OUTDIR [built-ins|variants|all|v10]
#   SETS="--set KEY=VALUE ..." adds parameter overrides to every run.
set -u
tree=$(cd "$1" && pwd); out=$2; which=${3:-all}
mkdir -p "$out/builtin" "$out/variants"
cd "$tree"
if [ "$which" = v10 ]; then
  mkdir -p "$out/v10"
  for f in docs/issue11/session18/variants_seed10/variant_*.yaml; do
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-1 --jobs 2 \
      --set sitl.pose_source=blazepose ${SETS:-} > "$out/v10/$(basename "$f" .yaml).txt" 2>&1
  done
  exit 0
fi
if [ "$which" != variants ]; then
  for s in paper_pool far_diver clutter5 distractor_behind far_placards left_arm murky near_miss nothing_there; do
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$s" --seeds 0-9 --jobs 2 \
      --set sitl.pose_source=blazepose ${SETS:-} > "$out/builtin/$s.txt" 2>&1
  done
fi
if [ "$which" != built-ins ]; then
  for f in docs/issue11/session18/variants_seed9/variant_*.yaml; do
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-1 --jobs 2 \
      --set sitl.pose_source=blazepose ${SETS:-} > "$out/variants/$(basename "$f" .yaml).txt" 2>&1
  done
fi
