"""Per seed, the mission outcomes of two folders of ``default_variant_*.txt`` campaign lines (after, before).

Usage: python docs/issue11/session19/compare.py AFTER_DIR BEFORE_DIR
Prints every run whose outcome or chosen placard changed, then the totals of both.
"""
import json, glob, sys, os
from collections import Counter
new_dir, old_dir = sys.argv[1], sys.argv[2]
cb, ca = Counter(), Counter()
for f in sorted(glob.glob(new_dir + "/default_variant_*.txt")):
    name = os.path.basename(f)
    old = os.path.join(old_dir, name)
    if not os.path.exists(old): continue
    def rows(p):
        return {d["seed"]: d for d in map(json.loads, open(p)) if "seed" in d}
    a, b = rows(f), rows(old)
    for s in sorted(a):
        if s not in b: continue
        ca[a[s]["outcome"]] += 1; cb[b[s]["outcome"]] += 1
        if a[s]["outcome"] != b[s]["outcome"] or a[s]["chosen_id"] != b[s]["chosen_id"]:
            print(name, s, "before", b[s]["outcome"], b[s]["chosen_id"], "after", a[s]["outcome"], a[s]["chosen_id"], "nothing" if a[s]["nothing_there"] else "")
print("before", dict(cb), "after", dict(ca))
