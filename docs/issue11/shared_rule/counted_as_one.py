"""Per seed: the mission outcome and every fused decision's posterior with the frames counted as one."""
import json, sys
import behaviours.fusion as fu
from sitl.point_campaign import mission_trial, _overrides, _seeds

calls = []
orig = fu.PointFusion.decide

def decide(self, min_posterior, min_led):
    d = orig(self, min_posterior, min_led)
    if d.best is not None and d.posterior.get(d.best, 0) >= min_posterior:
        one = self.posterior(1.0 / len(self.frames))
        calls.append((d.kind, d.best, round(d.posterior[d.best], 3), round(one[d.best], 3), len(self.frames),
                      d.reason[:90]))
    return d

fu.PointFusion.decide = decide
scen, seeds = sys.argv[1], _seeds(sys.argv[2])
sets = _overrides(sys.argv[3:])
for s in seeds:
    calls.clear()
    row = mission_trial((scen, s, sets))
    # the last distinct decisions only
    seen, uniq = set(), []
    for c in calls:
        if c[:2] + (c[4],) not in seen:
            seen.add(c[:2] + (c[4],)); uniq.append(c)
    print(json.dumps({"seed": s, "outcome": row["outcome"], "target": row["target_id"], "chosen": row["chosen_id"],
                      "decisions": [c for c in uniq if c[0] != "undecided"] or uniq[-3:]}), flush=True)
