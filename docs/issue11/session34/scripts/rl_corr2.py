import json, sys, numpy as np
rows = []
for f in sys.argv[1:]: rows += json.load(open(f))
dt = np.array([r["dt"] for r in rows]); lr = np.array([r["lr"] for r in rows]); rl = np.array([r["rl"] for r in rows])
lm = np.array([r["lrm"] for r in rows]); rm = np.array([r["rlm"] for r in rows]); g = np.array([r["given"] for r in rows])
av = np.where(lm & rm, 0.5*(lr+rl), np.where(lm, lr, np.where(rm, rl, g)))
ew = av[:, 2] - dt[:, 2]
print("wrist raw |e| med/p90", np.round([np.median(np.abs(ew)), np.percentile(np.abs(ew), 90)], 2), "signed med", round(np.median(ew),2))
for ref, name in ((1, "elbow"), (0, "shoulder")):
    x = dt[:, 2] - dt[:, ref]; a = np.polyfit(x, ew, 1); print(name, "truth slope", np.round(a, 3))
    for k in (0.05, 0.08, 0.1, 0.15, 0.2):
        xm = av[:, 2] - av[:, ref]
        c = ew - k * xm
        print(f"   k {k}: corrected |e| med {np.median(np.abs(c)):.2f} p90 {np.percentile(np.abs(c), 90):.2f}")
