#!/bin/bash
# Session 66's campaigns on the final code (a detached worktree TREE), one after the other:
#   bash docs/issue11/session66/scripts/chain.sh TREE OUT
set -u
tree=$1; out=$2; here=$(cd "$(dirname "$0")/../../../.." && pwd)
while [ ! -f /tmp/builtin66.done ]; do sleep 10; done
bash "$here/docs/issue11/session56/scripts/run_layouts.sh" "$tree" "$out/fresh" "" docs/issue11/session66/variants_seed39
mkdir -p "$out/pixels"; cd "$tree"
for s in paper_pool:0-9 far_diver:0-9 docs/issue11/session18/variants_seed9/variant_9_03.yaml:0-2; do
  name=${s%%:*}; o="$out/pixels/$(basename "$name" .yaml).txt"; [ -s "$o" ] && continue
  PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$name" --seeds "${s##*:}" --jobs 2 \
    --set sitl.pose_source=blazepose > "$o" 2>&1
done
echo done > "$out/pixels/DONE"
