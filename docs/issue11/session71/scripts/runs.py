"""One line per mission run of campaign output files: layout, seed, outcome, placard chosen / pointed, ambiguous round
trips, second looks, arrival time (issue 11 session 71).

    python docs/issue11/session71/scripts/runs.py FILE_OR_DIR ...
"""
import glob
import json
import os
import sys


def rows(path: str):
    """Yield (name, run dict) for every run line of a file or of every .txt file under a directory."""
    files = sorted(glob.glob(os.path.join(path, "**", "*.txt"), recursive=True)) if os.path.isdir(path) else [path]
    for f in files:
        name = os.path.basename(f)[:-4].replace("default_", "").replace("variant_", "")
        for line in open(f):
            if line.startswith('{"seed"'):
                yield name, json.loads(line)


def main() -> None:
    for path in sys.argv[1:]:
        for name, r in rows(path):
            t = r["time_to_arrive_s"]
            print(f"{name} s{r['seed']} {r['outcome']} chose {r['chosen_id']} pointed {r['target_id']} "
                  f"art {r['ambiguous_round_trips']} second_looks {r['second_looks']} "
                  f"arrive {'-' if t is None else round(t, 1)}")


if __name__ == "__main__":
    main()
