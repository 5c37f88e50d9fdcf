"""Runs whose outcome, chosen placard or decision one-look posterior differ between two mission folders.

    python docs/issue11/session33/scripts/one_look_diff.py AFTER_DIR BEFORE_DIR

Both hold SUBDIR/NAME.txt `point_campaign mission` lines. Prints each differing run and a count; lines two parallel
jobs wrote into one line are read by their {"seed" ...} pieces.
"""
import glob
import json
import os
import re
import sys


def load(path: str) -> dict:
    """Return {(seed, position): run} from one campaign output file."""
    out = {}
    for piece in re.findall(r'\{"seed".*?"decisions": \[.*?\]\}', open(path).read()):
        try:
            d = json.loads(piece)
        except json.JSONDecodeError:
            continue
        out[(d["seed"], d.get("position"))] = d
    return out


after, before = sys.argv[1], sys.argv[2]
same = changed = 0
for path in sorted(glob.glob(os.path.join(after, "*", "*.txt"))):
    rel = os.path.relpath(path, after)
    other = os.path.join(before, rel)
    if not os.path.exists(other):
        continue
    a, b = load(path), load(other)
    for key in sorted(set(a) & set(b), key=str):
        x, y = a[key], b[key]
        fields = ("outcome", "chosen_id", "decision_one_look", "time_to_arrive_s")
        if all(x.get(f) == y.get(f) for f in fields):
            same += 1
            continue
        changed += 1
        print(rel, key, " ".join(f"{f} {y.get(f)}->{x.get(f)}" for f in fields if x.get(f) != y.get(f)))
print(f"{same} runs the same, {changed} differ")
