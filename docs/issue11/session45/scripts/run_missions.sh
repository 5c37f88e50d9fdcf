#!/bin/bash
# session 42's mission set (run_missions.sh) with extra --set options, skipping files already written:
#   bash docs/issue11/session45/scripts/run_missions.sh TREE OUT "KEY=VALUE ..." [builtin|variants|all]
set -u
tree=$1; out=$2; sets=$3; which=${4:-all}
args=(); for kv in $sets; do args+=(--set "$kv"); done
cd "$tree"
if [ "$which" != variants ]; then
  mkdir -p "$out/builtin"
  for s in near_miss nothing_there far_diver paper_pool murky distractor_behind far_placards left_arm clutter5; do
    [ -s "$out/builtin/$s.txt" ] && continue
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$s" --seeds 0-9 --jobs 2 "${args[@]}" > "$out/builtin/$s.txt" 2>&1
  done
fi
if [ "$which" != builtin ]; then
  for set in variants_seed12_small variants_seed9 variants_seed10; do
    mkdir -p "$out/$set"
    for f in docs/issue11/session18/$set/variant_*.yaml; do
      o="$out/$set/default_$(basename "$f" .yaml).txt"
      [ -s "$o" ] && continue
      PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-2 --jobs 2 "${args[@]}" > "$o" 2>&1
    done
  done
fi
