#!/bin/bash
# BlazePose-pose missions from a frozen tree, one output file per scenario (skipped when complete):
#   bash docs/issue11/session68/scripts/pixels.sh TREE OUT "KEY=VALUE ..." SCENARIO:SEEDS ...
set -u
tree=$1; out=$2; sets=$3; shift 3
args=(--set sitl.pose_source=blazepose); for kv in $sets; do args+=(--set "$kv"); done
mkdir -p "$out"; cd "$tree"
for s in "$@"; do
  name=${s%%:*}; o="$out/$(basename "$name" .yaml).txt"; [ -s "$o" ] && grep -q '^{"runs"' "$o" && continue
  PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$name" --seeds "${s##*:}" --jobs 2 "${args[@]}" > "$o" 2>&1
done
echo done > "$out/DONE"
