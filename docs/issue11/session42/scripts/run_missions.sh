#!/bin/bash
# session 42's order: the built-ins (near_miss and nothing_there first), then the 4 cm targets, seed-9, seed-10 variants
set -u
tree=$1; out=$2
cd "$tree"
mkdir -p "$out/builtin"
for s in near_miss nothing_there far_diver paper_pool murky distractor_behind far_placards left_arm clutter5; do
  PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$s" --seeds 0-9 --jobs 2 > "$out/builtin/$s.txt" 2>&1
done
for set in variants_seed12_small variants_seed9 variants_seed10; do
  mkdir -p "$out/$set"
  for f in docs/issue11/session18/$set/variant_*.yaml; do
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-2 --jobs 2 > "$out/$set/default_$(basename "$f" .yaml).txt" 2>&1
  done
done
