"""First object decisions of the layout runs (latest campaign of each layout and seed, no move before it), counted by
one-look band, diver near (layout range <= 2.5 m) or far, and outcome; the wrong ones listed:
    python docs/issue11/session65/scripts/one_look_bands.py"""
import collections, glob, json, os

import yaml

ymls = {os.path.basename(p)[:-5]: p for p in glob.glob("docs/issue11/**/variant_*.yaml", recursive=True)}
rows = {}
for f in glob.glob("docs/issue11/session*/campaigns/**/default_variant_*.txt", recursive=True):
    name = os.path.basename(f)[8:-4]
    camp = f.split("/")[2]
    for l in open(f):
        if not l.startswith('{"seed"'): continue
        d = json.loads(l)
        if not d["decisions"]: continue
        dec = d["decisions"][0]
        if dec["kind"] != "object": continue
        moved = any(s in d["states"] for s in ("close_in", "second_look"))
        y = yaml.safe_load(open(ymls[name])) if name in ymls else None
        rng = y["diver"]["positions"][0]["range_m"] if y else None
        rows[(camp, name, d["seed"])] = (dec["one_look"], d["outcome"], moved, rng, len(d["decisions"]))
# keep latest session per (name, seed)
latest = {}
for (camp, name, seed), v in rows.items():
    k = (name, seed)
    if k not in latest or int(camp[7:]) > latest[k][0]: latest[k] = (int(camp[7:]), v)
bins = collections.Counter()
for k, (s, (ol, out, moved, rng, nd)) in latest.items():
    if moved or nd > 1 or rng is None: continue
    far = rng > 2.5
    b = "<0.6" if ol < 0.6 else "0.6-0.7" if ol < 0.7 else "0.7-0.8" if ol < 0.8 else ">=0.8"
    bins[(far, b, out)] += 1
    if out == "wrong": print(k, s, ol, rng)
for k in sorted(bins): print(k, bins[k])
