import json, sys, numpy as np
rows = []
for f in sys.argv[1:]: rows += json.load(open(f))
for j in (0, 1, 2):
    m = np.array([r["lrm"][j] and r["rlm"][j] for r in rows])
    e = np.array([0.5*(r["lr"][j]+r["rl"][j]) - r["dt"][j] for r in rows])[m]
    dt = np.array([r["dt"] for r in rows])[m]
    fe = dt[:, 2] - dt[:, 1]; us = dt[:, 1] - dt[:, 0]; sw = dt[:, 2]-dt[:,0]
    print(j, "n", m.sum(), "mean e", round(e.mean(),2), "corr w/ fore-dd", round(np.corrcoef(e, fe)[0,1],2), "upper-dd", round(np.corrcoef(e, us)[0,1],2), "S-W dd", round(np.corrcoef(e, sw)[0,1],2), "d", round(np.corrcoef(e, dt[:,2])[0,1],2))
    A = np.c_[fe, np.ones_like(fe)]; print("   fit e = a*fore_dd + b:", np.round(np.linalg.lstsq(A, e, rcond=None)[0], 3))
