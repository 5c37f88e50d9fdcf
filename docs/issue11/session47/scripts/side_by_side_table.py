"""Outcome per seed of each side_by_side run file: outcome (chosen placard / pointed placard).

    python docs/issue11/session47/scripts/side_by_side_table.py FILE...
"""
import json, sys

runs = {}
for f in sys.argv[1:]:
    runs[f] = {}
    for line in open(f):
        if line.startswith('{"seed"'):
            d = json.loads(line)
            runs[f][d["seed"]] = f"{d['outcome']} ({d['chosen_id']}/{d['target_id']})"
seeds = sorted({s for r in runs.values() for s in r})
print("| seed | " + " | ".join(f.split("/")[-1].removesuffix(".txt") for f in runs) + " |")
print("|---" * (len(runs) + 1) + "|")
for s in seeds:
    print(f"| {s} | " + " | ".join(runs[f].get(s, "") for f in runs) + " |")
for f, r in runs.items():
    tot = {o: sum(1 for v in r.values() if v.startswith(o)) for o in ("arrived", "wrong", "abstained")}
    print(f"{f.split('/')[-1]}: arrived {tot['arrived']} / wrong {tot['wrong']} / abstained {tot['abstained']}")
