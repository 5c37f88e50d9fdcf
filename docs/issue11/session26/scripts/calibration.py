"""Reliability of the default selector's per-frame confidence: the share of correct draws per confidence bin.

    python docs/issue11/session26/scripts/calibration.py DIR

DIR holds `docs/issue11/session20/family_scenes.py FAMILY 20 SEED 2` outputs (one per family and seed);
object picks (status ok) and "nothing detected" answers are binned apart.
"""
import glob, re, sys, collections
bins = [0.0, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.01]
for kind in ("ok", "nothing_on_ray"):
    tab = collections.defaultdict(lambda: [0, 0])
    for path in sorted(glob.glob(sys.argv[1] + "/*.txt")):
        for l in open(path):
            m = re.search(r"draw \d+ (\S+)\s+(\S+)\s+conf ([\d.]+) none ([\d.]+) amb (\d)", l)
            if not m or m[2] != kind:
                continue
            out, conf = m[1], float(m[3])
            b = max(i for i in range(len(bins) - 1) if conf >= bins[i])
            tab[b][0] += 1
            tab[b][1] += out == "correct"
    print(f"status {kind}: confidence bin -> correct / draws")
    for b in sorted(tab):
        n, c = tab[b]
        print(f"  [{bins[b]:.2f}, {min(bins[b + 1], 1.0):.2f}): {c:4d} / {n:4d} = {100 * c / n:5.1f} %")
