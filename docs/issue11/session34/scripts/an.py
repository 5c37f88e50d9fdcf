import json, sys, numpy as np, collections
rows = json.load(open(sys.argv[1]))
rows = [r for r in rows if r["det"] and r["err"] is not None]
c = collections.Counter(r["out"] for r in rows); print(c, len(rows))
for out in ("correct", "abstained", "wrong", "confident_wrong"):
    rr = [r for r in rows if r["out"] == out]
    if not rr: continue
    e = np.array([r["err"] for r in rr]); s = np.array([[x if x is not None else np.nan for x in r["sig"]] if r["sig"] else [np.nan]*3 for r in rr], float)
    sw = np.abs(e[:, 0] - e[:, 2])
    print(out, len(rr), "|e| med", np.round(np.median(np.abs(e), 0), 2), "p90", np.round(np.percentile(np.abs(e), 90, 0), 2),
          "|S-W| med", round(float(np.median(sw)), 2), "p90", round(float(np.percentile(sw, 90)), 2), "band3-6", sum(r["band"] == "3-6 m" for r in rr))
