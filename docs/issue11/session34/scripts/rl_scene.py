import json, sys, numpy as np, collections
for f in sys.argv[1:]:
    rows = json.load(open(f)); by = collections.defaultdict(list)
    for r in rows: by[r["k"]].append(r)
    print(f)
    for k, rr in sorted(by.items()):
        out = []
        for j in range(3):
            e = np.array([0.5*(r["lr"][j]+r["rl"][j]) - r["dt"][j] for r in rr if r["lrm"][j] and r["rlm"][j]])
            g = np.array([r["given"][j] - r["dt"][j] for r in rr])
            out.append(f"{np.mean(e):+.2f}±{np.std(e):.2f}({len(e)})" if len(e) else "   --   ")
        print(k, f"d {rr[0]['dt'][2]:.1f}", "  ".join(out))
