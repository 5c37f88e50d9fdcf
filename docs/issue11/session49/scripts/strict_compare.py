"""Run-by-run strict comparison of two mission folders: every field of every run line, not only the outcome.

    python docs/issue11/session49/scripts/strict_compare.py AFTER_DIR BEFORE_DIR

Prints each run (file, seed) whose JSON line differs in any field, with the fields that differ.
"""
import json, sys
from pathlib import Path


def runs(folder: Path) -> dict:
    """Return {(file, seed): run dict} for every run line under ``folder``."""
    out = {}
    for f in sorted(folder.rglob("*.txt")):
        for line in f.read_text().splitlines():
            if line.startswith('{"seed"'):
                d = json.loads(line)
                out[(str(f.relative_to(folder)), d["seed"])] = d
    return out


after, before = runs(Path(sys.argv[1])), runs(Path(sys.argv[2]))
common = sorted(k for k in after if k in before)
changed = 0
for k in common:
    a, b = after[k], before[k]
    diff = sorted(f for f in set(a) | set(b) if a.get(f) != b.get(f))
    if diff:
        changed += 1
        print(f"{k[0]} seed {k[1]}: " + "; ".join(f"{f}: {b.get(f)!r} -> {a.get(f)!r}" for f in diff if f != "decisions")
              + ("; decisions differ" if "decisions" in diff else ""))
print(f"{len(common)} runs compared, {changed} differ in any field")
