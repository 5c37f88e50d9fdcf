"""Totals and per-run differences of two mission campaigns (folders of point_campaign outputs):
python pair_diff.py BEFORE_DIR[,BEFORE_DIR...] AFTER_DIR[,AFTER_DIR...]"""
import glob, json, os, sys


def load(dirs: str) -> dict:
    """Return {(scenario file stem, seed): run} over comma-separated folders."""
    out = {}
    for d in dirs.split(","):
        for f in glob.glob(os.path.join(d, "*.txt")):
            for line in open(f):
                if line.startswith('{"seed"'):
                    r = json.loads(line)
                    out[(os.path.basename(f)[:-4].replace("default_", ""), r["seed"])] = r
    return out


def totals(runs: dict) -> str:
    """Return 'arrived / wrong / abstained (n)'."""
    n = {k: sum(r["outcome"] == k for r in runs.values()) for k in ("arrived", "wrong", "abstained")}
    return f"{n['arrived']} / {n['wrong']} / {n['abstained']} ({len(runs)})"


def main(before_dirs: str, after_dirs: str) -> None:
    """Print both campaigns' totals over their common runs, then each run whose outcome or placard changed."""
    before, after = load(before_dirs), load(after_dirs)
    common = sorted(set(before) & set(after))
    print("before", totals({k: before[k] for k in common}), " after", totals({k: after[k] for k in common}))
    for k in common:
        a, b = before[k], after[k]
        if (a["outcome"], a.get("chosen_id")) != (b["outcome"], b.get("chosen_id")):
            print(k, a["outcome"], a.get("chosen_id"), "->", b["outcome"], b.get("chosen_id"),
                  "| posterior", a.get("decision_posterior"), "->", b.get("decision_posterior"),
                  "| nothing there", a["nothing_there"], "->", b["nothing_there"])


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
