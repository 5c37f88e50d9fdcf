"""Layout runs (latest campaign of each layout and seed, docs/issue11/session*/campaigns) with a "nothing detected"
decision and the diver's layout range over MIN_RANGE_M, as run_pairs.sh lines "NAME SEED 0 OUTCOME":
    python docs/issue11/session66/scripts/none_runs.py MIN_RANGE_M > PAIRS"""
import glob, os, sys

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "session65", "scripts"))
from latest_runs import latest_runs  # noqa: E402

min_range = float(sys.argv[1])
ymls = {os.path.basename(p)[:-5]: p for p in glob.glob("docs/issue11/**/variant_*.yaml", recursive=True)}
for (name, seed), d in sorted(latest_runs().items()):
    if name not in ymls:
        continue
    rng = yaml.safe_load(open(ymls[name]))["diver"]["positions"][0]["range_m"]
    if rng > min_range and any(x["kind"] == "none" for x in d["decisions"]):
        print(name, seed, 0, d["outcome"])
