"""Tally a variants study: arrived / wrong / abstained over every file PREFIX_variant_*.txt, and each run that did not arrive.

Usage (from the repository root):
    python docs/issue11/session17/tally.py docs/issue11/session17/variants_seed7 default
    python docs/issue11/session17/tally.py docs/issue11/session17/variants_seed7 cap
Each ``PREFIX_NAME.txt`` is ``python -m sitl.point_campaign mission --scenario FOLDER/NAME.yaml --seeds 0-2``'s output.
"""
import collections
import json
import sys
from pathlib import Path

import yaml


def main() -> None:
    folder, prefix = Path(sys.argv[1]), sys.argv[2]
    total = collections.Counter()
    for path in sorted(folder.glob(f"{prefix}_variant_*.txt")):
        name = path.stem[len(prefix) + 1:]
        scenario = yaml.safe_load((folder / f"{name}.yaml").read_text())
        placards = {p["id"]: p for p in scenario["placards"]}
        for line in path.read_text().splitlines():
            if not line.startswith('{"seed"'):
                continue
            run = json.loads(line)
            total[run["outcome"]] += 1
            total[f"{run['outcome']} ({scenario['base']})"] += 1
            if run["outcome"] != "arrived":
                t = placards[run["target_id"]]
                looks = [(d["kind"], d.get("one_look_posterior")) for d in run["decisions"]]
                print(f"{name} {scenario['base']} seed {run['seed']}: target {run['target_id']} at {t['range_m']} m, "
                      f"chosen {run['chosen_id']}, {run['outcome']}{' (nothing there)' if run['nothing_there'] else ''}, "
                      f"decisions {looks}")
    print(dict(sorted(total.items())))


if __name__ == "__main__":
    main()
