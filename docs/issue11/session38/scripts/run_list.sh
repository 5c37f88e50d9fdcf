#!/bin/bash
# run_list.sh LISTFILE OUTDIR : each line "SUB NAME SEEDS" (SEEDS: 0-9 or 1,3,7); SETS="--set K=V ..." adds overrides.
# Runs `python -m sitl.point_campaign mission` in the worktree $WT (default /tmp/wl; git worktree add DIR COMMIT), --jobs 2.
list=$1; out=$2; mkdir -p $out
cd ${WT:-/tmp/wl}
while read sub name seeds; do
  case $sub in
    builtin) scen=$name;;
    variants_seed9|variants) scen=docs/issue11/session18/variants_seed9/${name#default_}.yaml;;
    variants_seed10|v10) scen=docs/issue11/session18/variants_seed10/${name#default_}.yaml;;
    variants_seed12_small) scen=docs/issue11/session18/variants_seed12_small/${name#default_}.yaml;;
  esac
  mkdir -p $out/$sub
  PYTHONPATH=${WT:-/tmp/wl} nice -n 5 python -m sitl.point_campaign mission --scenario $scen --seeds $seeds --jobs 2 ${SETS:-} >> $out/$sub/$name.txt 2>&1
done < $list
