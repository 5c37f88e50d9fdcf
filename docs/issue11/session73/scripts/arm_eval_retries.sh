#!/bin/bash
tag=$1; shift
cd /work/s73d
L=""
for f in /work/main/docs/issue11/session70/variants_seed43/variant_43_{01,03,05,07,09,11,13,15,17,19}.yaml /work/main/docs/issue11/session72/variants_seed44/variant_44_{01,03,05,07,09,11,13,15,17,19}.yaml /work/main/docs/issue11/session69/variants_seed42/variant_42_{01,03,05,07,09,11,13,15,17,19}.yaml; do L="$L $f:0"; done
for sc in murky:0-9 $L; do
  name=$(basename ${sc%%:*} .yaml)
  PYTHONPATH=/work/s73d python -m sitl.arm_eval --scenario ${sc%%:*} --seeds ${sc##*:} --frames 8 --select stereo --set sitl.pose_source=blazepose "$@" --json /tmp/s73/ae4/${tag}_$name.json > /tmp/s73/ae4/${tag}_$name.txt 2>&1
done
echo done > /tmp/s73/ae4/$tag.DONE
