"""Compare per-seed outcomes (outcome, chosen placard) of two campaign folders: python cmp.py AFTER BEFORE."""
import json, sys, pathlib
after, before = map(pathlib.Path, sys.argv[1:3])
def rows(p):
    out = {}
    for l in open(p):
        if l.startswith('{"seed"'):
            d = json.loads(l); out[(d["seed"], d.get("position"))] = (d["outcome"], d["chosen_id"], d["decision_one_look"])
    return out
tot = {}
for f in sorted(after.rglob("*.txt")):
    rel = f.relative_to(after); b = before / rel
    if not b.exists(): continue
    a, o = rows(f), rows(b)
    for k in sorted(a):
        if k in o and a[k][:2] != o[k][:2]:
            print(rel, k[0], o[k], "->", a[k])
