#!/bin/bash
# run_list.sh LISTFILE OUTDIR : each line "SUB NAME SEEDS" (SEEDS: 0-9 or 1,3,7); SETS="--set K=V ..." adds overrides.
# Runs in the worktree /tmp/wl (git worktree add /tmp/wl COMMIT), --jobs 2: session 38's run_list.sh with WT=/tmp/wl.
WT=${WT:-/tmp/wl} exec bash "$(dirname "$0")/../../session38/scripts/run_list.sh" "$@"
