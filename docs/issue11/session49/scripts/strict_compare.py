"""Run-by-run strict comparison of two mission folders: every field of every run line, not only the outcome.

    python docs/issue11/session49/scripts/strict_compare.py AFTER_DIR BEFORE_DIR

Prints each run (file, seed) whose JSON line differs in any field, with the fields that differ.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session45" / "scripts"))
from compare_missions import run_lines as runs  # noqa: E402  (session 45's reader of the run lines)


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
