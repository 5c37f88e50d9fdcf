"""The lowest one-look posteriors of the object decisions in mission campaign outputs (JSON lines).

    python docs/issue11/session24/scripts/one_look.py DIR [DIR ...]
"""
import json, sys, glob
vals = []
for d in sys.argv[1:]:
    for f in glob.glob(d + "/**/*.txt", recursive=True):
        for l in open(f):
            l = l.strip()
            if not l.startswith("{"): continue
            r = json.loads(l)
            if "outcome" not in r: continue
            for x in r.get("decisions", []):
                if x["kind"] == "object":
                    vals.append((x.get("one_look"), r["outcome"], f.split("/")[-1], r["seed"]))
lo = sorted(v for v in vals if v[0] is not None)
print(len(lo), "object decisions")
for v in lo[:25]: print(v)
