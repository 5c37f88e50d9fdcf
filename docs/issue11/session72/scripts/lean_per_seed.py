"""Per seed of an arm_eval JSON (``python -m sitl.arm_eval ... --select stereo --json OUT``): how many frames lean
to the pointed placard (its probability above the best other's), the mean [pointed, best other, nothing]
probabilities, and the median 3D direction error (deg) (issue 14 session 72).

    python docs/issue11/session72/scripts/lean_per_seed.py OUT.json
"""
import json
import sys
from collections import defaultdict

import numpy as np


def main() -> None:
    rows = json.load(open(sys.argv[1]))["rows"]
    by = defaultdict(list)
    for r in rows:
        by[(r["seed"], r["position"])].append(r["stereo"])
    print("seed position frames lean_right mean_p[pointed,other,nothing] deg_median")
    for (seed, pos), st in sorted(by.items()):
        ps = [s["p"] for s in st if s.get("p")]
        right = sum(1 for p in ps if p[0] > p[1])
        mean = np.round(np.mean(ps, axis=0), 2).tolist() if ps else None
        print(seed, pos, len(st), f"{right}/{len(ps)}", mean, round(float(np.median([s["deg"] for s in st])), 1))


if __name__ == "__main__":
    main()
