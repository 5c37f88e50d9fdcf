"""Outcome per single-mission file of run_pairs.sh against the earlier outcome listed in PAIRS:
    python docs/issue11/session64/scripts/pair_table.py PAIRS_WITH_OUTCOMES DIR [DIR ...]
PAIRS_WITH_OUTCOMES: lines "NAME SEED PIXELS OUTCOME ONE_LOOK" (the earlier run)."""
import json, os, sys
before = {}
for line in open(sys.argv[1]):
    p = line.split()
    if len(p) >= 5:
        before[(p[0], p[1], p[2])] = (p[3], p[4])
changed = 0
for (name, seed, px), (out0, ol0) in sorted(before.items()):
    rec = None
    for d in sys.argv[2:]:
        f = os.path.join(d, f"{name}_s{seed}_px{px}.txt")
        if os.path.exists(f):
            for l in open(f):
                if l.startswith('{"seed'):
                    rec = json.loads(l)
    if rec is None:
        continue
    now = (rec["outcome"], rec.get("decision_one_look"))
    mark = "" if now[0] == out0 else "  <- changed"
    changed += bool(mark)
    print(f"{name:22s} s{seed} px{px}  before {out0:10s} {ol0:>7s}   now {now[0]:10s} {now[1]}  second looks {rec.get('second_looks')}{mark}")
print(f"changed: {changed}")
