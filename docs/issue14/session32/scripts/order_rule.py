"""How well the pointing shoulder's disparity knows its error when BlazePose's shoulder order is doubted by its recent history.

    python docs/issue14/session32/scripts/order_rule.py docs/issue14/session30/census/census_{A,B,VA,VB}.jsonl.gz

Rules: G the fixed 5 % doubt (session 30); I N: the doubt is the share of the last N census frames of the same run
(scenario, seed) whose order disagrees with this frame's, at least 5 % (``shoulder_model.ShoulderOrder``).
"""
import collections, gzip, json, math, sys
import numpy as np
from dip3d_vehicle.perception.shoulder_model import reconcile as combine   # the head check, as the estimator does
rows = [json.loads(l) for f in sys.argv[1:] for l in gzip.open(f, "rt")]
def torso(r, floor_m, p):
    (dn, sn), (df, sf) = r["model_near"], r["model_far"]
    mean = (1 - p) * dn + p * df
    var = (1 - p) * sn ** 2 + p * sf ** 2 + p * (1 - p) * (dn - df) ** 2
    return mean, math.hypot(math.sqrt(var), mean ** 2 / r["fb"] * floor_m)
head = lambda r: [tuple(r["head"])] if r["head"] else []
seqs = collections.defaultdict(list)
for r in rows:
    seqs[(r["scenario"], r["seed"])].append(r)
for v in seqs.values(): v.sort(key=lambda r: r["t"])
def doubt_hist(N, floor=0.05):
    out = {}
    for k, v in seqs.items():
        for i, r in enumerate(v):
            w = v[max(0, i - N + 1): i + 1]
            dis = sum(x["near"] != r["near"] for x in w) / len(w)
            out[id(r)] = min(max(floor, dis), 1 - floor)
    return out
rules = {"G fixed 0.05": lambda r: combine([torso(r, 0.05, 0.05)] + head(r))}
for N in (3, 5, 8, 12):
    d = doubt_hist(N)
    rules[f"I history {N}"] = (lambda d: lambda r: combine([torso(r, 0.05, d[id(r)])] + head(r)))(d)
groups = collections.defaultdict(list)
for r in rows:
    groups["built-in" if not r["scenario"].endswith(".yaml") else "variants"].append(r)
    groups[r["scenario"].split("/")[-1].replace(".yaml", "")].append(r)
print("| rule | frames | |z| p50 | |z| p90 | > 3 sigma | sigma m median | |err| p90 m |")
for name, f in rules.items():
    for g in ["built-in", "variants", "variant_9_02", "variant_9_03", "variant_9_17", "variant_9_09"]:
        v = groups[g]; res = [f(r) for r in v]
        z = np.abs([(m - r["true_d_px"]) / s for (m, s), r in zip(res, v)])
        sm = np.median([s * (r["fb"] / m) ** 2 / r["fb"] for (m, s), r in zip(res, v)])
        em = np.percentile([abs(m - r["true_d_px"]) * r["fb"] / r["true_d_px"] ** 2 for (m, s), r in zip(res, v)], 90)
        print(f"| {name} | {g}: {len(v)} | {np.median(z):.2f} | {np.percentile(z, 90):.2f} | {np.mean(z > 3) * 100:.1f} % | {sm:.3f} | {em:.3f} |")
