"""Per family: each joint's final disparity error after ``estimate_arm`` against the truth joint (px), and
its |error| / sigma, at the given noise (truth keypoints plus Gaussian noise in both images).

    python docs/issue11/session45/scripts/joint_errors.py N SEED NOISE DRAWS [KEY=VALUE ...]
"""
import sys, collections
import numpy as np
sys.path.insert(0, "docs/issue11/session45/scripts")
from draw_loop import draws, sf  # noqa: E402

n, seed0, noise, per = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
rows = collections.defaultdict(list)
for family, k, d, scene, rig, left, right, perception, arm, base in draws(sf.FAMILIES, n, seed0, noise, per, sys.argv[5:]):
    td = arm.left_px[:, 0] - arm.right_px[:, 0]
    est = perception.estimate_arm(left, right)
    if est is None:
        continue
    e = (est.left_px[:, 0] - est.right_px[:, 0]) - td
    sig = est.disparity_sigma_px if est.disparity_sigma_px is not None else np.full(3, np.nan)
    rows[family].append(np.r_[e, sig, td])
for family, v in list(rows.items()) + [("all", sum(rows.values(), []))]:
    a = np.array(v)
    parts = []
    for j, name in enumerate(("shoulder", "elbow", "wrist")):
        e, s = a[:, j], a[:, 3 + j]
        parts.append(f"{name} med {np.median(e):+.2f} |e| {np.median(abs(e)):.2f}/{np.percentile(abs(e), 90):.2f} "
                     f"|z| {np.nanmedian(abs(e / s)):.2f}/{np.nanpercentile(abs(e / s), 90):.2f}")
    print(f"{family:14s} n {len(a):3d} | " + " | ".join(parts), flush=True)
