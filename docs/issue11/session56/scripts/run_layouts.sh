#!/bin/bash
# Every layout (variant_*.yaml) of the folders given, three seeds each, from a frozen tree, skipping files already
# written; each folder's runs go to OUT/<folder name>:
#   bash docs/issue11/session56/scripts/run_layouts.sh TREE OUT "KEY=VALUE ..." FOLDER [FOLDER ...]
# Session 56's fresh layouts (FOLDER paths relative to TREE):
#   python -m sitl.variants --count 20 --seed 23 --out docs/issue11/session56/variants_seed23
#   python -m sitl.variants --count 20 --seed 24 --small-share 0.3 --out docs/issue11/session56/variants_seed24_small30
set -u
tree=$1; out=$2; sets=$3; shift 3
args=(); for kv in $sets; do args+=(--set "$kv"); done
cd "$tree"
for folder in "$@"; do
  mkdir -p "$out/$(basename "$folder")"
  for f in "$folder"/variant_*.yaml; do
    o="$out/$(basename "$folder")/default_$(basename "$f" .yaml).txt"
    [ -s "$o" ] && continue
    PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-2 --jobs 2 "${args[@]}" > "$o" 2>&1
  done
done
echo done > "$out/DONE"
