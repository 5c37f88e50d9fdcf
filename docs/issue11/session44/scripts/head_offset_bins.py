"""From head_offset.py's output: the head's matched surface minus the shoulder joint's depth (m), by the torso's turn.

|sx| is the shoulder axis' share across the view (from the image offset of shoulder and head), |sz| = sqrt(1 - sx^2)
its share along the view; prints the offset per |sx| bin and per family, and the fit offset = a + b |sz|.

    python docs/issue11/session44/scripts/head_offset_bins.py FILE [FILE ...]
"""
import re, sys
import numpy as np

rows = []
for name in sys.argv[1:]:
    for line in open(name):
        m = re.search(r"\|sx\| (\S+) head-surface (\S+)", line)
        if m:
            rows.append((line.split()[0], float(m.group(1)), float(m.group(2))))
fam = np.array([r[0] for r in rows]); sx = np.array([r[1] for r in rows]); h = np.array([r[2] for r in rows])
sz = np.sqrt(np.maximum(1 - sx ** 2, 0))
print(f"n {len(h)}: offset median {np.median(h):+.3f} sd {h.std():.3f} m")
for lo, hi in ((0, 0.5), (0.5, 0.8), (0.8, 0.95), (0.95, 1.01)):
    s = (sx >= lo) & (sx < hi)
    print(f"  |sx| {lo:.2f}-{hi:.2f}: n {s.sum():3d} offset median {np.median(h[s]):+.3f} mad {np.median(abs(h[s] - np.median(h[s]))):.3f} m")
for f in sorted(set(fam)):
    s = fam == f
    print(f"  {f:14s} n {s.sum():3d} offset median {np.median(h[s]):+.3f} mad {np.median(abs(h[s] - np.median(h[s]))):.3f} m")
X = np.c_[np.ones(len(h)), sz]
c, *_ = np.linalg.lstsq(X, h, rcond=None)
r = h - X @ c
print(f"fit offset = {c[0]:+.3f} + {c[1]:.3f} |sz|: residual mad {np.median(abs(r)):.3f} p90 {np.percentile(abs(r), 90):.3f} m")
a = np.median(h - 0.19 * sz); r = h - 0.19 * sz - a
print(f"with half a shoulder width (0.19 m): offset = {a:+.3f} + 0.19 |sz|: residual mad {np.median(abs(r)):.3f} p90 {np.percentile(abs(r), 90):.3f} m")
