#!/bin/bash
# Single missions (scenario, seed) from a frozen tree, one output file each, skipping files already written:
#   bash docs/issue11/session64/scripts/run_pairs.sh TREE OUT PAIRS ["KEY=VALUE ..."]
# PAIRS: lines "NAME SEED PIXELS" (NAME a built-in scenario or a layout found under TREE/docs; PIXELS 1 = BlazePose).
set -u
tree=$1; out=$2; pairs=$3; sets=${4:-}
args=(); for kv in $sets; do args+=(--set "$kv"); done
mkdir -p "$out"; cd "$tree"
while read -r name seed px _; do
  [ -z "$name" ] && continue
  path=$(find docs -name "$name.yaml" -path "*scenarios*" -o -name "$name.yaml" -path "*variants*" | head -1)
  [ -z "$path" ] && path=$name
  extra=(); [ "$px" = 1 ] && extra=(--set sitl.pose_source=blazepose)
  o="$out/${name}_s${seed}_px${px}.txt"; [ -s "$o" ] && continue
  PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$path" --seeds "$seed" --jobs 1 \
    "${extra[@]}" "${args[@]}" > "$o" 2>&1 < /dev/null
done < "$pairs"
echo done > "$out/DONE"
