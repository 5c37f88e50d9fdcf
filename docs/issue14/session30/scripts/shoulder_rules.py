"""How well each rule for the pointing shoulder's disparity knows its own error, on the shoulder census.

    python docs/issue14/session30/scripts/shoulder_rules.py docs/issue14/session30/census/*.jsonl.gz

Per rule and group of frames: |error / sigma| (``z``, p50 and p90; a calibrated sigma gives 0.67 and 1.64),
the share of frames beyond 3 sigmas, the sigma's median in metres of depth and the error's p90 in metres.
Rules: A the torso model as it was (``shoulder_disparity``, the side BlazePose says); B A with the model's
0.05 m depth sigma; C B with a 10 % doubt of the side; F B reconciled with the head's match (Birge ratio);
G F with a 5 % doubt of the side (what ``torso_shoulder_disparity`` does); H F with 3 %.
"""
import collections, gzip, json, math, sys
import numpy as np

rows = [json.loads(l) for f in sys.argv[1:] for l in (gzip.open(f, "rt") if f.endswith(".gz") else open(f))]


def torso(r, floor_m, p):
    (dn, sn), (df, sf) = r["model_near"], r["model_far"]
    mean = (1 - p) * dn + p * df
    var = (1 - p) * sn ** 2 + p * sf ** 2 + p * (1 - p) * (dn - df) ** 2
    return mean, math.hypot(math.sqrt(var), mean ** 2 / r["fb"] * floor_m)


def combine(ests):
    d = np.array([e[0] for e in ests]); s = np.array([e[1] for e in ests]); w = 1 / s ** 2
    m = (w * d).sum() / w.sum(); sc = 1 / math.sqrt(w.sum())
    if len(ests) > 1:
        sc *= max(1.0, math.sqrt(((d - m) ** 2 * w).sum() / (len(ests) - 1)))
    return m, sc


def head(r):
    return [tuple(r["head"])] if r["head"] else []


RULES = {
    "A as it was": lambda r: tuple(r["model_near"]),
    "B + 0.05 m": lambda r: torso(r, 0.05, 0),
    "C B + side doubt 0.1": lambda r: torso(r, 0.05, 0.1),
    "F B + head": lambda r: combine([torso(r, 0.05, 0)] + head(r)),
    "G F + side doubt 0.05": lambda r: combine([torso(r, 0.05, 0.05)] + head(r)),
    "H F + side doubt 0.03": lambda r: combine([torso(r, 0.05, 0.03)] + head(r)),
}
groups = collections.defaultdict(list)
for r in rows:
    groups["built-in" if not r["scenario"].endswith(".yaml") else "variants"].append(r)
    groups["all"].append(r)
    groups[r["scenario"].split("/")[-1].replace(".yaml", "")].append(r)
print("| rule | frames | near right | |z| p50 | |z| p90 | > 3 sigma | sigma (m, median) | |error| p90 (m) |")
print("|---|---|---|---|---|---|---|---|")
for name, f in RULES.items():
    for g in ["all", "built-in", "variants"] + sorted(k for k in groups if k not in ("all", "built-in", "variants")):
        v = groups[g]
        res = [f(r) for r in v]
        z = np.abs([(m - r["true_d_px"]) / s for (m, s), r in zip(res, v)])
        sm = np.median([s * (r["fb"] / m) ** 2 / r["fb"] for (m, s), r in zip(res, v)])
        em = np.percentile([abs(m - r["true_d_px"]) * r["fb"] / r["true_d_px"] ** 2 for (m, s), r in zip(res, v)], 90)
        near = sum(r["near"] == r["true_near"] for r in v)
        print(f"| {name} | {g}: {len(v)} | {near} | {np.median(z):.2f} | {np.percentile(z, 90):.2f} | "
              f"{np.mean(z > 3) * 100:.1f} % | {sm:.3f} | {em:.3f} |")
