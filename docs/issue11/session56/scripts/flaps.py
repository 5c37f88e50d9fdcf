"""Arrived runs that went back from arrive to servo, and how often, over a campaign folder's run rows.

    python docs/issue11/session56/scripts/flaps.py DIR [DIR ...]
"""
import glob
import json
import sys

for top in sys.argv[1:]:
    runs = times = arrived = 0
    for path in sorted(glob.glob(f"{top}/**/*.txt", recursive=True)):
        for line in open(path):
            if not line.startswith('{"seed"'):
                continue
            row = json.loads(line)
            if not row.get("arrived"):
                continue
            arrived += 1
            states = row.get("states") or []
            back = sum(1 for a, b in zip(states, states[1:]) if (a, b) == ("arrive", "servo"))
            runs += back > 0
            times += back
    print(f"{top}: {runs} of {arrived} arrived runs went back from arrive to servo ({times} times)")
