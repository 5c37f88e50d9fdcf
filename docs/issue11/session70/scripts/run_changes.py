"""Runs whose outcome, nearest pass or hold-short changed between two campaign folders (same file names):
    python docs/issue11/session70/scripts/run_changes.py BEFORE_DIR AFTER_DIR
Prints each changed run (layout, seed, outcome, closest_other_m, held_short_m before -> after), then the count of
runs compared, changed, and the least closest_other_m on each side (metres)."""
import json
import sys
from pathlib import Path


def runs(folder: Path) -> dict:
    """Return {(file, seed): run row} of a campaign folder's mission rows."""
    out = {}
    for f in sorted(folder.glob("*.txt")):
        for line in f.read_text().splitlines():
            if line.startswith("{") and '"seed"' in line:
                row = json.loads(line)
                out[(f.stem, row["seed"])] = row
    return out


def main(before_dir: str, after_dir: str) -> None:
    """Print the changed runs and the totals."""
    before, after = runs(Path(before_dir)), runs(Path(after_dir))
    keys = ("outcome", "chosen_id", "closest_other_m", "held_short_m")
    changed = 0
    for k in sorted(before.keys() & after.keys()):
        b, a = before[k], after[k]
        if any(b.get(x) != a.get(x) for x in keys):
            changed += 1
            print(k[0], "s%d" % k[1], " | ".join(f"{x} {b.get(x)} -> {a.get(x)}" for x in keys if b.get(x) != a.get(x)))
    least = lambda rows: min((r["closest_other_m"] for r in rows.values() if r.get("closest_other_m") is not None),
                             default=None)
    print(f"{len(before.keys() & after.keys())} runs compared, {changed} changed; least closest_other_m "
          f"{least(before)} -> {least(after)}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
