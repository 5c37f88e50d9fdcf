"""Every field of every run line equal between two mission folders, the new closest-approach fields aside.

    python docs/issue11/session51/scripts/identical_but_closest.py AFTER_DIR BEFORE_DIR
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session45" / "scripts"))
from compare_missions import run_lines as runs  # noqa: E402  (session 45's reader of the run lines)

NEW = {"closest_m", "closest_other_m"}
after, before = runs(Path(sys.argv[1])), runs(Path(sys.argv[2]))
common = sorted(k for k in after if k in before)
differ = [(k, sorted(f for f in (set(after[k]) | set(before[k])) - NEW if after[k].get(f) != before[k].get(f)))
          for k in common]
differ = [(k, fs) for k, fs in differ if fs]
for k, fs in differ:
    print(f"{k[0]} seed {k[1]}: {', '.join(fs)}")
print(f"{len(common)} runs compared; {len(differ)} differ in any field but {', '.join(sorted(NEW))}")
