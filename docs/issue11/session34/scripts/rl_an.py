import json, sys, numpy as np
rows = []
for f in sys.argv[1:]: rows += json.load(open(f))
print(len(rows), "draws")
for j, name in enumerate(("shoulder", "elbow", "wrist")):
    dt = np.array([r["dt"][j] for r in rows]); lr = np.array([r["lr"][j] for r in rows]); rl = np.array([r["rl"][j] for r in rows])
    lm = np.array([r["lrm"][j] for r in rows]); rm = np.array([r["rlm"][j] for r in rows])
    ls = np.array([r["lrs"][j] for r in rows]); rs = np.array([r["rls"][j] for r in rows])
    b = lm & rm
    e1, e2 = np.abs(lr - dt)[b], np.abs(rl - dt)[b]; av = np.abs(0.5 * (lr + rl) - dt)[b]; sp = np.abs(lr - rl)[b]
    print(f"{name}: LR matched {lm.mean():.2f} RL {rm.mean():.2f} both {b.mean():.2f}; |e| LR med/p90 {np.median(e1):.2f}/{np.percentile(e1,90):.2f} RL {np.median(e2):.2f}/{np.percentile(e2,90):.2f} avg {np.median(av):.2f}/{np.percentile(av,90):.2f}; corr(e1,e2 signed) {np.corrcoef((lr-dt)[b],(rl-dt)[b])[0,1]:.2f}")
    for lo, hi in ((0, 0.3), (0.3, 0.7), (0.7, 1.5), (1.5, 99)):
        m = (sp >= lo) & (sp < hi)
        if m.sum(): print(f"   spread {lo}-{hi}: n {m.sum()} avg |e| med {np.median(av[m]):.2f} p90 {np.percentile(av[m],90):.2f}")
