#!/bin/bash
# Session 63's probe fault plans (docs/issue11/session63/plans/, written before any was run), seeds 0-9 each, from a
# frozen tree, skipping files already written:
#   bash docs/issue11/session63/scripts/probe_plans.sh TREE OUT LABEL [SCENARIO] [PLAN...]
# PLANS=DIR takes the plans from another folder (session 64: PLANS=docs/issue11/session64/plans, absolute).
set -u
tree=$1; out=$2; label=$3; scenario=${4:-paper_pool}; shift 4 2>/dev/null || shift $#
plans=("$@")
here=${PLANS:-$(cd "$(dirname "$0")/.." && pwd)/plans}
[ ${#plans[@]} -eq 0 ] && plans=($(ls "$here" | sed 's/\.yaml$//'))
mkdir -p "$out"; cd "$tree"
for p in "${plans[@]}"; do
  o="$out/${p}_${scenario##*/}_${label}.json"; [ -s "$o" ] && continue
  PYTHONPATH="$tree" nice -n 5 python -m sitl.fault_campaign missions --plan "$here/$p.yaml" --seeds 10 \
    --first-seed 0 --jobs 2 --scenario "$scenario" --json "$o" > "${o%.json}.txt" 2>&1
done
echo done > "$out/DONE_${label}"
