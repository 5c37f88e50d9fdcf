#!/bin/bash
# Session 67's campaigns on one frozen tree (a detached worktree TREE), one after the other:
#   bash docs/issue11/session67/scripts/chain.sh TREE OUT
# built-ins, the seed-39 layouts (where a way passed 0.278 m from a placard's face), the pixel set, the fresh seed-40 layouts.
set -u
tree=$1; out=$2; here=$(cd "$(dirname "$0")/../../../.." && pwd)
bash "$here/docs/issue11/session45/scripts/run_missions.sh" "$tree" "$out/missions" "" builtin
bash "$here/docs/issue11/session56/scripts/run_layouts.sh" "$tree" "$out/fresh" "" docs/issue11/session66/variants_seed39
mkdir -p "$out/pixels"; cd "$tree"
for s in paper_pool:0-9 far_diver:0-9 docs/issue11/session18/variants_seed9/variant_9_03.yaml:0-2; do
  name=${s%%:*}; o="$out/pixels/$(basename "$name" .yaml).txt"; [ -s "$o" ] && continue
  PYTHONPATH="$tree" nice -n 5 python -m sitl.point_campaign mission --scenario "$name" --seeds "${s##*:}" --jobs 2 \
    --set sitl.pose_source=blazepose > "$o" 2>&1
done
echo done > "$out/pixels/DONE"
bash "$here/docs/issue11/session56/scripts/run_layouts.sh" "$tree" "$out/fresh40" "" docs/issue11/session67/variants_seed40
echo done > "$out/ALL_DONE"
