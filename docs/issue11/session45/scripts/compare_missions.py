"""Run-by-run comparison of two mission folders (point_campaign JSON lines): totals and the runs that changed.

    python docs/issue11/session45/scripts/compare_missions.py AFTER_DIR BEFORE_DIR
"""
import json, sys
from pathlib import Path


def run_lines(folder: Path) -> dict:
    """Return {(file, seed): run dict} for every run line under ``folder`` (point_campaign's JSON lines).

    A line is read up to the end of its JSON object: the campaign's stderr notice, written to the same file, can
    land right after it on the same line.
    """
    out = {}
    for f in sorted(folder.rglob("*.txt")):
        for line in f.read_text().splitlines():
            if line.startswith('{"seed"'):
                d = json.JSONDecoder().raw_decode(line)[0]
                out[(str(f.relative_to(folder)), d["seed"])] = d
    return out


def runs(folder: Path) -> dict:
    """Return {(file, seed): (outcome, chosen, target, one_look, nothing_there)} for every run line under ``folder``."""
    return {k: (d["outcome"], d["chosen_id"], d["target_id"], d.get("decision_one_look"), d.get("nothing_there"))
            for k, d in run_lines(folder).items()}


def main() -> None:
    """Print both folders' totals over their common runs, the runs whose outcome or choice changed, and the rest."""
    after, before = runs(Path(sys.argv[1])), runs(Path(sys.argv[2]))
    for name, r in (("after", after), ("before", before)):
        common = [k for k in r if k in after and k in before]
        tot = {o: sum(1 for k in common if r[k][0] == o) for o in ("arrived", "wrong", "abstained")}
        nothing = sum(1 for k in common if r[k][0] == "abstained" and r[k][4])
        print(f"{name}: {len(common)} runs: arrived {tot['arrived']} / wrong {tot['wrong']} / abstained {tot['abstained']} ({nothing} nothing there)")
    for k in sorted(k for k in after if k in before and after[k][:2] != before[k][:2]):
        print(f"changed {k[0]} seed {k[1]}: {before[k][0]} (chosen {before[k][1]}, one look {before[k][3]}) -> "
              f"{after[k][0]} (chosen {after[k][1]}, one look {after[k][3]}), target {after[k][2]}")
    print("runs only in after:", len([k for k in after if k not in before]), "only in before:", len([k for k in before if k not in after]))


if __name__ == "__main__":
    main()
