"""Runs whose outcome, placard, nearest pass or hold-short changed between two campaign folders (same file names):
    python docs/issue11/session70/scripts/run_changes.py BEFORE_DIR[,...] AFTER_DIR[,...]
Prints each changed run (layout, seed, each changed field before -> after), then the count of runs compared,
changed, and the least closest_other_m on each side (metres). Runs are read by session 68's ``pair_diff.load``."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session68" / "scripts"))
from pair_diff import load  # noqa: E402

FIELDS = ("outcome", "chosen_id", "closest_other_m", "held_short_m")


def least_pass_m(runs: dict) -> float | None:
    """Return the least ``closest_other_m`` of the runs, metres (None: no run reports one)."""
    return min((r["closest_other_m"] for r in runs.values() if r.get("closest_other_m") is not None), default=None)


def main(before_dirs: str, after_dirs: str) -> None:
    """Print the changed runs and the totals."""
    before, after = load(before_dirs), load(after_dirs)
    common = sorted(before.keys() & after.keys())
    changed = 0
    for k in common:
        b, a = before[k], after[k]
        diff = [f"{x} {b.get(x)} -> {a.get(x)}" for x in FIELDS if b.get(x) != a.get(x)]
        if diff:
            changed += 1
            print(k[0], f"s{k[1]}", " | ".join(diff))
    print(f"{len(common)} runs compared, {changed} changed; least closest_other_m "
          f"{least_pass_m(before)} -> {least_pass_m(after)}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
