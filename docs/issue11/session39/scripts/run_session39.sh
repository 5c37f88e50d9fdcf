#!/bin/bash
tree=/tmp/wt; out=/tmp/s39/truth
cd $tree
echo "truth start $(date)" >> /tmp/s39/queue.log
mkdir -p $out/builtin
for s in near_miss nothing_there paper_pool far_diver clutter5 distractor_behind far_placards left_arm murky; do
  PYTHONPATH=$tree nice -n 5 python -m sitl.point_campaign mission --scenario $s --seeds 0-9 --jobs 2 > $out/builtin/$s.txt 2>&1
done
echo "builtin done $(date)" >> /tmp/s39/queue.log
for set in variants_seed9 variants_seed12_small; do
  mkdir -p $out/$set
  for f in docs/issue11/session18/$set/variant_*.yaml; do
    PYTHONPATH=$tree nice -n 5 python -m sitl.point_campaign mission --scenario $f --seeds 0-2 --jobs 2 > $out/$set/default_$(basename $f .yaml).txt 2>&1
  done
  echo "$set done $(date)" >> /tmp/s39/queue.log
done
printf "variants variant_9_03 0-2\nbuiltin paper_pool 0-9\nvariants variant_9_01 0-2\nv10 variant_10_05 0-2\nv10 variant_10_13 0-2\n" > /tmp/s39/list_px2.txt
SETS="--set sitl.pose_source=blazepose" WT=$tree bash /work/main/docs/issue11/session38/scripts/run_list.sh /tmp/s39/list_px2.txt /tmp/s39/px2
echo "px done $(date)" >> /tmp/s39/queue.log
mkdir -p $out/variants_seed10
for f in docs/issue11/session18/variants_seed10/variant_*.yaml; do
  PYTHONPATH=$tree nice -n 5 python -m sitl.point_campaign mission --scenario $f --seeds 0-2 --jobs 2 > $out/variants_seed10/default_$(basename $f .yaml).txt 2>&1
done
echo "v10 truth done $(date)" >> /tmp/s39/queue.log
