#!/bin/bash
# The nine built-ins, seeds 0-9, with the prior-per-target experiment patched in:
#   bash docs/issue11/session68/experiments/run_builtins_patched.sh TREE OUT
set -u
tree=$1; out=$2; here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"; cd "$tree"
for s in near_miss nothing_there far_diver paper_pool murky distractor_behind far_placards left_arm clutter5; do
  [ -s "$out/$s.txt" ] && grep -q '^{"runs"' "$out/$s.txt" && continue
  PYTHONPATH="$tree" nice -n 5 python "$here/prior_per_target.py" -m sitl.point_campaign mission --scenario "$s" \
    --seeds 0-9 --jobs 2 > "$out/$s.txt" 2>&1
done
echo done > "$out/DONE"
