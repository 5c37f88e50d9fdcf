import json, sys, math
import numpy as np
log = json.load(open(sys.argv[1]))
thr = 0.1
def run(rule, k=2):
    mean = None; n = 0; restarts = 0; runs = []; pending = []
    for t, a, L, src, *_ in log:
        if a is None: continue
        d = np.array([math.cos(a), math.sin(a)])
        if mean is None:
            mean = d.copy(); n = 1; continue
        m = mean / np.linalg.norm(mean)
        ang = math.acos(np.clip(m @ d, -1, 1))
        if rule == "now":
            if ang > thr:
                restarts += 1; runs.append(n); mean = d.copy(); n = 1
            else:
                mean += d; n += 1
        else:
            if ang > thr:
                pending.append(d)
                if len(pending) >= k:
                    pm = sum(pending); pm /= np.linalg.norm(pm)
                    if all(math.acos(np.clip(pm @ p, -1, 1)) <= thr for p in pending):
                        restarts += 1; runs.append(n); mean = sum(pending); n = len(pending); pending = []
                    else:
                        pending = pending[1:]
            else:
                pending = []; mean += d; n += 1
    runs.append(n)
    return restarts, max(runs), np.median(runs)
for rule in ("now", "persist2", "persist3"):
    print(rule, run(rule, 2 if rule == "persist2" else 3))
