"""Summarise raised_census.py output: how many hanging-arm frames pass the mission's raised test, by rule.

    python docs/issue14/session29/scripts/raised_table.py CENSUS.jsonl[.gz] [...]

"hanging": the diver's arm fully down (truth raised fraction 0); "raised": fully raised. A frame counts as raised
by the mission when its triangulated arm passes ``is_raised`` and, with a rule, is not a folded guess (joint
visibility under C with the wrist within A deg of straight up in the image).
"""
import collections, gzip, json, sys
import numpy as np

rows = [json.loads(l) for p in sys.argv[1:] for l in (gzip.open(p, "rt") if p.endswith(".gz") else open(p))]
down = [r for r in rows if r["raised"] <= 0.01]
up = [r for r in rows if r["raised"] >= 0.99]


def raised(r: dict, conf: float, up_deg: float) -> bool:
    """The mission's test with a folded-guess rule (visibility under conf, wrist within up_deg of straight up)."""
    if not r["arm_raised"] or "vis" not in r:
        return False
    return min(r["vis"]) >= conf or (180.0 - r["img_from_down_deg"]) > up_deg


def pct(x) -> list:
    return np.round(np.percentile(x, [5, 25, 50, 75, 95]), 2).tolist()


fa = [r for r in down if raised(r, 0.0, 0.0)]
ok = [r for r in up if raised(r, 0.0, 0.0)]
print(f"frames {len(rows)}: hanging {len(down)} (passing the raised test {len(fa)}), raised {len(up)} (passing {len(ok)})")
print("hanging but passing, per scenario:", dict(sorted(collections.Counter(r["scenario"] for r in fa).items())))
print("joint visibility (min of shoulder/elbow/wrist), p5/25/50/75/95: hanging-passing", pct([min(r["vis"]) for r in fa]),
      "raised", pct([min(r["vis"]) for r in ok]))
print("image direction, deg from straight down: hanging-passing", pct([r["img_from_down_deg"] for r in fa]),
      "raised", pct([r["img_from_down_deg"] for r in ok]))
print("| rule | hanging frames passing | raised frames passing |\n|---|---|---|")
print(f"| none | {len(fa)} / {len(down)} | {len(ok)} / {len(up)} |")
for conf, up_deg in ((0.8, 180.0), (0.85, 180.0), (0.8, 45.0), (0.85, 45.0), (0.9, 45.0)):
    name = f"visibility >= {conf}" + ("" if up_deg >= 180 else f" where the wrist is within {up_deg:g} deg of straight up")
    print(f"| {name} | {sum(raised(r, conf, up_deg) for r in down)} / {len(down)} | {sum(raised(r, conf, up_deg) for r in up)} / {len(up)} |")
