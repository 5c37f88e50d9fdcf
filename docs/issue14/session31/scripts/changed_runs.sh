#!/bin/bash
# Print the runs whose outcome or chosen placard changed between two mission folders (compare_runs.py lines);
# run from the repository root:  bash docs/issue14/session31/scripts/changed_runs.sh AFTER_DIR BEFORE_DIR
python docs/issue11/session26/scripts/compare_runs.py "$1" "$2" | python -c "
import sys, re
for l in sys.stdin:
    m = re.search(r'\) (\w+)->(\w+) chosen (\w+)->(\w+)', l)
    if m and (m.group(1) != m.group(2) or m.group(3) != m.group(4)): print(l.rstrip())
    elif 'runs compared' in l: print(l.rstrip())"
