"""Arrived runs that went back from arrive to servo, and how often, over a campaign folder's run rows.

    python docs/issue11/session56/scripts/flaps.py DIR [DIR ...]
"""
import glob
import json
import sys


def _rows(path: str):
    """Yield the run rows of a campaign file (a line may run on into the next row)."""
    dec = json.JSONDecoder()
    for line in open(path):
        at = line.find('{"seed"')
        while at >= 0:
            row, end = dec.raw_decode(line, at)
            yield row
            at = line.find('{"seed"', end)


for top in sys.argv[1:]:
    runs = times = arrived = 0
    for path in sorted(glob.glob(f"{top}/**/*.txt", recursive=True)):
        for row in _rows(path):
            if not row.get("arrived"):
                continue
            arrived += 1
            states = row.get("states") or []
            back = sum(1 for a, b in zip(states, states[1:]) if (a, b) == ("arrive", "servo"))
            runs += back > 0
            times += back
    print(f"{top}: {runs} of {arrived} arrived runs went back from arrive to servo ({times} times)")
