"""Per joint: |depth error / depth sigma| quantiles over the families' draws (2 px), and by range band."""
import sys, tempfile, json
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
rows = []
for family in ["line_of_sight", "far", "elbow", "far_diver", "undetectable"]:
  with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        J = scene.frame.meta["joints_cam_m"]; T = np.array([J["shoulder"], J["elbow"], J["wrist"]])
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", ())
        rng = np.random.default_rng(seed0 + k)
        for _ in range(8):
            pose.provide(sf.noisy(truth, 2.0, rng))
            a = perception.check_arm(perception.estimate_arm(left, right))
            if a.arm3d is None: continue
            e = a.arm3d.xyz_m[:, 2] - T[:, 2]
            rows.append(dict(f=family, k=k, z=T[:, 2].tolist(), e=e.tolist(), s=a.arm3d.depth_sigma_m.tolist()))
json.dump(rows, open(sys.argv[3], "w"))
E = np.array([r["e"] for r in rows]); S = np.array([r["s"] for r in rows]); Z = np.array([r["z"] for r in rows])
for j, name in enumerate(["shoulder", "elbow", "wrist"]):
    r = np.abs(E[:, j] / S[:, j])
    print(name, "n", len(r), "|e/s| p50 %.2f p90 %.2f p95 %.2f" % tuple(np.percentile(r, [50, 90, 95])), "|e| p50 %.3f p90 %.3f" % tuple(np.percentile(np.abs(E[:, j]), [50, 90])), "sigma p50 %.3f" % np.median(S[:, j]))
    for lo, hi in ((0, 3), (3, 7)):
        m = (Z[:, j] >= lo) & (Z[:, j] < hi)
        if m.any(): print("   ", lo, hi, "n", m.sum(), "|e/s| p50 %.2f p90 %.2f" % tuple(np.percentile(r[m], [50, 90])), "mean e/s %+.2f" % np.mean(E[m, j] / S[m, j]))
# the arm's tilt: relative depth S-W
rel = (E[:, 0] - E[:, 2]) / np.hypot(S[:, 0], S[:, 2])
print("S-W rel |e/s| p50 %.2f p90 %.2f" % tuple(np.percentile(np.abs(rel), [50, 90])))
