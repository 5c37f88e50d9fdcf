"""Layout runs (latest campaign of each layout and seed, docs/issue11/session*/campaigns) with an object decision whose
one look lies in [LO, HI) and the diver's layout range over MIN_RANGE_M, as run_pairs.sh lines "NAME SEED 0 OUTCOME":
    python docs/issue11/session65/scripts/band_runs.py LO HI MIN_RANGE_M > PAIRS"""
import glob, os, sys

import yaml
from latest_runs import latest_runs

lo, hi, min_range = (float(v) for v in sys.argv[1:4])
ymls = {os.path.basename(p)[:-5]: p for p in glob.glob("docs/issue11/**/variant_*.yaml", recursive=True)}
latest = latest_runs()
for (name, seed), d in sorted(latest.items()):
    if name not in ymls:
        continue
    rng = yaml.safe_load(open(ymls[name]))["diver"]["positions"][0]["range_m"]
    if rng > min_range and any(x["kind"] == "object" and lo <= (x["one_look"] or 0) < hi for x in d["decisions"]):
        print(name, seed, 0, d["outcome"])
