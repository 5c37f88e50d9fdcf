"""Compare two mission folders run by run (outcome, chosen placard, close-in, one look, time to arrive).

    python docs/issue11/session26/scripts/compare_runs.py AFTER_DIR BEFORE_DIR

Both folders hold SUBDIR/NAME.txt campaign lines (`point_campaign mission` output); every run that closed in or
changed its outcome or chosen placard is printed.
"""
import json, glob, os, sys
def load(p):
    out = {}
    for l in open(p):
        if l.startswith('{"seed"'):
            d = json.loads(l); out[(d["seed"], d.get("position"))] = d
    return out
a_dir, b_dir = sys.argv[1], sys.argv[2]
n = 0
for f in sorted(glob.glob(a_dir + "/*/*.txt")):
    rel = os.path.relpath(f, a_dir)
    bf = os.path.join(b_dir, rel)
    if not os.path.exists(bf): continue
    A, B = load(f), load(bf)
    for k in sorted(A):
        x, y = A[k], B.get(k)
        if y is None: continue
        n += 1
        ci = "close_in" in x["states"]
        if ci or x["outcome"] != y["outcome"] or x["chosen_id"] != y["chosen_id"]:
            t = lambda d: d["time_to_arrive_s"] and round(d["time_to_arrive_s"], 1)
            print(rel, k, f'{y["outcome"]}->{x["outcome"]}', f'chosen {y["chosen_id"]}->{x["chosen_id"]} (target {x["target_id"]})',
                  "close_in" if ci else "", f'one_look {y["decision_one_look"]}->{x["decision_one_look"]}', f"t {t(y)}->{t(x)}",
                  f'decisions {len(y["decisions"])}->{len(x["decisions"])}')
print(n, "runs compared")
