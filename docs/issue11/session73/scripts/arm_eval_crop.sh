#!/bin/bash
# run.sh TAG SETTING: arm_eval with --select stereo on the clear-water scenarios
tag=$1; shift
cd /work/s73a
for sc in paper_pool:0-9 far_diver:0-9 clutter5:0-4 left_arm:0-4 murky:0-4; do
  name=${sc%%:*}; seeds=${sc##*:}
  PYTHONPATH=/work/s73a python -m sitl.arm_eval --scenario $name --seeds $seeds --frames 8 --select stereo --set sitl.pose_source=blazepose "$@" --json /tmp/s73/ae/${tag}_${name}.json > /tmp/s73/ae/${tag}_${name}.txt 2>&1
done
echo done > /tmp/s73/ae/${tag}.DONE
