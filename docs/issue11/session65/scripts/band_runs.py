"""Layout runs (latest campaign of each layout and seed, docs/issue11/session*/campaigns) with an object decision whose
one look lies in [LO, HI) and the diver's layout range over MIN_RANGE_M, as run_pairs.sh lines "NAME SEED 0 OUTCOME":
    python docs/issue11/session65/scripts/band_runs.py LO HI MIN_RANGE_M > PAIRS"""
import glob, json, os, sys
import yaml

lo, hi, min_range = (float(v) for v in sys.argv[1:4])
ymls = {os.path.basename(p)[:-5]: p for p in glob.glob("docs/issue11/**/variant_*.yaml", recursive=True)}
latest = {}
for f in sorted(glob.glob("docs/issue11/session*/campaigns/**/default_variant_*.txt", recursive=True)):
    name, session = os.path.basename(f)[8:-4], int(f.split("/")[2][7:])
    for line in open(f):
        if line.startswith('{"seed"'):
            d = json.loads(line)
            key = (name, d["seed"])
            if key not in latest or session >= latest[key][0]:
                latest[key] = (session, d)
for (name, seed), (session, d) in sorted(latest.items()):
    if name not in ymls:
        continue
    rng = yaml.safe_load(open(ymls[name]))["diver"]["positions"][0]["range_m"]
    if rng > min_range and any(x["kind"] == "object" and lo <= (x["one_look"] or 0) < hi for x in d["decisions"]):
        print(name, seed, 0, d["outcome"])
