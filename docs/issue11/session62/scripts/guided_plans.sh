#!/bin/bash
# Every other bundled fault plan in GUIDED (docs/issue11/session62/plans/*_guided.yaml: the plan's own params plus
# link.output_mode guided_velocity, sim.has_position), paper_pool seeds 0-9, from a frozen tree; skips files written:
#   bash docs/issue11/session62/scripts/guided_plans.sh TREE OUT LABEL [PLAN ...]
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
tree=$1; out=$2; label=$3; shift 3
mkdir -p "$out"; cd "$tree"
plans=("$@"); [ ${#plans[@]} -eq 0 ] && plans=($(cd "$here/plans" && ls *_guided.yaml | sed 's/.yaml$//'))
for p in "${plans[@]}"; do
  o="$out/${p}_${label}_s0.json"; [ -s "$o" ] && continue
  nice -n 5 python -m sitl.fault_campaign missions --plan "$here/plans/$p.yaml" --seeds 10 --first-seed 0 --jobs 2 \
    --json "$o" > "${o%.json}.txt" 2>&1
done
