"""The wrist's raw L->R match error against the truth, before / after moving it back by a share of the
shoulder-to-wrist disparity difference (the shoulder's own raw match, else its given disparity), from rl_probe's JSON.

    python docs/issue11/session34/scripts/wrist_share.py docs/issue11/session34/probe/rl_far.json ...
"""
import json
import sys

import numpy as np

rows = []
for f in sys.argv[1:]:
    rows += json.load(open(f))
dt = np.array([r["dt"] for r in rows]); lr = np.array([r["lr"] for r in rows]); lm = np.array([r["lrm"] for r in rows])
g = np.array([r["given"] for r in rows])
m = lm[:, 2]
ref = np.where(lm[:, 0], lr[:, 0], g[:, 0])
e0 = (lr[:, 2] - dt[:, 2])[m]
print(f"{len(rows)} draws, wrist matched {m.sum()}; slope of the error vs the truth S->W disparity difference "
      f"{np.polyfit((dt[:, 2] - dt[:, 0])[m], e0, 1)[0]:.3f}, corr {np.corrcoef((dt[:, 2] - dt[:, 0])[m], e0)[0, 1]:.2f}")
for k in (0.0, 0.04, 0.06, 0.08, 0.1, 0.12):
    e = (lr[:, 2] - k * (lr[:, 2] - ref) - dt[:, 2])[m]
    print(f"share {k:.2f}: |error| median {np.median(np.abs(e)):.2f} p90 {np.percentile(np.abs(e), 90):.2f} px, signed median {np.median(e):+.2f}")
