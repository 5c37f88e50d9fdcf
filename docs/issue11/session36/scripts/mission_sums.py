"""Arrived / wrong / abstained (nothing there) per set of a mission folder."""
import glob, json, os, re, sys
root = sys.argv[1]
tot = [0, 0, 0, 0, 0]
for sub in sorted(os.listdir(root)):
    if not os.path.isdir(os.path.join(root, sub)):
        continue
    n = [0, 0, 0, 0, 0]
    for path in sorted(glob.glob(os.path.join(root, sub, "*.txt"))):
        for piece in re.findall(r'\{"seed".*?"decisions": \[.*?\]\}', open(path).read()):
            try:
                d = json.loads(piece)
            except json.JSONDecodeError:
                continue
            n[0] += 1
            n[1] += d["outcome"] == "arrived"
            n[2] += d["outcome"] == "wrong"
            n[3] += d["outcome"] == "abstained"
            n[4] += bool(d.get("nothing_there")) and d["outcome"] == "abstained"
    tot = [a + b for a, b in zip(tot, n)]
    print(f"{sub:24s} runs {n[0]:3d}: {n[1]} / {n[2]} / {n[3]} ({n[4]})")
print(f"{'all':24s} runs {tot[0]:3d}: {tot[1]} / {tot[2]} / {tot[3]} ({tot[4]})")
