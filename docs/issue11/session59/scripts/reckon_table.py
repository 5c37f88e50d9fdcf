"""Median / max of reckon.py's errors at 1, 2, 3 s after the last sighting and at the streak's end, over every
miss streak of its output files:  python docs/issue11/session59/scripts/reckon_table.py FILE ..."""
import re
import sys

for path in sys.argv[1:]:
    got = {"1s": [], "2s": [], "3s": [], "end": []}
    streaks = 0
    for line in open(path):
        for part in line.split("; ")[1:]:
            if not part.startswith("miss"):
                continue
            streaks += 1
            for key in got:
                m = re.search(rf"{key} err ([0-9.]+)", part)
                if m:
                    got[key].append(float(m.group(1)))
    cells = []
    for key, v in got.items():
        v.sort()
        cells.append(f"{key}: {v[len(v) // 2]:.2f} / {v[-1]:.2f} ({len(v)})" if v else f"{key}: -")
    print(f"{path}: {streaks} streaks; error median / max (streaks) " + ", ".join(cells))
