#!/bin/bash
# Chosen runs again from a frozen tree, one output file per scenario (skipped when complete):
#   bash docs/issue11/session71/scripts/rerun.sh TREE OUT "KEY=VALUE ..." SCENARIO:SEEDS ...
# (SEEDS as point_campaign's --seeds: 0-2 or 0,2; SCENARIO a built-in name or a .yaml path; JOBS=N processes per
# scenario, default 1; runs are deterministic, so the number of processes changes no row)
# session 68's pixels.sh is this with sitl.pose_source=blazepose first and JOBS=2.
set -u
tree=$1; out=$2; sets=$3; shift 3
args=(); for kv in $sets; do args+=(--set "$kv"); done
mkdir -p "$out"; cd "$tree"
for s in "$@"; do
  name=${s%%:*}; o="$out/$(basename "$name" .yaml).txt"; [ -s "$o" ] && grep -q '^{"runs"' "$o" && continue
  PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$name" --seeds "${s##*:}" --jobs "${JOBS:-1}" "${args[@]}" > "$o" 2>&1
done
echo done > "$out/DONE"
