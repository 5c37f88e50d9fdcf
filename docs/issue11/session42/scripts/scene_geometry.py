import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
fam, n, seed0, want = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        if k != want: continue
        meta = scene.frame.meta
        J = {j: np.array(v) for j, v in meta["joints_cam_m"].items()}
        ax = (J["wrist"] - J["shoulder"]); ax /= np.linalg.norm(ax)
        print("target", scene.scenario.target_id, "margin", sf.pointing_margin_deg(scene))
        for pid, p in meta["placards"].items():
            d = np.array(p["xyz_cam_m"]) - J["shoulder"]
            print(" placard", pid, np.round(p["xyz_cam_m"], 2), "angle from truth arm %.1f deg" % np.degrees(np.arccos(d @ ax / np.linalg.norm(d))))
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        rng = np.random.default_rng(seed0 + k)
        truth = meta["keypoints_truth"]
        for _ in range(2):
            pose.provide(sf.noisy(truth, 2.0, rng))
            r = sf.decided(perception, left, right, base)
            X = r.arm3d.xyz_m; a = (X[2] - X[0]) / np.linalg.norm(X[2] - X[0])
            print(" est arm err %.1f deg" % np.degrees(np.arccos(a @ ax)), "depth err", np.round(X[:, 2] - np.array([J[j][2] for j in ("shoulder", "elbow", "wrist")]), 3))
            for o, p in zip(r.selection.objects, r.selection.scores):
                d = o.xyz_m - X[0]; dt = o.xyz_m - J["shoulder"]
                print("   obj", np.round(o.xyz_m, 2), "P %.2f" % p, "angle est arm %.1f truth arm %.1f" % (np.degrees(np.arccos(d @ a / np.linalg.norm(d))), np.degrees(np.arccos(dt @ ax / np.linalg.norm(dt)))))
