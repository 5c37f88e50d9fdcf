#!/bin/bash
# Session 55's fresh layouts (never run before this session), three seeds each, skipping files already written:
#   bash docs/issue11/session55/scripts/run_fresh.sh TREE OUT ["KEY=VALUE ..."]
# The layouts: python -m sitl.variants --count 20 --seed 21 --out docs/issue11/session55/variants_seed21
#              python -m sitl.variants --count 20 --seed 22 --small-share 0.3 --out docs/issue11/session55/variants_seed22_small30
set -u
tree=$1; out=$2; sets=${3:-}
args=(); for kv in $sets; do args+=(--set "$kv"); done
cd "$tree"
for set in variants_seed21 variants_seed22_small30; do
  mkdir -p "$out/$set"
  for f in docs/issue11/session55/$set/variant_*.yaml; do
    o="$out/$set/default_$(basename "$f" .yaml).txt"
    [ -s "$o" ] && continue
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-2 --jobs 2 "${args[@]}" > "$o" 2>&1
  done
done
echo done > "$out/DONE"
