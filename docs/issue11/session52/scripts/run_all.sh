#!/bin/bash
# Session 52's mission set from a frozen tree: the 90 built-in truth missions, the four two-placard scenarios,
# issue 14's pixel set (BlazePose) and the 180 variant runs, skipping files already written:
#   bash docs/issue11/session52/scripts/run_all.sh TREE OUT ["KEY=VALUE ..."]
set -u
tree=$1; out=$2; sets=${3:-}
args=(); for kv in $sets; do args+=(--set "$kv"); done
bash "$tree/docs/issue11/session45/scripts/run_missions.sh" "$tree" "$out/missions" "$sets" builtin
cd "$tree"
mkdir -p "$out/two_placards" "$out/pixels"
for f in docs/issue11/session47/scenarios/side_by_side.yaml docs/issue11/session48/scenarios/{side_by_side_close,side_by_side_far,stacked}.yaml; do
  o="$out/two_placards/$(basename "$f" .yaml).txt"; [ -s "$o" ] && continue
  nice -n 5 python -m sitl.point_campaign mission --scenario "$f" --seeds 0-9 --jobs 2 "${args[@]}" > "$o" 2>&1
done
for spec in "paper_pool 0-9" "far_diver 0-9" "docs/issue11/session18/variants_seed9/variant_9_03.yaml 0-2"; do
  set -- $spec; o="$out/pixels/$(basename "$1" .yaml).txt"; [ -s "$o" ] && continue
  nice -n 5 python -m sitl.point_campaign mission --scenario "$1" --seeds "$2" --jobs 2 --set sitl.pose_source=blazepose "${args[@]}" > "$o" 2>&1
done
bash "$tree/docs/issue11/session45/scripts/run_missions.sh" "$tree" "$out/missions" "$sets" variants
echo done > "$out/DONE"
